#include "skelgrasp/perception/depth_camera.h"

#include <gtest/gtest.h>

#include <cmath>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/geometry/shapes.h"

namespace skelgrasp::perception {
namespace {

DepthCameraParams noiseless() {
  DepthCameraParams p;
  p.noise.enabled = false;
  return p;
}

// Only the axial noise of the model (no quantisation, no dropouts).
DepthCameraParams axialOnly(std::uint64_t seed) {
  DepthCameraParams p;
  p.noise.disparity_step_px = 0;
  p.noise.grazing_start_rad = p.noise.grazing_max_rad = 1.57;
  p.noise.edge_dropout_probability = 0;
  p.noise.random_dropout_probability = 0;
  p.noise.projector_shadow = false;
  p.noise.seed = seed;
  return p;
}

TriangleMesh wallAt(double z) {  // a 4 m x 4 m wall facing the origin at distance z along +z
  TriangleMesh wall = geometry::shapes::makeBox({4, 4, 0.01});
  wall.transform(Pose(Eigen::Translation3d(0, 0, z + 0.005)));
  return wall;
}

TEST(DepthCamera, LookAtUsesTheOpenCvCameraFrame) {
  const Pose pose = lookAt({1, 0, 0}, {0, 0, 0}, Eigen::Vector3d::UnitZ());
  EXPECT_LT((pose.linear().col(2) - Eigen::Vector3d(-1, 0, 0)).norm(), 1e-12);  // z forward
  EXPECT_LT((pose.linear().col(1) - Eigen::Vector3d(0, 0, -1)).norm(), 1e-12);  // y down
  EXPECT_LT((pose.linear().col(0) - Eigen::Vector3d(0, 1, 0)).norm(), 1e-12);   // x right
  EXPECT_NO_THROW(lookAt({0, 0, 1}, {0, 0, 0}));  // looking along "up" still has a frame
  EXPECT_THROW(lookAt({0, 0, 0}, {0, 0, 0}), InvalidArgument);
}

TEST(DepthCamera, NoiselessDepthIsExact) {
  const auto view = renderDepth({wallAt(1.0)}, Pose::Identity(), noiseless());
  ASSERT_EQ(view.depth.width, 640);
  EXPECT_EQ(view.valid_pixels, 640u * 480u);
  for (float z : view.depth.data) ASSERT_NEAR(z, 1.0, 1e-6);
  for (int label : view.labels.data) ASSERT_EQ(label, 0);
  ASSERT_TRUE(view.cloud.isOrganized());
  EXPECT_EQ(view.cloud.sensor_origin, Eigen::Vector3d::Zero());
}

TEST(DepthCamera, SpherePointsLieOnTheSphereAndCarryItsLabel) {
  const Eigen::Vector3d centre(0.3, 0.1, 0.2);
  TriangleMesh sphere = geometry::shapes::makeSphere(0.05, 96, 48);
  sphere.transform(Pose(Eigen::Translation3d(centre)));
  const Pose camera = lookAt({0.3, 0.1, 0.9}, centre, Eigen::Vector3d::UnitY());
  const auto view = renderDepth({wallAt(-0.5), sphere}, camera, noiseless());
  std::size_t on_sphere = 0;
  for (std::size_t i = 0; i < view.cloud.size(); ++i) {
    if (view.point_labels[i] != 1) continue;
    ++on_sphere;
    // 96 segments: the facets lie within r (1 - cos(pi / 48)) = 0.1 mm of the sphere.
    ASSERT_NEAR((view.cloud.points[i] - centre).norm(), 0.05, 1.5e-4);
  }
  // The sphere spans about pi (0.05 * 525 / 0.7)^2 pixels.
  EXPECT_NEAR(static_cast<double>(on_sphere), 3.1416 * std::pow(0.05 * 525 / 0.7, 2), 300);
}

TEST(DepthCamera, AxialNoiseFollowsTheModelAndTheSeed) {
  for (const double z : {1.0, 2.0}) {
    const auto view = renderDepth({wallAt(z)}, Pose::Identity(), axialOnly(3));
    double sum = 0, sq = 0;
    for (float d : view.depth.data) {
      sum += d - z;
      sq += (d - z) * (d - z);
    }
    const double n = static_cast<double>(view.depth.data.size());
    const double sigma = std::sqrt(sq / n - (sum / n) * (sum / n));
    const double model = 0.0012 + 0.0019 * (z - 0.4) * (z - 0.4);  // incidence angle ~0
    EXPECT_NEAR(sigma, model, 0.1 * model) << "at " << z << " m";
    EXPECT_NEAR(sum / n, 0.0, 1e-4);
  }
  const auto a = renderDepth({wallAt(1.0)}, Pose::Identity(), axialOnly(3));
  const auto b = renderDepth({wallAt(1.0)}, Pose::Identity(), axialOnly(3));
  const auto c = renderDepth({wallAt(1.0)}, Pose::Identity(), axialOnly(4));
  EXPECT_EQ(a.depth.data, b.depth.data);
  EXPECT_NE(a.depth.data, c.depth.data);
}

TEST(DepthCamera, DisparityIsQuantised) {
  DepthCameraParams p = axialOnly(1);
  p.noise.axial_sigma_base_m = p.noise.axial_sigma_quadratic = p.noise.axial_sigma_angle = 0;
  p.noise.disparity_step_px = 0.125;
  TriangleMesh ramp =
      geometry::shapes::makeBox({4, 4, 0.01});  // a tilted wall: depth varies smoothly
  ramp.transform(Pose(Eigen::Translation3d(0, 0, 1.5)) *
                 Pose(Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitY())));
  const auto view = renderDepth({ramp}, Pose::Identity(), p);
  const double fb = 525.0 * 0.075;
  std::size_t checked = 0;
  for (float z : view.depth.data) {
    if (!std::isfinite(z)) continue;
    const double steps = fb / z / 0.125;  // disparity in 1/8 pixel steps: an integer
    ASSERT_NEAR(steps, std::round(steps), 1e-3);
    ++checked;
  }
  EXPECT_GT(checked, 100000u);
}

TEST(DepthCamera, DropoutsAtTheConfiguredRate) {
  DepthCameraParams p = axialOnly(5);
  p.noise.random_dropout_probability = 0.1;
  const auto view = renderDepth({wallAt(1.0)}, Pose::Identity(), p);
  const double dropped = static_cast<double>(view.dropped_pixels) / (640.0 * 480.0);
  EXPECT_NEAR(dropped, 0.1, 0.005);

  // A wall seen at 80 degrees incidence drops 2/3 of its pixels (linear from 70 to 85 degrees).
  DepthCameraParams grazing = noiseless();
  grazing.noise.enabled = true;
  grazing.noise.random_dropout_probability = 0;
  grazing.noise.projector_shadow = false;
  grazing.noise.edge_dropout_probability = 0;
  TriangleMesh slanted = geometry::shapes::makeBox({20, 20, 0.01});
  slanted.transform(Pose(Eigen::Translation3d(0, 0, 2.0)) *
                    Pose(Eigen::AngleAxisd(radiansFromDegrees(80.0), Eigen::Vector3d::UnitX())));
  const auto g = renderDepth({slanted}, Pose::Identity(), grazing);
  double hit = 0, lost = 0;
  for (int v = 235; v <= 245; ++v) {  // rays within 0.5 degrees of the axis
    for (int u = 300; u < 340; ++u) {
      if (g.labels.at(u, v) < 0) continue;
      ++hit;
      lost += std::isfinite(g.depth.at(u, v)) ? 0 : 1;
    }
  }
  ASSERT_GT(hit, 400);
  EXPECT_NEAR(lost / hit, 2.0 / 3.0, 0.08);
}

TEST(DepthCamera, ProjectorShadowFallsBesideObjects) {
  // Camera 1 m above a table looking down, a 10 cm cube on it; the projector sits 7.5 cm along
  // the camera's +x, so the shadow lies on the cube's -x side in the image.
  DepthCameraParams p = noiseless();
  p.noise.enabled = true;
  p.noise.random_dropout_probability = 0;
  p.noise.edge_dropout_probability = 0;
  p.noise.axial_sigma_base_m = p.noise.axial_sigma_quadratic = p.noise.axial_sigma_angle = 0;
  TriangleMesh table = geometry::shapes::makeBox({2, 2, 0.02});
  table.transform(Pose(Eigen::Translation3d(0, 0, -0.01)));
  TriangleMesh cube = geometry::shapes::makeBox({0.1, 0.1, 0.1});
  cube.transform(Pose(Eigen::Translation3d(0, 0, 0.05)));
  const Pose camera = lookAt({0, 0, 1}, {0, 0, 0}, Eigen::Vector3d::UnitY());
  const auto view = renderDepth({table, cube}, camera, p);
  std::size_t left = 0, right = 0;
  for (int v = 200; v < 280; ++v) {
    for (int u = 0; u < 640; ++u) {
      if (view.labels.at(u, v) != 0 || std::isfinite(view.depth.at(u, v))) continue;
      (u < 320 ? left : right) += 1;  // missing table pixels
    }
  }
  EXPECT_GT(left, 200u);
  EXPECT_EQ(right, 0u);
}

TEST(DepthCamera, OrbitPosesLookAtTheTarget) {
  const Eigen::Vector3d target(0.1, 0.2, 0.3);
  const auto poses = orbitPoses(target, 0.5, 0.4, 6);
  ASSERT_EQ(poses.size(), 6u);
  for (const auto& pose : poses) {
    EXPECT_NEAR((pose.translation() - target).norm(), 0.5, 1e-12);
    const Eigen::Vector3d forward = pose.linear().col(2);
    EXPECT_NEAR(forward.dot((target - pose.translation()).normalized()), 1.0, 1e-12);
    EXPECT_NEAR(pose.translation().z() - target.z(), 0.5 * std::sin(0.4), 1e-12);
  }
}

}  // namespace
}  // namespace skelgrasp::perception
