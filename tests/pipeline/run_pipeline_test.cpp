// The scene-aware pipeline end to end: the demo scene (ground truth known) and real table scans.
#include "skelgrasp/pipeline/run_pipeline.h"
#include "skelgrasp/pipeline/run_output.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/datasets/input.h"
#include "skelgrasp/geometry/mesh_query.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"
#include "skelgrasp/perception/demo_scene.h"
#include "skelgrasp/perception/depth_camera.h"
#include "skelgrasp/perception/image_io.h"
#include "test_support.h"

namespace skelgrasp::pipeline {
using namespace grasping;  // the stages under test are grasping's
namespace {

RunParams targetNear(const Eigen::Vector3d& point) {
  RunParams params;
  params.reconstruction.ingest.scene.target.mode = perception::TargetMode::kNearest;
  params.reconstruction.ingest.scene.target.point = point;
  return params;
}

// The demo scene is made once for the suite: it costs a few seconds.
class DemoScenePipeline : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new perception::DemoScene(perception::makeDemoScene(1, 3));
    scan_ = new perception::Scan;
    scan_->cloud = scene_->cloud;
    scan_->per_view_normals = true;
    scan_->views = 3;
    scan_->source = "demo scene";
  }
  static void TearDownTestSuite() {
    delete scene_;
    delete scan_;
  }
  static perception::DemoScene* scene_;
  static perception::Scan* scan_;
};
perception::DemoScene* DemoScenePipeline::scene_ = nullptr;
perception::Scan* DemoScenePipeline::scan_ = nullptr;

TEST_F(DemoScenePipeline, EveryObjectGetsCollisionFreeForceClosureGraspsOnItself) {
  const auto hand = loadBuiltinHand("armar3");
  // The table sunk by more than the plane tolerance of the check (2 mm) plus the sensor noise of
  // the fitted plane: touching the top is fine, going through it is not.
  TriangleMesh table = scene_->meshes[0];
  table.transform(Pose(Eigen::Translation3d(0, 0, -0.004)));
  std::vector<std::unique_ptr<GraspObject>> obstacles;
  obstacles.push_back(std::make_unique<GraspObject>(table));
  for (std::size_t k = 1; k < scene_->meshes.size(); ++k)
    obstacles.push_back(std::make_unique<GraspObject>(scene_->meshes[k]));

  for (std::size_t k = 1; k < scene_->meshes.size(); ++k) {
    SCOPED_TRACE(scene_->names[k]);
    const RunResult run = runPipeline(*scan_, hand, targetNear(scene_->centres[k]));
    ASSERT_TRUE(run.status.ok()) << run.status.message;
    ASSERT_FALSE(run.ranked.empty());
    ASSERT_TRUE(run.plane.has_value());
    EXPECT_GT(run.plane->z(), 0.99);  // the table top, object side up
    EXPECT_LT(std::abs(run.plane->w()), 0.003);

    std::vector<std::unique_ptr<geometry::MeshQuery>> truths;
    for (const auto& mesh : scene_->meshes)
      truths.push_back(std::make_unique<geometry::MeshQuery>(mesh));
    for (std::size_t r = 0; r < run.ranked.size(); ++r) {
      const auto& g = run.ranked[r].grasp;
      EXPECT_TRUE(g.force_closure);
      EXPECT_GT(g.epsilon, 0);
      // Robust ranking (RunParams): the scored grasps first, then the others, each group by score.
      if (r > 0 && run.ranked[r - 1].grasp.robustness.has_value() == g.robustness.has_value()) {
        EXPECT_LE(run.ranked[r].score, run.ranked[r - 1].score);
      }
      if (r > 0 && g.robustness) {
        EXPECT_TRUE(run.ranked[r - 1].grasp.robustness.has_value());
      }
      if (g.robustness) {
        EXPECT_LE(0.0, g.robustness->ci95_low);
        EXPECT_LE(g.robustness->ci95_low, g.robustness->r);
        EXPECT_LE(g.robustness->r, g.robustness->ci95_high);
        EXPECT_LE(g.robustness->ci95_high, 1.0);
      }
      EXPECT_GE(run.ranked[r].observed_contact_ratio, 0);
      EXPECT_LE(run.ranked[r].observed_contact_ratio, 1);
      // Contacts, in the scan frame, are on this object: close to its true surface, and each
      // link's patch (its contacts' centre) nearer to it than to any other. The cameras see the
      // objects' front halves only; the unseen backs are completed flatter than they are (the
      // bottle's by up to 2 cm), hence the tolerance; a patch corner at the foot of a completed
      // back may lie nearer the table than the object's true surface.
      std::map<std::string, std::pair<Eigen::Vector3d, int>> patches;
      for (const auto& c : g.contacts) {
        EXPECT_LT((truths[k]->closestPointAndFace(c.point).first - c.point).norm(), 0.025)
            << "grasp " << g.id << " has a contact off the " << scene_->names[k];
        auto& patch = patches.try_emplace(c.link, Eigen::Vector3d::Zero(), 0).first->second;
        patch.first += c.point;
        patch.second += 1;
      }
      for (const auto& [link, patch] : patches) {
        const Eigen::Vector3d centre = patch.first / patch.second;
        std::vector<double> distance;
        for (const auto& t : truths)
          distance.push_back((t->closestPointAndFace(centre).first - centre).norm());
        const auto nearest = std::min_element(distance.begin(), distance.end()) - distance.begin();
        EXPECT_EQ(scene_->names[nearest], scene_->names[k])
            << "grasp " << g.id << " touches another object with " << link;
      }
      // Neither the open hand at the final pose nor the closed hand touches the table or another
      // object's true shape.
      const Eigen::VectorXd open = hand.preshape(g.preshape).joints;
      for (std::size_t o = 0; o < obstacles.size(); ++o) {
        if (o == k) continue;
        GraspSimulator against(hand, *obstacles[o]);
        EXPECT_FALSE(against.inCollision(g.hand_pose, g.joints))
            << "grasp " << g.id << " (closed) hits the " << scene_->names[o];
        EXPECT_FALSE(against.inCollision(g.hand_pose, open))
            << "grasp " << g.id << " (open) hits the " << scene_->names[o];
      }
    }
  }
}

TEST_F(DemoScenePipeline, WritesTheReportWithItsPictures) {
  const auto hand = loadBuiltinHand("armar3");
  const RunResult run = runPipeline(*scan_, hand, targetNear(scene_->centres[2]));  // the mug
  ASSERT_TRUE(run.status.ok()) << run.status.message;
  const std::string dir = test::tempDir("run_report");
  writeRunOutputs(dir, run, hand, *scan_, "mug");
  for (const char* file : {"grasps.json", "object.ply", "skeleton.json", "segmentation.ply",
                           "scene.bt", "report.html"}) {
    EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/" + file)) << file;
    EXPECT_GT(std::filesystem::file_size(dir + "/" + file), 100u) << file;
  }
  std::ifstream html_file(dir + "/report.html");
  const std::string html((std::istreambuf_iterator<char>(html_file)), {});
  const std::regex image(R"(<img src="([^"]+\.png)\")");
  std::vector<std::string> pictures;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), image);
       it != std::sregex_iterator(); ++it)
    pictures.push_back((*it)[1]);
  for (const char* expected :
       {"scan.png", "reconstruction.png", "skeleton.png", "grasps.png", "best_0.png"}) {
    EXPECT_NE(std::find(pictures.begin(), pictures.end(), expected), pictures.end()) << expected;
  }
  for (const auto& png : pictures) {
    const auto picture = perception::readColorImage(dir + "/" + png);  // throws if broken
    EXPECT_GE(picture.width, 400) << png;
    EXPECT_GE(picture.height, 400) << png;
    // Not blank: a fair share of pixels differ from the (white) background.
    std::size_t drawn = 0;
    for (const auto& c : picture.data) drawn += c[0] < 240 || c[1] < 240 || c[2] < 240;
    EXPECT_GT(static_cast<double>(drawn) / picture.data.size(), 0.02) << png << " is blank";
  }
  EXPECT_NE(html.find("scene_collision"), std::string::npos);  // the rejection table
  EXPECT_NE(html.find("occupancy"), std::string::npos);        // the timing table

  std::ifstream json_file(dir + "/grasps.json");
  const auto doc = nlohmann::json::parse(json_file);
  EXPECT_EQ(doc.at("schema"), "skelgrasp.run/4");
  // r with its interval per grasp and the histogram of r (inline SVG).
  EXPECT_NE(html.find("r [95% interval]"), std::string::npos);
  EXPECT_NE(html.find("failed samples: start in object / too few contacts / slipped"),
            std::string::npos);
  EXPECT_NE(html.find("robustness-histogram"), std::string::npos);
  ASSERT_EQ(doc.at("objects").size(), 1u);
  EXPECT_EQ(doc.at("objects")[0].at("grasps"), run.ranked.size());
  EXPECT_EQ(doc.at("objects")[0].at("mesh"), "object.ply");
  ASSERT_EQ(doc.at("scene").at("plane").size(), 4u);
  EXPECT_EQ(doc.at("grasps").size(), run.ranked.size());
  const std::size_t top_k = RunParams{}.robust_ranking.top_k;
  for (const auto& g : doc.at("grasps")) {
    EXPECT_TRUE(g.contains("observed_contact_ratio"));
    EXPECT_TRUE(g.contains("rank_score"));
    // The mug's few grasps are all within the robust ranking's top K.
    if (doc.at("grasps").size() <= top_k) {
      ASSERT_TRUE(g.contains("robustness"));
      EXPECT_EQ(g["robustness"]["samples"], RunParams{}.robust_ranking.robustness.samples);
      EXPECT_EQ(g["robustness"]["variant"], "settled");
    }
  }
}

TEST_F(DemoScenePipeline, WithoutRobustnessTheRankingIsEpsilonTimesTrust) {
  const auto hand = loadBuiltinHand("armar3");
  RunParams params = targetNear(scene_->centres[2]);  // the mug
  params.robust_ranking.enabled = false;
  const RunResult run = runPipeline(*scan_, hand, params);
  ASSERT_TRUE(run.status.ok()) << run.status.message;
  ASSERT_FALSE(run.ranked.empty());
  for (std::size_t r = 0; r < run.ranked.size(); ++r) {
    const auto& ranked = run.ranked[r];
    EXPECT_FALSE(ranked.grasp.robustness.has_value());
    EXPECT_DOUBLE_EQ(ranked.score, ranked.grasp.epsilon *
                                       (1 - params.observed_weight +
                                        params.observed_weight * ranked.observed_contact_ratio));
    if (r > 0) {
      EXPECT_LE(ranked.score, run.ranked[r - 1].score);
    }
  }
}

// A can on a table, optionally inside four walls 4 cm from it and lower than it, seen from above
// by the simulated camera.
perception::Scan walledCanScan(bool walls, std::vector<TriangleMesh>* wall_meshes) {
  std::vector<TriangleMesh> meshes;
  TriangleMesh table = geometry::shapes::makeBox({0.8, 0.8, 0.04}, 6);
  table.transform(Pose(Eigen::Translation3d(0, 0, -0.02)));
  meshes.push_back(table);
  TriangleMesh can = geometry::shapes::makeCylinder(0.035, 0.16, 48, 10);
  can.transform(Pose(Eigen::Translation3d(0, 0, 0.08)));
  meshes.push_back(can);
  for (int side = 0; walls && side < 4; ++side) {
    TriangleMesh wall = geometry::shapes::makeBox({0.01, 0.12, 0.1}, 4);  // open corners
    wall.transform(Pose(Eigen::AngleAxisd(side * kPi / 2, Eigen::Vector3d::UnitZ()) *
                        Eigen::Translation3d(0.08, 0, 0.05)));
    meshes.push_back(wall);
    if (wall_meshes) wall_meshes->push_back(wall);
  }
  const Pose camera = perception::lookAt({0.3, -0.2, 0.6}, {0, 0, 0.08});
  perception::DepthCameraParams camera_params;
  camera_params.noise.seed = 3;
  const auto view = perception::renderDepth(meshes, camera, camera_params);
  perception::Scan scan;
  scan.source = walls ? "walled can" : "can";
  for (const auto& p : view.cloud.points)
    if (p.allFinite()) scan.cloud.points.push_back(p);
  scan.cloud.sensor_origin = camera.translation();
  return scan;
}

TEST(RunPipeline, WallsOfPointsBlockTheApproachesThroughThem) {
  const auto hand = loadBuiltinHand("armar3");
  std::vector<TriangleMesh> walls;
  const RunResult open_run =
      runPipeline(walledCanScan(false, nullptr), hand, targetNear({0, 0, 0.08}));
  const RunResult walled = runPipeline(walledCanScan(true, &walls), hand, targetNear({0, 0, 0.08}));
  for (const RunResult* run : {&open_run, &walled}) {
    ASSERT_TRUE(run->reconstruction.status.ok()) << run->reconstruction.status.message;
    const AxisAlignedBox bounds = run->mesh.bounds();
    EXPECT_LT((bounds.max - bounds.min).head<2>().maxCoeff(), 0.09) << "the target is not the can";
  }
  const auto sceneRejections = [](const RunResult& run) {
    const auto& r = run.plan.summary.rejections;
    return r.count(reason::kSceneCollision) ? r.at(reason::kSceneCollision) : std::size_t{0};
  };
  EXPECT_GT(sceneRejections(walled), sceneRejections(open_run) + 20);
  // The walls are lower than the can: approaches from above (the fallback's "top" poses) still
  // find room, so both runs may fill the grasp limit; the walls show in the rejections.
  EXPECT_FALSE(walled.ranked.empty());
  EXPECT_FALSE(walled.plan.summary.scene_collision_links.empty());
  // Whatever is kept clears the walls' true shapes, open and closed.
  for (const auto& wall : walls) {
    const GraspObject obstacle(wall);
    GraspSimulator against(hand, obstacle);
    for (const auto& r : walled.ranked) {
      EXPECT_FALSE(against.inCollision(r.grasp.hand_pose, r.grasp.joints))
          << "grasp " << r.grasp.id;
      EXPECT_FALSE(against.inCollision(r.grasp.hand_pose, hand.preshape(r.grasp.preshape).joints))
          << "grasp " << r.grasp.id;
    }
  }
}

// The real table scans with a mug: every grasp is on the mug and none passes through the table.
void expectGraspsOnTheMug(const std::string& file) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  const std::string path = test::sharedDataDir() + "/scans/pcd/" + file;
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not in the shared data";
  const auto scan = datasets::loadInput(path, {});
  const auto hand = loadBuiltinHand("armar3");
  const RunResult run = runPipeline(scan, hand, RunParams());
  ASSERT_TRUE(run.status.ok()) << run.status.message;
  ASSERT_TRUE(run.plane.has_value());
  // The mug: about 8-14 cm across with its handle, 9-12 cm tall.
  const AxisAlignedBox bounds = run.mesh.bounds();
  const Eigen::Vector3d size = bounds.max - bounds.min;
  EXPECT_GT(size.maxCoeff(), 0.08);
  EXPECT_LT(size.maxCoeff(), 0.17);
  ASSERT_GE(run.ranked.size(), 2u);
  EXPECT_GT(run.plan.summary.rejections.at("scene_collision"), 0u);
  const Eigen::Vector3d normal = run.plane->head<3>();
  const double d = run.plane->w();
  const geometry::MeshQuery surface(run.mesh);
  for (const auto& r : run.ranked) {
    const auto& g = r.grasp;
    EXPECT_TRUE(g.force_closure);
    for (const auto& c : g.contacts) {
      EXPECT_LT((surface.closestPointAndFace(c.point).first - c.point).norm(), 0.005);
      EXPECT_GT(normal.dot(c.point) + d, -0.002) << "contact below the table";
    }
    // Every link origin of the closed hand stays above the table.
    for (const auto& link_pose : hand.linkPoses(g.joints)) {
      const Eigen::Vector3d p = g.hand_pose * link_pose.translation();
      EXPECT_GT(normal.dot(p) + d, -0.002) << "grasp " << g.id << " has a link below the table";
    }
  }
}

TEST(RealScanPipeline, PclStereoMugScene) {
  expectGraspsOnTheMug("pcl_table_scene_mug_stereo_textured.pcd");
}
TEST(RealScanPipeline, GpdKinectMugScene) {
  expectGraspsOnTheMug("gpd_table_mug.pcd");
}

TEST(RunPipeline, AllObjectsIsACallerMistake) {
  perception::Scan scan;
  RunParams params;
  params.reconstruction.ingest.scene.target.mode = perception::TargetMode::kAll;
  EXPECT_THROW(runPipeline(scan, loadBuiltinHand("sdh"), params), InvalidArgument);
}

TEST(RunPipeline, AnEmptySceneIsADataFailureNotACrash) {
  perception::Scan scan;
  scan.source = "empty";
  for (int i = 0; i < 50; ++i) scan.cloud.points.emplace_back(0.001 * i, 0, 0);
  const RunResult run = runPipeline(scan, loadBuiltinHand("sdh"), RunParams());
  EXPECT_FALSE(run.status.ok());
  EXPECT_TRUE(run.ranked.empty());
  EXPECT_FALSE(run.status.message.empty());
}

}  // namespace
}  // namespace skelgrasp::pipeline
