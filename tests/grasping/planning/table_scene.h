#pragma once
// The scene of the tests that plan against a table: a box standing on the plane z = 0, and that
// plane as the scene check's support plane.
#include "skelgrasp/common/pose.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/planning/scene.h"

namespace skelgrasp::test {

constexpr double kTableBoxHeightM = 0.10;

// A 12 x 5 x 10 cm box (long side along x) standing on z = 0.
inline TriangleMesh boxStandingOnTable() {
  TriangleMesh box = geometry::shapes::makeBox(Eigen::Vector3d(0.12, 0.05, kTableBoxHeightM), 4);
  box.transform(Pose(Eigen::Translation3d(0, 0, kTableBoxHeightM / 2)));
  return box;
}

// The table z = 0, the object's side up.
inline grasping::SupportPlane table() {
  return grasping::SupportPlane{Eigen::Vector4d(0, 0, 1, 0)};
}

}  // namespace skelgrasp::test
