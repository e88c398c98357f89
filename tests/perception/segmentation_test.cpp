// Segmentation of the points above the support: touching objects (LCCP), fragments and bad input.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "perception/synthetic_scenes.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/perception/demo_scene.h"
#include "skelgrasp/perception/depth_camera.h"
#include "skelgrasp/perception/filters.h"
#include "skelgrasp/perception/ingest.h"
#include "skelgrasp/perception/scene.h"

namespace skelgrasp::perception {
namespace {

// The ball pushed against the bottle (bounding-box radii, 2 mm into each other along the line
// between their default positions) so that the scan shows them as one connected blob.
std::vector<DemoPlacement> ballAgainstBottle() {
  const DemoScene base = makeDemoScene(1, 1);
  auto index = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(base.names.begin(), base.names.end(), name) -
                                    base.names.begin());
  };
  const auto& bottle = base.meshes[index("bottle")];
  const auto& ball = base.meshes[index("ball")];
  const double bottle_radius = 0.5 * (bottle.bounds().max.x() - bottle.bounds().min.x());
  const double ball_radius = 0.5 * (ball.bounds().max.x() - ball.bounds().min.x());
  const Eigen::Vector2d from = base.centres[index("bottle")].head<2>();
  const Eigen::Vector2d direction = (base.centres[index("ball")].head<2>() - from).normalized();
  const Eigen::Vector2d at = from + (bottle_radius + ball_radius - 0.002) * direction;
  return {{"ball", at.x(), at.y()}};
}

IngestResult ingestDemo(const DemoScene& scene, SegmentationMethod method) {
  Scan scan;
  scan.cloud = scene.cloud;
  scan.per_view_normals = true;
  IngestParams params;
  params.scene.target = TargetSpec::parse("all");
  params.scene.segmentation = method;
  return ingestScan(scan, params);
}

TEST(Segmentation, DemoSceneWithTwoObjectsInContactStillYieldsFiveObjects) {
  const DemoScene scene = makeDemoScene(1, 3, ballAgainstBottle());
  // The contact is real: Euclidean clustering welds the ball to the bottle.
  const IngestResult euclidean = ingestDemo(scene, SegmentationMethod::kEuclidean);
  ASSERT_TRUE(euclidean.status.ok()) << euclidean.status.message;
  EXPECT_EQ(euclidean.scene.clusters.size(), 4u);

  const IngestResult lccp = ingestDemo(scene, SegmentationMethod::kLccp);
  ASSERT_TRUE(lccp.status.ok()) << lccp.status.message;
  EXPECT_EQ(lccp.scene.segmentation, SegmentationMethod::kLccp);
  ASSERT_EQ(lccp.scene.clusters.size(), 5u);
  // Each object is the segment whose centroid is nearest to its true centre (on the table plane,
  // the scan sees the objects' front halves), and no two objects share one.
  std::set<std::size_t> used;
  for (std::size_t k = 1; k < scene.meshes.size(); ++k) {
    SCOPED_TRACE(scene.names[k]);
    std::size_t best = 0;
    double best_distance = 1e9;
    for (std::size_t c = 0; c < lccp.scene.cluster_info.size(); ++c) {
      const double d =
          (lccp.scene.cluster_info[c].centroid.head<2>() - scene.centres[k].head<2>()).norm();
      if (d < best_distance) {
        best = c;
        best_distance = d;
      }
    }
    EXPECT_LT(best_distance, 0.04);
    EXPECT_TRUE(used.insert(best).second);
  }
}

// A long low box behind a tall cylinder, seen from the front: the scan shows the box's two ends
// left and right of the cylinder, touching nowhere (mOSD osd_test26 on the table).
test::TableScene boxBehindCylinder(bool with_cylinder) {
  test::TableScene scene;
  TriangleMesh table = geometry::shapes::makeBox({1.0, 0.8, 0.04}, 4);
  table.transform(Pose(Eigen::Translation3d(0, 0, -0.02)));
  scene.meshes.push_back(table);
  TriangleMesh box = geometry::shapes::makeBox({0.06, 0.30, 0.06}, 6);
  box.transform(Pose(Eigen::Translation3d(0, 0, 0.03)));
  scene.meshes.push_back(box);
  if (with_cylinder) {
    TriangleMesh cylinder = geometry::shapes::makeCylinder(0.04, 0.20, 48, 8);
    cylinder.transform(Pose(Eigen::Translation3d(0.12, 0, 0.10)));
    scene.meshes.push_back(cylinder);
  }
  DepthCameraParams camera;
  camera.noise.seed = 5;
  scene.cloud = renderDepth(scene.meshes, lookAt({0.75, 0, 0.35}, {0, 0, 0.05}), camera).cloud;
  return scene;
}

std::size_t lccpObjectCount(const test::TableScene& scene, bool join_hidden_gaps) {
  Scan scan;
  scan.cloud = scene.cloud;
  IngestParams params;
  params.scene.target = TargetSpec::parse("all");
  params.scene.segmentation = SegmentationMethod::kLccp;
  params.scene.lccp.join_hidden_gaps = join_hidden_gaps;
  const IngestResult r = ingestScan(scan, params);
  EXPECT_TRUE(r.status.ok()) << r.status.message;
  return r.scene.clusters.size();
}

TEST(Segmentation, AnObjectSeenInTwoPiecesAroundAnOccluderIsOneObject) {
  const test::TableScene occluded = boxBehindCylinder(true);
  // Without the rule the box's two visible ends are two objects.
  EXPECT_EQ(lccpObjectCount(occluded, false), 3u);
  EXPECT_EQ(lccpObjectCount(occluded, true), 2u);
  // Nothing hides the gap between two boxes standing apart: they stay two.
  test::TableScene apart = boxBehindCylinder(false);
  TriangleMesh second = geometry::shapes::makeBox({0.06, 0.10, 0.06}, 4);
  second.transform(Pose(Eigen::Translation3d(0, 0.25, 0.03)));
  apart.meshes.push_back(second);
  TriangleMesh third = geometry::shapes::makeBox({0.06, 0.06, 0.10}, 4);
  third.transform(Pose(Eigen::Translation3d(0.05, -0.28, 0.05)));
  apart.meshes.push_back(third);
  DepthCameraParams camera;
  camera.noise.seed = 5;
  apart.cloud = renderDepth(apart.meshes, lookAt({0.75, 0, 0.35}, {0, 0, 0.05}), camera).cloud;
  EXPECT_EQ(lccpObjectCount(apart, true), 3u);
}

// An open cup (8 cm wide, 10 cm tall, 5 mm wall) standing at (x, y): from above the scan sees
// the outside of its near wall and, over the rim, the inside of its far wall.
TriangleMesh openCup(double x, double y) {
  TriangleMesh cup = geometry::shapes::makeRevolution(
      {{0.0, 0.0}, {0.04, 0.0}, {0.04, 0.10}, {0.035, 0.10}, {0.035, 0.006}, {0.0, 0.006}}, 64);
  cup.transform(Pose(Eigen::Translation3d(x, y, 0)));
  return cup;
}

// LCCP segments of the objects on a table seen from 45 degrees up, with or without the
// symmetric-body rule.
std::size_t cupSceneObjects(const std::vector<TriangleMesh>& objects, bool join_symmetric) {
  TriangleMesh table = geometry::shapes::makeBox({1.0, 0.8, 0.04}, 4);
  table.transform(Pose(Eigen::Translation3d(0, 0, -0.02)));
  std::vector<TriangleMesh> meshes{table};
  meshes.insert(meshes.end(), objects.begin(), objects.end());
  DepthCameraParams camera;
  camera.noise.seed = 11;
  Scan scan;
  scan.cloud = renderDepth(meshes, lookAt({0.5, 0.0, 0.5}, {0, 0, 0.05}), camera).cloud;
  IngestParams params;
  params.scene.target = TargetSpec::parse("all");
  params.scene.lccp.join_symmetric_bodies = join_symmetric;
  const IngestResult r = ingestScan(scan, params);
  EXPECT_TRUE(r.status.ok()) << r.status.message;
  return r.scene.clusters.size();
}

TEST(Segmentation, ACupCutAtItsRimIsOneObjectAndTwoCupsSideBySideStayTwo) {
  // LCCP cuts the cup where the inside of its far wall meets the outside of its near wall; both
  // lie on one circle about its axis, so the rule joins them.
  const std::size_t without_rule = cupSceneObjects({openCup(0, 0)}, false);
  const std::size_t with_rule = cupSceneObjects({openCup(0, 0)}, true);
  std::cout << "[ cup      ] " << without_rule << " segment(s) without the rule, " << with_rule
            << " with it" << std::endl;
  EXPECT_EQ(with_rule, 1u);
  // Two cups side by side, touching across the line of sight and 2 cm apart along it: each is
  // joined about its own axis, and the two stay apart.
  EXPECT_EQ(cupSceneObjects({openCup(0, -0.041), openCup(0, 0.041)}, true), 2u);
  EXPECT_EQ(cupSceneObjects({openCup(-0.05, 0), openCup(0.05, 0)}, true), 2u);
}

TEST(Segmentation, DefaultDemoSceneYieldsFiveObjectsWithEitherMethod) {
  const DemoScene scene = makeDemoScene(1, 3);
  for (const auto method : {SegmentationMethod::kLccp, SegmentationMethod::kEuclidean}) {
    SCOPED_TRACE(toString(method));
    const IngestResult r = ingestDemo(scene, method);
    ASSERT_TRUE(r.status.ok()) << r.status.message;
    EXPECT_EQ(r.scene.clusters.size(), 5u);
    for (const auto& c : r.scene.cluster_info) {
      std::cout << "[ segment  ] " << c.points << " points at " << c.centroid.transpose()
                << ", top " << c.height_above_plane_m << " m" << std::endl;
    }
  }
}

TEST(Segmentation, EmptyTableGivesNoObjectWithAReason) {
  const auto empty_table = test::renderTableScene(24, {0.55, 0.05, 0.6}, false);
  const FilterResult f = filterCloud(empty_table.cloud);
  ASSERT_TRUE(f.status.ok());
  SceneParams params;
  params.segmentation = SegmentationMethod::kLccp;
  const SceneResult r = parseScene(f.cloud, params);
  EXPECT_EQ(r.status.code, StatusCode::kNoResult);
  EXPECT_NE(r.status.message.find("no object above the support plane"), std::string::npos)
      << r.status.message;
  EXPECT_TRUE(r.clusters.empty());
}

TEST(Segmentation, NoiseAboveTheTableIsDroppedWithReasons) {
  // A flat table of points and 40 lone points scattered 2-30 cm above it, each far from the
  // others: nothing is an object, every dropped point is accounted for.
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> across(-0.3, 0.3), height(0.02, 0.3);
  std::normal_distribution<double> noise(0, 0.001);
  PointCloud cloud;
  for (double x = -0.4; x <= 0.4; x += 0.005) {
    for (double y = -0.4; y <= 0.4; y += 0.005) cloud.points.emplace_back(x, y, noise(rng));
  }
  for (int i = 0; i < 40; ++i) cloud.points.emplace_back(across(rng), across(rng), height(rng));
  cloud.sensor_origin = {0.5, 0, 0.8};
  for (const auto method : {SegmentationMethod::kLccp, SegmentationMethod::kEuclidean}) {
    SCOPED_TRACE(toString(method));
    SceneParams params;
    params.segmentation = method;
    const SceneResult r = parseScene(cloud, params);
    EXPECT_EQ(r.status.code, StatusCode::kNoResult);
    EXPECT_TRUE(r.clusters.empty());
    EXPECT_FALSE(r.dropped.empty());
    std::size_t dropped_points = 0;
    for (const auto& d : r.dropped) {
      EXPECT_FALSE(d.reason.empty());
      dropped_points += d.points;
    }
    EXPECT_EQ(dropped_points, r.candidate_points);
    EXPECT_GT(r.candidate_points, 0u);
  }
}

TEST(Segmentation, MethodNamesRoundTrip) {
  for (const auto method : {SegmentationMethod::kLccp, SegmentationMethod::kEuclidean}) {
    EXPECT_EQ(parseSegmentationMethod(toString(method)), method);
  }
  EXPECT_THROW(parseSegmentationMethod("watershed"), InvalidArgument);
  SceneParams bad;
  bad.lccp.seed_resolution_m = bad.lccp.voxel_resolution_m / 2;
  EXPECT_THROW(parseScene(test::renderTableScene(3).cloud, bad), InvalidArgument);
}

}  // namespace
}  // namespace skelgrasp::perception
