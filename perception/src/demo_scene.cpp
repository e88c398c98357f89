#include "skelgrasp/perception/demo_scene.h"

#include <algorithm>
#include <cmath>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/perception/cloud_ops.h"
#include "skelgrasp/perception/depth_camera.h"
#include "skelgrasp/perception/filters.h"

namespace skelgrasp::perception {
namespace {

// Rests the mesh on z = 0 at (x, y) after rotating it.
TriangleMesh placed(TriangleMesh mesh, double x, double y,
                    const Eigen::AngleAxisd& rotation = Eigen::AngleAxisd::Identity()) {
  Pose turn = Pose::Identity();
  turn.linear() = rotation.toRotationMatrix();
  mesh.transform(turn);
  const AxisAlignedBox box = mesh.bounds();
  mesh.transform(
      Pose(Eigen::Translation3d(x - box.center().x(), y - box.center().y(), -box.min.z())));
  return mesh;
}

}  // namespace

DemoScene makeDemoScene(std::uint64_t seed, int views, const std::vector<DemoPlacement>& moved) {
  if (views < 1) throw InvalidArgument("demo scene: at least one view");
  DemoScene scene;
  TriangleMesh table = geometry::shapes::makeBox({1.2, 0.8, 0.04}, 6);
  table.transform(Pose(Eigen::Translation3d(0, 0, -0.02)));
  auto add = [&](const std::string& name, TriangleMesh mesh) {
    scene.names.push_back(name);
    scene.centres.push_back(mesh.bounds().center());
    scene.meshes.push_back(std::move(mesh));
  };
  add("table", table);
  add("bottle", placed(geometry::shapes::makeNamedShape("bottle"), 0.02, -0.26));
  add("mug", placed(geometry::shapes::makeNamedShape("mug"), 0.16, -0.04,
                    Eigen::AngleAxisd(kPi / 4, Eigen::Vector3d::UnitZ())));
  // Tall enough for the power interval of the large hands (ARMAR-III: 9.4 cm along the skeleton);
  // the 16 cm named box contracts to a shorter trunk and gets no skeleton grasp.
  add("box", placed(geometry::shapes::makeBox({0.05, 0.08, 0.20}, 4), -0.12, 0.10,
                    Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ())));
  // Standing on its head like a mallet, handle up.
  add("hammer", placed(geometry::shapes::makeNamedShape("hammer"), 0.12, 0.25,
                       Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitX())));
  add("ball", placed(geometry::shapes::makeNamedShape("ball"), -0.16, -0.20));
  for (const auto& m : moved) {
    const auto it = std::find(scene.names.begin() + 1, scene.names.end(), m.name);
    if (it == scene.names.end()) throw InvalidArgument("demo scene: no object '" + m.name + "'");
    const auto k = static_cast<std::size_t>(it - scene.names.begin());
    const Eigen::Vector3d shift(m.x - scene.centres[k].x(), m.y - scene.centres[k].y(), 0);
    scene.meshes[k].transform(Pose(Eigen::Translation3d(shift)));
    scene.centres[k] += shift;
  }

  const Eigen::Vector3d target(0, 0, 0.05);
  std::vector<PointCloud> clouds;
  for (int v = 0; v < views; ++v) {
    const double azimuth = views == 1 ? 0.0 : radiansFromDegrees(-50.0 + 100.0 * v / (views - 1));
    const double elevation = radiansFromDegrees(50.0), radius = 0.85;
    const Eigen::Vector3d eye =
        target + radius * Eigen::Vector3d(std::cos(elevation) * std::cos(azimuth),
                                          std::cos(elevation) * std::sin(azimuth),
                                          std::sin(elevation));
    const Pose camera = lookAt(eye, target);
    DepthCameraParams params;
    params.noise.seed = seed + static_cast<std::uint64_t>(v);
    DepthView view = renderDepth(scene.meshes, camera, params);
    // Keep measured pixels only; the view's own origin orients its normals.
    std::vector<int> valid;
    for (std::size_t i = 0; i < view.cloud.size(); ++i) {
      if (view.cloud.points[i].allFinite()) valid.push_back(static_cast<int>(i));
    }
    PointCloud cloud = subset(view.cloud, valid);
    cloud.sensor_origin = camera.translation();
    cloud.sensor_orientation = Eigen::Quaterniond(camera.rotation());
    clouds.push_back(std::move(cloud));
    scene.cameras.push_back(camera);
  }
  scene.cloud = fuseViews(clouds);
  scene.cloud.sensor_origin = scene.cameras.front().translation();
  scene.cloud.sensor_orientation = Eigen::Quaterniond(scene.cameras.front().rotation());
  return scene;
}

}  // namespace skelgrasp::perception
