#pragma once
// Closed, outward-oriented triangle meshes of primitive and composite shapes, made in code. They
// are the project's own test and demo assets (no data files needed). Lengths in metres.
#include <string>
#include <vector>

#include "skelgrasp/common/mesh.h"

namespace skelgrasp::geometry::shapes {

// Box centred at the origin with the given edge lengths; each face split into n x n squares.
TriangleMesh makeBox(const Eigen::Vector3d& size, int subdivisions = 1);

// UV sphere centred at the origin.
TriangleMesh makeSphere(double radius, int segments = 32, int rings = 16);

// Solid of revolution about z. `profile` lists (radius, z) from bottom to top; an end with radius 0
// becomes a pole, otherwise it is closed by a flat cap.
TriangleMesh makeRevolution(const std::vector<Eigen::Vector2d>& profile, int segments = 32);

// Cylinder along z, centred at the origin.
TriangleMesh makeCylinder(double radius, double height, int segments = 32, int rings = 8);

// Truncated cone along z from z = 0 (radius r_bottom) to z = height (radius r_top).
TriangleMesh makeFrustum(double r_bottom, double r_top, double height, int segments = 32);

// Cylinder with hemispherical ends along z, centred; total length = cylinder_length + 2 radius.
TriangleMesh makeCapsule(double radius, double cylinder_length, int segments = 32);

// Torus in the xy plane centred at the origin.
TriangleMesh makeTorus(double major_radius, double minor_radius, int major_segments = 48,
                       int minor_segments = 16);

// Composite shapes made of overlapping closed parts (a multi-part soup; regularisation fuses it):
//   capsule, y_shape, t_shape, torus, mug, bottle, box, hammer, ball, rod.
// Throws InvalidArgument for an unknown name.
TriangleMesh makeNamedShape(const std::string& name);
std::vector<std::string> namedShapes();

}  // namespace skelgrasp::geometry::shapes
