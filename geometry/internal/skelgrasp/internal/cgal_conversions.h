#pragma once
// Internal (not installed): the one place where skelgrasp meshes meet CGAL types. geometry/ uses
// it, and exports it on purpose through the separate target skelgrasp::geometry_cgal to .cpp files
// of other modules that run CGAL algorithms (skeleton/src/contraction.cpp). Never include it from a
// public header: CGAL types stay out of module boundaries.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include <vector>

#include "skelgrasp/common/mesh.h"

namespace skelgrasp::internal {

using CgalKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalPoint = CgalKernel::Point_3;
using CgalMesh = CGAL::Surface_mesh<CgalPoint>;

inline CgalPoint toCgal(const Eigen::Vector3d& p) {
  return {p.x(), p.y(), p.z()};
}
inline Eigen::Vector3d toEigen(const CgalPoint& p) {
  return {p.x(), p.y(), p.z()};
}

// Polygon soup view of a mesh (what CGAL's soup algorithms consume).
void toCgalSoup(const TriangleMesh& mesh, std::vector<CgalPoint>& points,
                std::vector<std::array<std::size_t, 3>>& faces);

// Builds a Surface_mesh; vertex i of the result is vertex i of `mesh`. Returns false if the faces
// do not form an oriented 2-manifold (Surface_mesh rejects such faces).
bool toCgalMesh(const TriangleMesh& mesh, CgalMesh& out);

// Copies a Surface_mesh (garbage is collected first); vertex order = Surface_mesh index order.
TriangleMesh fromCgalMesh(const CgalMesh& mesh);

}  // namespace skelgrasp::internal
