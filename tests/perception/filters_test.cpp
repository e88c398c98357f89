#include "skelgrasp/perception/filters.h"

#include <gtest/gtest.h>

#include <random>

#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/perception/cloud_ops.h"

namespace skelgrasp::perception {
namespace {

// A 10 x 10 grid with 1 mm spacing at z = 0, offset half a millimetre from the voxel borders.
PointCloud grid(std::uint32_t label, const Eigen::Vector3d& offset) {
  PointCloud cloud;
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 10; ++j) {
      cloud.points.push_back(offset + Eigen::Vector3d(0.0005 + 0.001 * i, 0.0005 + 0.001 * j, 0));
      cloud.labels.push_back(label);
      cloud.colors.push_back({static_cast<std::uint8_t>(10 * label), 0, 0});
    }
  }
  return cloud;
}

TEST(Filters, VoxelGridKeepsOnePointPerVoxelAndTheLabels) {
  PointCloud cloud = grid(1, {0, 0, 0});
  append(cloud, grid(2, {0.1, 0, 0}));
  FilterParams p;
  p.voxel_leaf_m = 0.005;
  p.sor_mean_k = 0;
  const FilterResult r = filterCloud(cloud, p);
  ASSERT_TRUE(r.status.ok());
  ASSERT_EQ(r.cloud.size(), 8u);  // 2 x 2 voxels per grid
  ASSERT_TRUE(r.cloud.hasLabels());
  ASSERT_TRUE(r.cloud.hasColors());
  for (std::size_t i = 0; i < r.cloud.size(); ++i) {
    const std::uint32_t expected = r.cloud.points[i].x() < 0.05 ? 1 : 2;
    EXPECT_EQ(r.cloud.labels[i], expected);
    EXPECT_EQ(r.cloud.colors[i][0], 10 * expected);
  }
  ASSERT_EQ(r.steps.size(), 2u);
  EXPECT_EQ(r.steps[1].name, "voxel_grid");
  EXPECT_EQ(r.steps[1].points_in, 200u);
  EXPECT_EQ(r.steps[1].points_out, 8u);
}

// Each voxel takes the label of the input point of that voxel nearest to its centroid. Against
// the plain definition (the nearest input point of all, by brute force) on three touching labelled
// blobs: every label is one found in the voxel, and almost all equal the plain one (they differ
// only where a neighbouring voxel's point lies nearer the centroid than any point of its own).
TEST(Filters, VoxelLabelsComeFromTheVoxelsOwnPointNearestTheCentroid) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  PointCloud cloud;
  for (std::uint32_t label = 1; label <= 3; ++label) {
    const Eigen::Vector3d centre(0.03 * label, 0.01 * (label % 2), 0);
    for (int i = 0; i < 3000; ++i) {
      cloud.points.push_back(centre + Eigen::Vector3d(u(rng), u(rng), u(rng)));
      cloud.labels.push_back(label);
    }
  }
  FilterParams p;
  p.voxel_leaf_m = 0.004;
  p.sor_mean_k = 0;
  const FilterResult r = filterCloud(cloud, p);
  ASSERT_TRUE(r.status.ok());
  ASSERT_TRUE(r.cloud.hasLabels());
  const double voxel_diagonal = std::sqrt(3.0) * p.voxel_leaf_m;
  std::size_t plain_agrees = 0;
  for (std::size_t i = 0; i < r.cloud.size(); ++i) {
    const Eigen::Vector3d& c = r.cloud.points[i];
    std::size_t nearest = 0;
    bool label_within_voxel = false;
    for (std::size_t j = 0; j < cloud.size(); ++j) {
      const double d = (cloud.points[j] - c).norm();
      if (d < (cloud.points[nearest] - c).norm()) nearest = j;
      if (d <= voxel_diagonal && cloud.labels[j] == r.cloud.labels[i]) label_within_voxel = true;
    }
    EXPECT_TRUE(label_within_voxel) << "voxel " << i;
    plain_agrees += cloud.labels[nearest] == r.cloud.labels[i];
  }
  EXPECT_GE(plain_agrees, 0.97 * r.cloud.size()) << plain_agrees << " of " << r.cloud.size();
}

TEST(Filters, NonFiniteCropAndOutliers) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0.0, 1.0);
  PointCloud cloud;
  for (int i = 0; i < 2000; ++i) {  // points on a 5 cm sphere
    cloud.points.push_back(0.05 * Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized());
  }
  for (int i = 0; i < 10; ++i) cloud.points.push_back(Eigen::Vector3d(0.3 + 0.05 * i, 0.2, 0));
  cloud.points.push_back(Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
  FilterParams p;
  p.voxel_leaf_m = 0;
  const FilterResult r = filterCloud(cloud, p);
  ASSERT_TRUE(r.status.ok());
  EXPECT_EQ(r.steps[0].points_out, 2010u);                          // the NaN went
  for (const auto& q : r.cloud.points) EXPECT_LT(q.norm(), 0.051);  // the 10 stragglers went
  EXPECT_GT(r.cloud.size(), 1950u);

  p.crop_box = AxisAlignedBox{{0, -1, -1}, {1, 1, 1}};  // keep x >= 0
  const FilterResult cropped = filterCloud(cloud, p);
  for (const auto& q : cropped.cloud.points) EXPECT_GE(q.x(), 0.0);
  EXPECT_EQ(cropped.steps[1].name, "crop_box");
  p.crop_box = AxisAlignedBox{{1, 1, 1}, {0, 0, 0}};
  EXPECT_THROW(filterCloud(cloud, p), InvalidArgument);
}

TEST(Filters, EmptyAndAllNaNCloudsAreInvalidInput) {
  EXPECT_EQ(filterCloud(PointCloud{}).status.code, StatusCode::kInvalidInput);
  PointCloud nan;
  nan.points.assign(50, Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
  const FilterResult r = filterCloud(nan);
  EXPECT_EQ(r.status.code, StatusCode::kInvalidInput);
  EXPECT_NE(r.status.message.find("all 50 points are NaN"), std::string::npos) << r.status.message;
  FilterParams far;
  far.crop_box = AxisAlignedBox{{5, 5, 5}, {6, 6, 6}};
  EXPECT_EQ(filterCloud(grid(1, {0, 0, 0}), far).status.code, StatusCode::kNoResult);
}

TEST(Filters, NormalsFaceTheSensor) {
  PointCloud plane = grid(1, {0, 0, 0});
  plane.sensor_origin = {0, 0, 1};
  NormalParams p;
  p.radius_m = 0.003;
  NormalResult up = estimateNormals(plane, p);
  ASSERT_TRUE(up.status.ok());
  ASSERT_EQ(up.cloud.size(), 100u);
  for (const auto& n : up.cloud.normals) EXPECT_GT(n.z(), 0.999);
  plane.sensor_origin = {0, 0, -1};
  for (const auto& n : estimateNormals(plane, p).cloud.normals) EXPECT_LT(n.z(), -0.999);
  p.radius_m = 0;
  EXPECT_THROW(estimateNormals(plane, p), InvalidArgument);
}

TEST(Filters, FusedViewsHaveOutwardNormals) {
  // Two caps of a sphere, each seen from its own side: per-view orientation makes all normals
  // point out of the sphere, which no single viewpoint could do.
  const TriangleMesh sphere = geometry::shapes::makeSphere(0.05, 64, 32);
  PointCloud left, right;
  for (const auto& v : sphere.vertices) {
    if (std::abs(v.x()) > 0.015) (v.x() < 0 ? left : right).points.push_back(v);
  }
  left.sensor_origin = {-0.5, 0, 0};
  right.sensor_origin = {0.5, 0, 0};
  NormalParams p;
  p.k = 12;
  const PointCloud fused = fuseViews({left, right}, p);
  ASSERT_TRUE(fused.hasNormals());
  EXPECT_EQ(fused.size(), left.size() + right.size());
  std::size_t outward = 0;
  for (std::size_t i = 0; i < fused.size(); ++i) {
    outward += fused.normals[i].dot(fused.points[i].normalized()) > 0.9 ? 1 : 0;
  }
  EXPECT_EQ(outward, fused.size());
}

}  // namespace
}  // namespace skelgrasp::perception
