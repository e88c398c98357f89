#pragma once
// Table-top scenes rendered by the simulated depth camera: the project's own test scans.
#include <limits>
#include <vector>

#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/perception/depth_camera.h"

namespace skelgrasp::test {

struct TableScene {
  std::vector<TriangleMesh> meshes;  // 0 = table top (z = 0 is its surface), then the objects
  PointCloud cloud;                  // organised, world frame; labels = mesh index + 1, 0 = none
};

// A 1 m x 0.8 m table with a cylinder (r 3 cm, h 10 cm) and a box (6 x 6 x 8 cm) on it, seen by
// a Primesense-like camera from `eye` (z up, metres), with the error model seeded by `seed`.
inline TableScene renderTableScene(std::uint64_t seed,
                                   const Eigen::Vector3d& eye = Eigen::Vector3d(0.55, 0.05, 0.6),
                                   bool with_objects = true) {
  TableScene scene;
  TriangleMesh table = geometry::shapes::makeBox({1.0, 0.8, 0.04}, 4);
  table.transform(Pose(Eigen::Translation3d(0, 0, -0.02)));
  scene.meshes.push_back(table);
  if (with_objects) {
    TriangleMesh cylinder = geometry::shapes::makeCylinder(0.03, 0.10, 48, 4);
    cylinder.transform(Pose(Eigen::Translation3d(0.05, -0.09, 0.05)));
    scene.meshes.push_back(cylinder);
    TriangleMesh box = geometry::shapes::makeBox({0.06, 0.06, 0.08}, 2);
    box.transform(Pose(Eigen::Translation3d(-0.06, 0.10, 0.04)));
    scene.meshes.push_back(box);
  }
  perception::DepthCameraParams camera;
  camera.noise.seed = seed;
  const auto view =
      perception::renderDepth(scene.meshes, perception::lookAt(eye, {0, 0, 0.05}), camera);
  scene.cloud = view.cloud;
  scene.cloud.labels.resize(view.point_labels.size());
  for (std::size_t i = 0; i < view.point_labels.size(); ++i) {
    const auto l = view.point_labels[i];
    scene.cloud.labels[i] = l == std::numeric_limits<std::uint32_t>::max() ? 0 : l + 1;
  }
  return scene;
}

}  // namespace skelgrasp::test
