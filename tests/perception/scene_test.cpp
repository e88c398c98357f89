#include "skelgrasp/perception/scene.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

#include "perception/synthetic_scenes.h"
#include "skelgrasp/perception/completion.h"
#include "skelgrasp/perception/filters.h"
#include "skelgrasp/perception/ingest.h"

namespace skelgrasp::perception {
namespace {

PointCloud filtered(const PointCloud& cloud) {
  FilterResult r = filterCloud(cloud);
  EXPECT_TRUE(r.status.ok()) << r.status.message;
  return r.cloud;
}

// Majority label of a cluster and the fraction of its points carrying it.
std::pair<std::uint32_t, double> majority(const PointCloud& cluster) {
  std::map<std::uint32_t, std::size_t> counts;
  for (auto l : cluster.labels) ++counts[l];
  auto best = std::max_element(counts.begin(), counts.end(),
                               [](const auto& a, const auto& b) { return a.second < b.second; });
  return {best->first, static_cast<double>(best->second) / cluster.size()};
}

TEST(Scene, FindsTheTableAndSeparatesTheObjects) {
  const auto scene = test::renderTableScene(21);
  const PointCloud cloud = filtered(scene.cloud);
  SceneParams p;
  p.target = TargetSpec::parse("all");
  const SceneResult r = parseScene(cloud, p);
  ASSERT_TRUE(r.status.ok()) << r.status.message;
  ASSERT_TRUE(r.plane);
  EXPECT_GT(r.plane->normal.z(), 0.999);  // the table's top faces up, towards the camera
  EXPECT_NEAR(r.plane->d, 0.0, 0.003);
  ASSERT_EQ(r.clusters.size(), 2u);
  std::map<std::uint32_t, std::size_t> in_cloud;
  for (auto l : cloud.labels) ++in_cloud[l];
  std::set<std::uint32_t> found;
  for (const auto& cluster : r.clusters) {
    const auto [label, purity] = majority(cluster);
    EXPECT_GT(purity, 0.98) << "cluster of object " << label;
    EXPECT_GE(label, 2u);
    // Recall against the object's filtered points: only the few within 1 cm of the table miss.
    EXPECT_GT(static_cast<double>(cluster.size()), 0.85 * in_cloud[label]) << label;
    found.insert(label);
  }
  EXPECT_EQ(found.size(), 2u);
  EXPECT_EQ(r.selected.size(), 2u);
  EXPECT_EQ(r.plane_points.size(), r.plane->inliers);
  EXPECT_EQ(
      r.other_points.size() + r.plane_points.size() + r.clusters[0].size() + r.clusters[1].size(),
      cloud.size());
  for (const auto& info : r.cluster_info) EXPECT_TRUE(info.selected);
  EXPECT_EQ(r.loose_points.size(), r.other_points.size());  // every cluster selected
  EXPECT_NEAR(r.cluster_info[majority(r.clusters[0]).first == 2 ? 0 : 1].height_above_plane_m, 0.10,
              0.01);  // the cylinder
}

TEST(Scene, SelectsTheLargestOrTheNearestCluster) {
  const PointCloud cloud = filtered(test::renderTableScene(22).cloud);
  SceneParams p;
  const SceneResult largest = parseScene(cloud, p);
  ASSERT_EQ(largest.selected, std::vector<std::size_t>{0});
  p.target = TargetSpec::parse("nearest:-0.06,0.10,0.04");  // the box
  const SceneResult nearest = parseScene(cloud, p);
  ASSERT_EQ(nearest.selected.size(), 1u);
  EXPECT_EQ(majority(nearest.clusters[nearest.selected[0]]).first, 3u);
  // The box is not in "other"; the cylinder is, but it is no loose point.
  for (auto l : nearest.other_points.labels) EXPECT_NE(l, 3u);
  std::size_t unselected = 0;
  for (std::size_t c = 0; c < nearest.clusters.size(); ++c)
    unselected += c == nearest.selected[0] ? 0 : nearest.clusters[c].size();
  EXPECT_GT(unselected, 0u);
  EXPECT_EQ(nearest.loose_points.size() + unselected, nearest.other_points.size());
  EXPECT_EQ(TargetSpec::parse("nearest:1,2,3").toString(), "nearest:1,2,3");
  EXPECT_THROW(TargetSpec::parse("nearest:1,2"), InvalidArgument);
  EXPECT_THROW(TargetSpec::parse("biggest"), InvalidArgument);
}

TEST(Scene, SelectsAnObjectByIndexLargestFirst) {
  const PointCloud cloud = filtered(test::renderTableScene(22).cloud);
  SceneParams p;
  p.target = TargetSpec::parse("all");
  const SceneResult all = parseScene(cloud, p);
  ASSERT_EQ(all.clusters.size(), 2u);
  for (std::size_t k = 0; k < all.clusters.size(); ++k) {
    p.target = TargetSpec::parse("index:" + std::to_string(k));
    const SceneResult one = parseScene(cloud, p);
    ASSERT_TRUE(one.status.ok()) << one.status.message;
    ASSERT_EQ(one.selected, std::vector<std::size_t>{k});
    EXPECT_EQ(majority(one.clusters[k]).first, majority(all.clusters[k]).first);
  }
  EXPECT_GE(all.clusters[0].size(), all.clusters[1].size());  // index 0 is the largest
  // Past the last object: a data failure that names the count, not an exception.
  p.target = TargetSpec::parse("index:2");
  const SceneResult past = parseScene(cloud, p);
  EXPECT_EQ(past.status.code, StatusCode::kNoResult);
  EXPECT_NE(past.status.message.find("has 2 object(s)"), std::string::npos) << past.status.message;
  EXPECT_EQ(TargetSpec::parse("index:12").toString(), "index:12");
  for (const char* bad :
       {"index:", "index:-1", "index:1.5", "index: 1", "index:1x", "index:99999999999999999999"})
    EXPECT_THROW(TargetSpec::parse(bad), InvalidArgument) << bad;
}

TEST(Scene, PrefersTheTableOverTheFloorBehindIt) {
  // A floor 75 cm below fills more of the image than the table; the table is nearer the camera.
  auto scene = test::renderTableScene(23, {1.1, 0.0, 0.7});
  TriangleMesh floor = geometry::shapes::makeBox({6, 6, 0.02});
  floor.transform(Pose(Eigen::Translation3d(0, 0, -0.76)));
  scene.meshes.push_back(floor);
  const auto view = renderDepth(scene.meshes, lookAt({1.1, 0.0, 0.7}, {0, 0, 0.05}));
  const SceneResult r = parseScene(filtered(view.cloud));
  ASSERT_TRUE(r.status.ok()) << r.status.message;
  EXPECT_NEAR(r.plane->d, 0.0, 0.003);
}

TEST(Scene, ReportsMissingPlaneAndMissingObjects) {
  const auto empty_table = test::renderTableScene(24, {0.55, 0.05, 0.6}, false);
  const SceneResult no_object = parseScene(filtered(empty_table.cloud));
  EXPECT_EQ(no_object.status.code, StatusCode::kNoResult);
  EXPECT_NE(no_object.status.message.find("no object above the support plane"), std::string::npos);

  // Points filling a 30 cm cube: the best slab holds 7 % of them and is not flat.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.15, 0.15);
  PointCloud volume;
  for (int i = 0; i < 20000; ++i) volume.points.emplace_back(u(rng), u(rng), 0.8 + u(rng));
  const SceneResult no_plane = parseScene(volume);
  EXPECT_EQ(no_plane.status.code, StatusCode::kNoResult);
  EXPECT_NE(no_plane.status.message.find("no support plane"), std::string::npos)
      << no_plane.status.message;

  // A lone ball with plane detection off is one object.
  TriangleMesh sphere = geometry::shapes::makeSphere(0.08, 48, 24);
  const auto view = renderDepth({sphere}, lookAt({0.6, 0, 0.3}, {0, 0, 0}));
  const PointCloud ball = filtered(view.cloud);
  SceneParams none;
  none.plane = PlaneRequirement::kNone;
  const SceneResult alone = parseScene(ball, none);
  ASSERT_TRUE(alone.status.ok());
  EXPECT_EQ(alone.clusters.size(), 1u);
  EXPECT_FALSE(alone.plane);

  // A lone box seen mostly face on: its front face passes for the support and the rest of the box
  // lies behind it. The message points to --plane none, and with it the box is one object.
  const TriangleMesh box = geometry::shapes::makeBox({0.1, 0.25, 0.3});
  const auto box_view = renderDepth({box}, lookAt({0.7, 0.35, 0.3}, {0, 0, 0}));
  const PointCloud carton = filtered(box_view.cloud);
  const SceneResult face = parseScene(carton);
  EXPECT_EQ(face.status.code, StatusCode::kNoResult);
  EXPECT_NE(face.status.message.find("below it"), std::string::npos) << face.status.message;
  EXPECT_NE(face.status.message.find("--plane none"), std::string::npos) << face.status.message;
  const SceneResult whole = parseScene(carton, none);
  ASSERT_TRUE(whole.status.ok()) << whole.status.message;
  EXPECT_EQ(whole.clusters.size(), 1u);
  // An empty table has nothing below it: no such hint.
  EXPECT_EQ(no_object.status.message.find("below it"), std::string::npos)
      << no_object.status.message;
}

// The visible table ends where objects at its edge hide it; objects lie inside the hull of the
// table's points grown by plane_hull_margin_m (10 cm by default), measured as a Minkowski sum.
TEST(Scene, ObjectsJustOutsideTheTablesHullAreKeptFarOnesAreNot) {
  constexpr double kTableHalfM = 0.2, kGridM = 0.005, kCubeM = 0.04;
  PointCloud cloud;
  cloud.sensor_origin = Eigen::Vector3d(0, 0, 1);
  for (double x = -kTableHalfM; x <= kTableHalfM + 1e-9; x += kGridM)
    for (double y = -kTableHalfM; y <= kTableHalfM + 1e-9; y += kGridM)
      cloud.points.emplace_back(x, y, 0);
  // A cube's top and the upper part of its sides (points 5 mm apart) at (x, 0). The sides start
  // above the plane's inlier distance so that no cube point widens the table's hull.
  constexpr double kLowestSideM = 0.015;
  const auto addCube = [&](double centre_x) {
    for (double a = -kCubeM / 2; a <= kCubeM / 2 + 1e-9; a += kGridM) {
      for (double b = -kCubeM / 2; b <= kCubeM / 2 + 1e-9; b += kGridM)
        cloud.points.emplace_back(centre_x + a, b, kCubeM);
      for (double h = kLowestSideM; h < kCubeM; h += kGridM)
        for (double side : {-kCubeM / 2, kCubeM / 2}) {
          cloud.points.emplace_back(centre_x + side, a, h);
          cloud.points.emplace_back(centre_x + a, side, h);
        }
    }
  };
  addCube(kTableHalfM + 0.05);  // 3-7 cm beyond the table's edge: kept
  addCube(kTableHalfM + 0.18);  // 16-20 cm beyond: not on this table
  SceneParams params;
  params.target = TargetSpec::parse("all");
  const SceneResult grown = parseScene(cloud, params);
  ASSERT_TRUE(grown.status.ok()) << grown.status.message;
  ASSERT_EQ(grown.clusters.size(), 1u);
  EXPECT_NEAR(grown.clusters[0].bounds().center().x(), kTableHalfM + 0.05, 0.005);
  params.plane_hull_margin_m = 0;
  const SceneResult tight = parseScene(cloud, params);
  EXPECT_EQ(tight.status.code, StatusCode::kNoResult);
  params.plane_hull_margin_m = 0.25;
  EXPECT_EQ(parseScene(cloud, params).clusters.size(), 2u);
  params.plane_hull_margin_m = -0.01;
  EXPECT_THROW(parseScene(cloud, params), InvalidArgument);
}

TEST(Scene, AnObjectMaskReplacesThePrism) {
  const auto scene = test::renderTableScene(25);
  Scan scan;
  scan.cloud = scene.cloud;
  scan.object_mask.resize(scan.cloud.size());
  for (std::size_t i = 0; i < scan.cloud.size(); ++i)
    scan.object_mask[i] = scene.cloud.labels[i] == 3;
  const IngestResult r = ingestScan(scan);
  ASSERT_TRUE(r.status.ok()) << r.status.message;
  ASSERT_TRUE(r.scene.plane);
  EXPECT_GT(r.scene.plane->normal.z(), 0.999);
  ASSERT_EQ(r.objects.size(), 1u);
  EXPECT_EQ(majority(r.objects[0]).first, 3u);
  EXPECT_DOUBLE_EQ(majority(r.objects[0]).second, 1.0);
  ASSERT_TRUE(r.objects[0].hasNormals());
  EXPECT_GT(r.filter_steps.size(), 2u);
  EXPECT_EQ(r.filter_steps.front().name, "object/non_finite");
}

TEST(Completion, FillsTheFootprintAndWallsUnderTheObservedTop) {
  // The top of a 4 x 4 x 6 cm box seen from above: a footprint of about 10 x 10 cells and walls
  // up to 6 cm along its outline.
  PointCloud top;
  for (int i = 0; i <= 40; ++i) {
    for (int j = 0; j <= 40; ++j)
      top.points.emplace_back(-0.02 + 0.001 * i, -0.02 + 0.001 * j, 0.06);
  }
  SupportPlane plane;
  const SupportCompletion c = completeOnSupport(top, plane);
  EXPECT_NEAR(static_cast<double>(c.bottom_points), 121.0, 25.0);
  EXPECT_EQ(c.bottom_points, c.footprint_cells);
  EXPECT_GT(c.wall_points, 4u * 10u * 14u);
  for (std::size_t i = 0; i < c.points.size(); ++i) {
    const auto& p = c.points.points[i];
    const auto& n = c.points.normals[i];
    EXPECT_LE(p.z(), 0.06 + 1e-9);
    if (p.z() == 0.0) {
      EXPECT_EQ(n, Eigen::Vector3d(0, 0, -1));
    } else {
      EXPECT_NEAR(n.z(), 0.0, 1e-12);                // walls are vertical
      EXPECT_GT(p.head<2>().dot(n.head<2>()), 0.0);  // and face away from the box
    }
  }
}

}  // namespace
}  // namespace skelgrasp::perception
