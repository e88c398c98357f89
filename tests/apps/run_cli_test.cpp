// skelgrasp run / demo: the product's main job from the command line.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "cli_support.h"
#include "perception/synthetic_scenes.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/perception/cloud_io.h"
#include "skelgrasp/perception/demo_scene.h"
#include "test_support.h"

namespace skelgrasp {
namespace {

using test::BadCliInput;
using test::CliRun;
using test::countLines;
using test::lastLine;
using test::runCli;
using test::withDir;

TEST(RunCli, ScanToRankedGraspsWithReport) {
  const std::string dir = test::tempDir("cli_run");
  perception::savePointCloud(dir + "/scene.pcd", test::renderTableScene(41).cloud);
  // The cylinder of the synthetic scene stands at (0.05, -0.09).
  const CliRun r = runCli(
      "run " + dir + "/scene.pcd --hand sdh --object nearest:0.05,-0.09,0.05 --out " + dir + "/out",
      dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // One line per stage, then the summary.
  for (const char* stage :
       {"filter", "segment", "reconstruct", "skeleton", "occupancy", "plan", "rank"}) {
    EXPECT_NE(r.out.find(stage), std::string::npos) << stage << " missing in\n" << r.out;
  }
  EXPECT_NE(lastLine(r.out).find("ranked grasps"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("skeleton planner"), std::string::npos);  // progress on stderr

  const auto j = readJsonFile(dir + "/out/grasps.json");
  EXPECT_EQ(j["schema"], "skelgrasp.run/4");
  EXPECT_EQ(j["hand"], "sdh");
  ASSERT_EQ(j["scene"]["plane"].size(), 4u);
  EXPECT_GT(j["scene"]["plane"][2].get<double>(), 0.99);  // z up, the objects above
  EXPECT_GT(j["grasps"].size(), 0u);
  const auto& target = j["target"];
  EXPECT_NEAR(target["centroid"][0].get<double>(), 0.05, 0.02);
  EXPECT_NEAR(target["centroid"][1].get<double>(), -0.09, 0.02);
  for (const auto& g : j["grasps"]) {
    EXPECT_TRUE(g["force_closure"].get<bool>());
    EXPECT_GE(g["observed_contact_ratio"].get<double>(), 0.0);
  }
  for (const char* file : {"object.ply", "skeleton.json", "segmentation.ply", "scene.bt",
                           "report.html", "scan.png", "grasps.png"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/out/" + file)) << file;
  }
  EXPECT_GT(loadMesh(dir + "/out/object.ply").numVertices(), 100u);
}

class RunCliBadInput : public ::testing::TestWithParam<BadCliInput> {};

TEST_P(RunCliBadInput, ExitsTwoWithOneErrorLine) {
  const auto& c = GetParam();
  const std::string dir = test::tempDir("cli_bad_run_" + c.name);
  std::ofstream(dir + "/garbage.pcd") << "this is not a point cloud\n";
  perception::savePointCloud(dir + "/table.pcd",
                             test::renderTableScene(41, {0.55, 0.05, 0.6}, false).cloud);
  const std::string args = withDir(c.args, dir);
  const CliRun r = runCli("-q " + args, dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(r.err.rfind("skelgrasp: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out/grasps.json"));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, RunCliBadInput,
    ::testing::Values(
        BadCliInput{"missing", "run {dir}/none.pcd --out {dir}/out", "none.pcd"},
        BadCliInput{"garbage", "run {dir}/garbage.pcd --out {dir}/out", "garbage.pcd"},
        BadCliInput{"no_object", "run {dir}/table.pcd --out {dir}/out", "table.pcd"},
        BadCliInput{"all_objects_of_none", "run {dir}/table.pcd --object all --out {dir}/out",
                    "table.pcd"},
        BadCliInput{"bad_hand", "run {dir}/table.pcd --hand nohand --out {dir}/out", "nohand"}),
    [](const auto& info) { return info.param.name; });

// `run --object all`: every object of the synthetic scene (a cylinder and a box) in one process,
// one object list in grasps.json, a mesh per object, a report section per object.
TEST(RunCli, EveryObjectInOneRun) {
  const std::string dir = test::tempDir("cli_run_all");
  perception::savePointCloud(dir + "/scene.pcd", test::renderTableScene(41).cloud);
  const CliRun r =
      runCli("run " + dir + "/scene.pcd --hand sdh --object all --out " + dir + "/out", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(lastLine(r.out).find("objects got grasps"), std::string::npos) << r.out;
  const auto j = readJsonFile(dir + "/out/grasps.json");
  EXPECT_EQ(j["schema"], "skelgrasp.run/4");
  const auto& objects = j["objects"];
  ASSERT_EQ(objects.size(), 2u) << objects.dump();
  std::size_t listed = 0, hypotheses = 0;
  for (std::size_t k = 0; k < objects.size(); ++k) {
    const auto& o = objects[k];
    EXPECT_EQ(o["id"], k);
    // What the planner did with the object, and why an object without grasps has none.
    ASSERT_TRUE(o["planning"].is_object()) << o.dump();
    EXPECT_GT(o["planning"]["hypotheses"].get<std::size_t>(), 0u);
    if (o["grasps"].get<std::size_t>() == 0) {
      EXPECT_FALSE(o["planning"]["rejections"].empty());
    }
    hypotheses += o["planning"]["hypotheses"].get<std::size_t>();
    EXPECT_GT(o["points"].get<std::size_t>(), 100u);
    ASSERT_TRUE(o["mesh"].is_string());
    EXPECT_GT(loadMesh(dir + "/out/" + o["mesh"].get<std::string>()).numVertices(), 100u);
    // An object has grasps, or says why not (the SDH finds none on this box, in a one-target
    // run too: the scene blocks most of its hypotheses).
    EXPECT_NE(o["grasps"].get<std::size_t>() > 0, o["reason"].is_string()) << o.dump();
    listed += o["grasps"].get<std::size_t>();
  }
  // The two objects: the cylinder at (0.05, -0.09) and the box at (-0.06, 0.10), in either order.
  const double x0 = objects[0]["centroid"][0].get<double>();
  const double x1 = objects[1]["centroid"][0].get<double>();
  EXPECT_NEAR(std::min(x0, x1), -0.06, 0.02);
  EXPECT_NEAR(std::max(x0, x1), 0.05, 0.02);
  EXPECT_GT(listed, 0u);
  ASSERT_EQ(j["grasps"].size(), listed);
  EXPECT_EQ(j["summary"]["hypotheses"].get<std::size_t>(), hypotheses);  // the scene's sums
  EXPECT_EQ(j["summary"]["kept"].get<std::size_t>(), listed);
  for (std::size_t i = 0; i < j["grasps"].size(); ++i) {
    const auto& g = j["grasps"][i];
    EXPECT_EQ(g["id"], i);  // ids are unique over the scene
    EXPECT_LT(g["object"].get<std::size_t>(), objects.size());
    EXPECT_TRUE(g["force_closure"].get<bool>());
  }
  std::ifstream html_file(dir + "/out/report.html");
  const std::string html((std::istreambuf_iterator<char>(html_file)), {});
  for (const char* text : {"Object 0", "Object 1", "scan.png", "grasps_0.png", "data-status",
                           "Object 1: why hypotheses were rejected"}) {
    EXPECT_NE(html.find(text), std::string::npos) << text;
  }
  for (const char* file : {"scene.bt", "scan.png", "skeleton_0.json", "skeleton_1.json"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/out/" + file)) << file;
  }
}

TEST(DemoCli, EveryObjectOfTheGeneratedSceneGetsGraspsAndAReport) {
  const std::string dir = test::tempDir("cli_demo");
  const CliRun r = runCli("demo --out " + dir + "/demo", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(lastLine(r.out).find("index.html"), std::string::npos) << r.out;
  // A real PCD with the first camera as its viewpoint.
  const auto cloud = perception::loadPointCloud(dir + "/demo/scene.pcd");
  EXPECT_GT(cloud.size(), 100000u);
  EXPECT_GT(cloud.sensor_origin.norm(), 0.5);
  // One `run --object all`: one report, one grasps.json with every object, and the index naming
  // the objects the scene was made of with a link to each one's section.
  for (const char* file : {"index.html", "report.html", "scene.bt", "scan.png"})
    EXPECT_TRUE(std::filesystem::exists(dir + "/demo/" + file)) << file;
  const auto j = readJsonFile(dir + "/demo/grasps.json");
  ASSERT_GE(j["objects"].size(), 5u);
  std::ifstream index_file(dir + "/demo/index.html");
  const std::string index((std::istreambuf_iterator<char>(index_file)), {});
  const auto demo = perception::makeDemoScene(1, 3);
  for (std::size_t k = 1; k < demo.meshes.size(); ++k) {
    const std::string& object = demo.names[k];
    EXPECT_TRUE(std::filesystem::exists(dir + "/demo/truth_" + object + ".ply")) << object;
    EXPECT_NE(index.find("<td>" + object + "</td>"), std::string::npos) << object;
    // The run's object nearest to what was made has grasps.
    double best = 1e9;
    std::size_t grasps = 0;
    for (const auto& o : j["objects"]) {
      const Eigen::Vector3d c(o["centroid"][0], o["centroid"][1], o["centroid"][2]);
      if ((c - demo.centres[k]).norm() < best) {
        best = (c - demo.centres[k]).norm();
        grasps = o["grasps"].get<std::size_t>();
      }
    }
    EXPECT_LT(best, 0.05) << object;
    EXPECT_GE(grasps, 1u) << object;
  }
  EXPECT_NE(index.find("report.html#object-"), std::string::npos);
}

TEST(BenchRunCli, ReportsEveryStageOfEveryInput) {
  const std::string dir = test::tempDir("cli_bench_run");
  perception::savePointCloud(dir + "/scene.pcd", test::renderTableScene(41).cloud);
  const CliRun r = runCli("bench run " + dir +
                              "/scene.pcd --hand sdh --object nearest:0.05,-0.09,0.05 "
                              "--repeat 1 --json " +
                              dir + "/bench.json",
                          dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = readJsonFile(dir + "/bench.json");
  ASSERT_EQ(j["rows"].size(), 1u) << j.dump();
  const auto& row = j["rows"][0];
  EXPECT_EQ(row["status"], "ok");
  EXPECT_GE(row["grasps"].get<int>(), 1);
  double sum = 0;
  for (const char* stage :
       {"filter", "segment", "reconstruct", "skeleton", "occupancy", "plan", "rank"}) {
    ASSERT_TRUE(row["stages_s"].contains(stage)) << stage;
    const double seconds = row["stages_s"][stage].get<double>();
    EXPECT_TRUE(std::isfinite(seconds) && seconds >= 0) << stage << ": " << seconds;
    sum += seconds;
  }
  // The stages are parts of the run (no assertion on how large a share: that is the machine's
  // load, not the program's).
  EXPECT_LE(sum, row["total_s"].get<double>() + 1e-6);
}

}  // namespace
}  // namespace skelgrasp
