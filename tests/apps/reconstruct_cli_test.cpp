// skelgrasp reconstruct / ingest / datasets: outputs for good input, exit 2 and one error line for
// bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "cli_support.h"
#include "perception/synthetic_scenes.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/perception/cloud_io.h"
#include "skelgrasp/perception/image_io.h"
#include "skelgrasp/perception/scene.h"
#include "skelgrasp/reconstruction/meshing.h"
#include "test_support.h"

namespace skelgrasp {
namespace {

using test::BadCliInput;
using test::CliRun;
using test::countLines;
using test::lastLine;
using test::runCli;
using test::withDir;

// The rendered table-top scene as a binary-compressed PCD with its viewpoint.
std::string writeScene(const std::string& dir, bool with_objects = true) {
  const std::string path = dir + "/scene.pcd";
  perception::savePointCloud(path,
                             test::renderTableScene(41, {0.55, 0.05, 0.6}, with_objects).cloud);
  return path;
}

TEST(ReconstructCli, WritesMeshFlagsAndReport) {
  const std::string dir = test::tempDir("cli_reconstruct");
  const std::string scene = writeScene(dir);
  const CliRun r = runCli(
      "reconstruct " + scene + " --out " + dir + "/mug.ply --report " + dir + "/report.json", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(countLines(r.out), 1) << r.out;
  EXPECT_NE(r.out.find("mug.ply"), std::string::npos);
  const TriangleMesh mesh = loadMesh(dir + "/mug.ply");
  const auto observed = reconstruction::loadObservedFlags(dir + "/mug.ply");
  ASSERT_EQ(observed.size(), mesh.numVertices());
  const auto j = readJsonFile(dir + "/report.json");
  EXPECT_EQ(j["schema"], "skelgrasp.reconstruction/1");
  EXPECT_EQ(j["status"]["code"], "ok");
  EXPECT_EQ(j["clusters"].size(), 2u);
  EXPECT_GT(j["plane"]["coefficients"][2].get<double>(), 0.99);
  EXPECT_EQ(j["filters"]["steps"][0]["name"], "non_finite");
  EXPECT_EQ(j["scene"]["plane_hull_margin_m"].get<double>(),
            perception::SceneParams{}.plane_hull_margin_m);
  const auto& object = j["objects"][0];
  EXPECT_TRUE(object["mesh"]["closed"].get<bool>());
  EXPECT_EQ(object["mesh"]["vertices"], mesh.numVertices());
  EXPECT_EQ(object["mesh_file"], dir + "/mug.ply");
  std::size_t count = 0;
  for (auto f : observed) count += f;
  EXPECT_EQ(object["observed"]["vertices"], count);
  EXPECT_GT(object["poisson"]["faces"].get<int>(), 0);
  EXPECT_GT(j["timings"]["total_s"].get<double>(), 0.0);
}

TEST(ReconstructCli, AllObjectsAndIngest) {
  const std::string dir = test::tempDir("cli_all");
  const std::string scene = writeScene(dir);
  const CliRun all =
      runCli("-q reconstruct " + scene + " --object all --out " + dir + "/m.ply", dir);
  ASSERT_EQ(all.exit_code, 0) << all.err;
  EXPECT_EQ(countLines(all.out), 2);
  EXPECT_TRUE(std::filesystem::exists(dir + "/m_0.ply"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/m_1.ply"));
  const CliRun ingest =
      runCli("-q ingest " + scene + " --object nearest:-0.06,0.1,0.04 --hull-margin 0.05 --out " +
                 dir + "/box.pcd --report " + dir + "/ingest.json",
             dir);
  ASSERT_EQ(ingest.exit_code, 0) << ingest.err;
  const PointCloud box = perception::loadPointCloud(dir + "/box.pcd");
  EXPECT_TRUE(box.hasNormals());
  EXPECT_NEAR(box.bounds().center().y(), 0.10, 0.02);
  EXPECT_EQ(readJsonFile(dir + "/ingest.json")["scene"]["plane_hull_margin_m"].get<double>(), 0.05);
}

TEST(ReconstructCli, BenchSegmentScoresALabelledScanAndRefusesAnUnlabelledOne) {
  const std::string dir = test::tempDir("cli_bench_segment");
  // The generated scene carries no object labels: refused before anything runs.
  const std::string unlabelled = writeScene(dir);
  const CliRun refused = runCli("bench segment " + unlabelled, dir);
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_EQ(countLines(refused.err), 1) << refused.err;
  EXPECT_NE(lastLine(refused.err).find("scene.pcd"), std::string::npos) << refused.err;
  SKELGRASP_REQUIRE_SHARED_DATA();
  const std::string osd = test::sharedDataDir() + "/scans/pcd/osd_test2.pcd";
  if (!std::filesystem::exists(osd)) GTEST_SKIP() << osd << " not in the shared data";
  const CliRun r = runCli("-q bench segment " + osd + " --method lccp --hull-margin 0.05 --json " +
                              dir + "/segment.json",
                          dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = readJsonFile(dir + "/segment.json");
  EXPECT_EQ(j["schema"], "skelgrasp.bench_segment");
  EXPECT_EQ(j["method"], "lccp");
  EXPECT_EQ(j["parameters"]["plane_hull_margin_m"].get<double>(), 0.05);
  ASSERT_EQ(j["scenes"].size(), 1u);
  // Two boxes standing apart (docs/reconstruction.md: both found, precision 1.000).
  EXPECT_EQ(j["scenes"][0]["objects_labelled"], 2);
  EXPECT_EQ(j["scenes"][0]["objects_found"], 2);
  EXPECT_GT(j["scenes"][0]["mean_precision"].get<double>(), 0.99);
}

TEST(ReconstructCli, CaptureDescriptionAndYcbRawFolder) {
  const std::string dir = test::tempDir("cli_inputs");
  // A capture made with the simulated camera: depth .npy, mask .png, intrinsics, pose.
  const auto scene = test::renderTableScene(42);
  perception::DepthImage depth(640, 480);
  perception::MaskImage mask(640, 480, 0);
  const Pose camera = perception::lookAt({0.55, 0.05, 0.6}, {0, 0, 0.05});
  for (std::size_t i = 0; i < depth.data.size(); ++i) {
    const auto& p = scene.cloud.points[i];
    depth.data[i] = p.allFinite() ? static_cast<float>((camera.inverse() * p).z()) : 0.0f;
    mask.data[i] = scene.cloud.labels[i] == 2 ? 255 : 0;  // the cylinder
  }
  perception::writeDepthNpy(dir + "/depth.npy", depth);
  perception::writeMaskImage(dir + "/mask.png", mask);
  const auto xyzq = toXyzQuatWxyz(camera);
  std::ofstream(dir + "/capture.json")
      << "{\"depth\": \"depth.npy\", \"mask\": \"mask.png\", \"intrinsics\": {\"fx\": 525, "
         "\"fy\": 525, \"cx\": 319.5, \"cy\": 239.5, \"width\": 640, \"height\": 480}, "
         "\"camera_to_world\": \""
      << xyzq[0] << " " << xyzq[1] << " " << xyzq[2] << " " << xyzq[3] << " " << xyzq[4] << " "
      << xyzq[5] << " " << xyzq[6] << "\"}";
  const CliRun capture =
      runCli("-q reconstruct " + dir + "/capture.json --out " + dir + "/c.ply", dir);
  ASSERT_EQ(capture.exit_code, 0) << capture.err;
  EXPECT_NEAR(loadMesh(dir + "/c.ply").bounds().max.z(), 0.10, 0.01);  // the cylinder's top

  const CliRun fixture = runCli("datasets fixture ycb-raw " + dir + "/ycb/000_test", dir);
  ASSERT_EQ(fixture.exit_code, 0) << fixture.err;
  const CliRun raw = runCli("-q reconstruct " + dir + "/ycb --out " + dir + "/y.ply", dir);
  ASSERT_EQ(raw.exit_code, 0) << raw.err;
  EXPECT_NEAR(loadMesh(dir + "/y.ply").bounds().extent().z(), 0.10, 0.01);
}

class ReconstructCliBadInput : public ::testing::TestWithParam<BadCliInput> {};

TEST_P(ReconstructCliBadInput, ExitsTwoWithTheReasonOnTheLastLine) {
  const auto& c = GetParam();
  const std::string dir = test::tempDir("cli_bad_reconstruct_" + c.name);
  std::ofstream(dir + "/garbage.pcd") << "this is not a point cloud\n";
  std::ofstream(dir + "/empty.pcd") << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
                                       "COUNT 1 1 1\nWIDTH 0\nHEIGHT 1\nPOINTS 0\nDATA ascii\n";
  PointCloud nan;
  nan.points.assign(100, Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
  perception::savePointCloud(dir + "/nan.pcd", nan);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.15, 0.15);
  PointCloud volume;  // fills a cube: no plane anywhere
  for (int i = 0; i < 20000; ++i) volume.points.emplace_back(u(rng), u(rng), 0.8 + u(rng));
  perception::savePointCloud(dir + "/volume.pcd", volume);
  if (c.name == "no_object") writeScene(dir, false);

  const std::string args = withDir(c.args, dir);
  for (const std::string quiet : {"", "-q "}) {
    const CliRun r = runCli(quiet + args, dir);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    const std::string line = lastLine(r.err);
    EXPECT_EQ(line.rfind("skelgrasp: error: ", 0), 0u) << r.err;
    EXPECT_NE(line.find(c.expected), std::string::npos) << r.err;
    if (!quiet.empty()) {
      EXPECT_EQ(countLines(r.err), 1) << r.err;  // -q: nothing but the error
    }
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/out.ply"));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, ReconstructCliBadInput,
    ::testing::Values(
        BadCliInput{"missing", "reconstruct {dir}/none.pcd --out {dir}/out.ply",
                    "none.pcd: no such file"},
        BadCliInput{"corrupt", "reconstruct {dir}/garbage.pcd --out {dir}/out.ply",
                    "garbage.pcd: PCD header has no DATA line"},
        BadCliInput{"empty", "reconstruct {dir}/empty.pcd --out {dir}/out.ply",
                    "empty.pcd: point cloud has no points"},
        BadCliInput{"all_nan", "reconstruct {dir}/nan.pcd --out {dir}/out.ply",
                    "nan.pcd: all 100 points are NaN"},
        BadCliInput{"no_plane", "reconstruct {dir}/volume.pcd --out {dir}/out.ply",
                    "volume.pcd: no support plane found"},
        BadCliInput{"no_object", "reconstruct {dir}/scene.pcd --out {dir}/out.ply",
                    "scene.pcd: no object above the support plane"},
        BadCliInput{"ingest_no_plane", "ingest {dir}/volume.pcd --out {dir}/out.pcd",
                    "no support plane found"},
        BadCliInput{"bad_target",
                    "reconstruct {dir}/volume.pcd --object biggest --out {dir}/out.ply",
                    "bad object selection"},
        BadCliInput{"bad_output", "reconstruct {dir}/volume.pcd --out {dir}/out.obj",
                    "--out must be a .ply file"},
        BadCliInput{"not_ycb", "reconstruct {dir} --out {dir}/out.ply", "not a YCB raw capture"},
        BadCliInput{"bad_ycb_id", "datasets fetch ycb 003_cracker_box ../etc --dir {dir}",
                    "not a YCB object id"}),
    [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace skelgrasp
