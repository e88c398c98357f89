// Scene parsing on the real recordings in ../shared/data/scans/pcd: the PCL mug scene and the
// mOSD scenes, whose points carry ground-truth object labels.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "skelgrasp/perception/cloud_io.h"
#include "skelgrasp/perception/ingest.h"
#include "skelgrasp/perception/label_score.h"
#include "test_support.h"

namespace skelgrasp::perception {
namespace {

TEST(RealScans, MugSceneYieldsTheTableAndTheMug) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  Scan scan;
  scan.cloud =
      loadPointCloud(test::sharedDataDir() + "/scans/pcd/pcl_table_scene_mug_stereo_textured.pcd");
  const IngestResult r = ingestScan(scan);
  ASSERT_TRUE(r.status.ok()) << r.status.message;
  ASSERT_TRUE(r.scene.plane);
  // The table 0.53 m from the camera, not the floor 1.9 m away that holds more points.
  EXPECT_NEAR(r.scene.plane->signedDistance(scan.cloud.sensor_origin), 0.528, 0.01);
  // Measured: one cluster of 2287 points, 0.146 x 0.111 x 0.088 m (PCA), 0.11 m tall.
  ASSERT_EQ(r.scene.clusters.size(), 1u);
  const auto& mug = r.scene.cluster_info[0];
  EXPECT_GT(mug.points, 1500u);
  EXPECT_GT(mug.extent[0], 0.06);
  EXPECT_LT(mug.extent[0], 0.15);
  EXPECT_GT(mug.height_above_plane_m, 0.08);
  EXPECT_LT(mug.height_above_plane_m, 0.13);
  ASSERT_EQ(r.objects.size(), 1u);
  EXPECT_TRUE(r.objects[0].hasNormals());
}

// Floors of the default segmentation (LCCP): measured (docs/perception.md: every scene's count
// within 1, worst scene precision 0.989 and recall 0.942, overall 0.992 / 0.960) less a margin;
// the scene floors are the goals (0.9 each).
constexpr long kMaxCountError = 1;
constexpr double kMinScenePrecision = 0.95;
constexpr double kMinSceneRecall = 0.90;
constexpr double kMinPrecision = 0.97;
constexpr double kMinRecall = 0.93;

struct OsdScene {
  std::string name;
  LabelScore score;
};

// Every mOSD scene segmented with `method` and scored against its labels (perception::
// scoreAgainstLabels: each labelled object matched to the segment holding most of its points).
std::vector<OsdScene> segmentOsdScenes(SegmentationMethod method) {
  std::vector<OsdScene> scenes;
  for (const auto& file : test::sharedFiles("scans/pcd", {".pcd"})) {
    if (file.find("/osd_") == std::string::npos) continue;
    Scan scan;
    scan.cloud = loadPointCloud(file);
    EXPECT_TRUE(hasObjectLabels(scan.cloud)) << file;
    IngestParams params;
    params.scene.target = TargetSpec::parse("all");
    params.scene.segmentation = method;
    const IngestResult r = ingestScan(scan, params);
    EXPECT_TRUE(r.status.ok()) << file << ": " << r.status.message;
    if (!r.status.ok()) continue;
    OsdScene scene{std::filesystem::path(file).filename().string(),
                   scoreAgainstLabels(scan.cloud, r.scene.clusters)};
    std::cout << "[ osd      ] " << toString(method) << " " << scene.name << ": "
              << scene.score.objects.size() << " objects, " << scene.score.segments
              << " segments, mean precision " << scene.score.mean_precision << ", mean recall "
              << scene.score.mean_recall << std::endl;
    scenes.push_back(std::move(scene));
  }
  return scenes;
}

std::pair<double, double> overall(const std::vector<OsdScene>& scenes) {
  double precision = 0, recall = 0;
  std::size_t objects = 0;
  for (const auto& s : scenes) {
    precision += s.score.mean_precision * s.score.objects.size();
    recall += s.score.mean_recall * s.score.objects.size();
    objects += s.score.objects.size();
  }
  return {precision / objects, recall / objects};
}

TEST(RealScans, OsdEuclideanClustersMatchTheLabelledObjects) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  const auto scenes = segmentOsdScenes(SegmentationMethod::kEuclidean);
  ASSERT_EQ(scenes.size(), 8u);
  for (const auto& s : scenes) {
    if (s.name == "osd_test2.pcd") {
      // Two boxes standing apart: both found whole (measured precision 1.000, recall 0.977).
      EXPECT_GT(s.score.mean_precision, 0.99);
      EXPECT_GT(s.score.mean_recall, 0.95);
    }
  }
  const auto [precision, recall] = overall(scenes);
  RecordProperty("osd_euclidean_precision", std::to_string(precision));
  RecordProperty("osd_euclidean_recall", std::to_string(recall));
  // Measured: precision 0.641, recall 0.957 over 42 objects. Precision is what Euclidean
  // clustering loses on touching objects (stacked boxes become one cluster).
  EXPECT_GT(precision, 0.60);
  EXPECT_GT(recall, 0.92);
}

TEST(RealScans, OsdDefaultSegmentationSeparatesTouchingObjects) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  ASSERT_EQ(SceneParams{}.segmentation, SegmentationMethod::kLccp);
  const auto scenes = segmentOsdScenes(SceneParams{}.segmentation);
  ASSERT_EQ(scenes.size(), 8u);
  // Floors: the measured values (docs/reconstruction.md) less a margin for noise; one setting for
  // every scene.
  for (const auto& s : scenes) {
    SCOPED_TRACE(s.name);
    const long extra =
        static_cast<long>(s.score.segments) - static_cast<long>(s.score.objects.size());
    EXPECT_LE(std::abs(extra), kMaxCountError);
    EXPECT_GT(s.score.mean_precision, kMinScenePrecision);
    EXPECT_GT(s.score.mean_recall, kMinSceneRecall);
    if (s.name == "osd_test18.pcd") {
      // The stacked boxes are two objects, each nearly whole.
      EXPECT_EQ(s.score.segments, 2u);
      EXPECT_GT(s.score.mean_precision, 0.95);
    }
    if (s.name == "osd_test26.pcd") {
      // The low box seen in two pieces around the object in front of it is one segment (hidden
      // gaps; measured recall 0.977, 0.800 without the rule).
      EXPECT_EQ(s.score.segments, 2u);
      EXPECT_GT(s.score.mean_recall, 0.95);
    }
    if (s.name == "osd_test33.pcd") {
      // The bowl-like object whose inside meets its outside at 24-41 degrees is one segment with a
      // concavity tolerance of 27 degrees (measured recall 0.972; 0.875 at 20 degrees).
      EXPECT_EQ(s.score.segments, 4u);
      EXPECT_GT(s.score.mean_recall, 0.93);
    }
    if (s.name == "osd_test58.pcd") {
      // The round object LCCP cuts in two is joined by the symmetric-body rule: 16 segments for
      // the 16 labels (17 without the rule), measured recall 0.943 (0.931).
      EXPECT_EQ(s.score.segments, 16u);
    }
  }
  const auto [precision, recall] = overall(scenes);
  RecordProperty("osd_lccp_precision", std::to_string(precision));
  RecordProperty("osd_lccp_recall", std::to_string(recall));
  EXPECT_GT(precision, kMinPrecision);
  EXPECT_GT(recall, kMinRecall);
}

// Every single-object scan gives one object with the defaults: the mugs of the PCL stereo scan and
// the GPD scan, which LCCP alone cuts at the rim (the symmetric-body rule joins them), and the
// scans without a table (--plane none, where segmentation is Euclidean).
TEST(RealScans, SingleObjectScansGiveOneObject) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  const std::vector<std::pair<std::string, PlaneRequirement>> scans = {
      {"pcl_table_scene_mug_stereo_textured.pcd", PlaneRequirement::kRequired},
      {"gpd_table_mug.pcd", PlaneRequirement::kRequired},
      {"gpd_krylon.pcd", PlaneRequirement::kNone},
      {"pcl_milk_color.pcd", PlaneRequirement::kNone}};
  for (const auto& [name, plane] : scans) {
    SCOPED_TRACE(name);
    const std::string path = test::sharedDataDir() + "/scans/pcd/" + name;
    if (!std::filesystem::exists(path)) {
      std::cout << "[ skipped  ] " << path << " not in the shared data" << std::endl;
      continue;
    }
    Scan scan;
    scan.cloud = loadPointCloud(path);
    IngestParams params;
    params.scene.target = TargetSpec::parse("all");
    params.scene.plane = plane;
    const IngestResult r = ingestScan(scan, params);
    ASSERT_TRUE(r.status.ok()) << r.status.message;
    EXPECT_EQ(r.scene.clusters.size(), 1u);
    if (plane == PlaneRequirement::kRequired) {
      EXPECT_EQ(r.scene.segmentation, SegmentationMethod::kLccp);
      // The rule is what makes it one: without it the mug is two segments.
      params.scene.lccp.join_symmetric_bodies = false;
      EXPECT_EQ(ingestScan(scan, params).scene.clusters.size(), 2u);
    }
  }
}

// Objects at the edge of the visible table stand partly or wholly outside the hull of the
// table's points: in mOSD scan 58 one object (label 60, 6 000 points) is wholly outside it. The
// hull margin keeps them (docs/perception.md, "Stages and parameters").
TEST(RealScans, OsdObjectsAtTheTableEdgeAreKeptByTheHullMargin) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  const std::string path = test::sharedDataDir() + "/scans/pcd/osd_test58.pcd";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not in the shared data";
  Scan scan;
  scan.cloud = loadPointCloud(path);
  const auto scoreWithMargin = [&](double margin_m) {
    IngestParams params;
    params.scene.target = TargetSpec::parse("all");
    params.scene.segmentation = SegmentationMethod::kLccp;
    params.scene.plane_hull_margin_m = margin_m;
    const IngestResult r = ingestScan(scan, params);
    EXPECT_TRUE(r.status.ok()) << r.status.message;
    return scoreAgainstLabels(scan.cloud, r.scene.clusters);
  };
  const auto unmatched = [](const LabelScore& score) {
    return std::count_if(score.objects.begin(), score.objects.end(),
                         [](const LabelledObjectScore& o) { return o.segment < 0; });
  };
  const LabelScore tight = scoreWithMargin(0.0);
  const LabelScore grown = scoreWithMargin(SceneParams{}.plane_hull_margin_m);
  // Measured: recall 0.828 with one object in no segment; 0.929 and none with the margin.
  EXPECT_GE(unmatched(tight), 1);
  EXPECT_EQ(unmatched(grown), 0);
  EXPECT_GT(grown.mean_recall, 0.9);
  EXPECT_GT(grown.mean_recall, tight.mean_recall + 0.05);
  EXPECT_GE(grown.mean_precision, tight.mean_precision);
}

}  // namespace
}  // namespace skelgrasp::perception
