#pragma once
// Principal axes of a mesh's surface: the object's own frame and size, independent of how the mesh
// is turned. The fallback grasp strategies place the hand along these axes, and preshapes made for
// small objects are closed by the length along the longest (docs/hands.md).
#include <Eigen/Core>
#include <vector>

#include "skelgrasp/common/mesh.h"

namespace skelgrasp::geometry {

// Principal axes of the surface (area-weighted, about the surface centroid): columns sorted by
// decreasing standard deviation; `sd` holds those standard deviations in metres. A mesh without
// area keeps the identity and zero deviations.
struct PrincipalAxes {
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  Eigen::Vector3d sd = Eigen::Vector3d::Zero();
};
PrincipalAxes surfacePrincipalAxes(const TriangleMesh& mesh);

// Length of the mesh's vertices along its longest principal axis (`axes`, the mesh's
// surfacePrincipalAxes, computed once by the caller), in metres. When the two largest deviations
// are nearly equal (a cube, a square plate, a ball) that axis may lie anywhere in their plane, and
// the length anywhere between the side and the diagonal of that cross-section. A mesh without area
// has no axes: its bounding box diagonal is returned.
double principalLengthM(const TriangleMesh& mesh, const PrincipalAxes& axes);

// The footprint of points on a plane with unit normal `up`: their extents, in metres, along the
// principal axes of their projection onto it (the widest and the narrowest way across, as an
// object stands on a table). No points: zeros.
struct FootprintExtents {
  double widest_m = 0;
  double narrowest_m = 0;
};
FootprintExtents footprintExtents(const std::vector<Eigen::Vector3d>& points,
                                  const Eigen::Vector3d& up);

}  // namespace skelgrasp::geometry
