// skelgrasp bench scan2grasp: a generated shape on a table, seen in one view, run and judged on
// its true mesh; the JSON's rows and summary agree with each other and with the printed table;
// bad input is one line, exit 2, nothing written.
#include <gtest/gtest.h>

#include <filesystem>

#include "cli_support.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "test_support.h"

namespace skelgrasp {
namespace {

using test::CliRun;
using test::runCli;

TEST(BenchScanToGraspCli, RowsAndSummaryAgree) {
  const std::string dir = test::tempDir("cli_bench_scan2grasp");
  saveMesh(dir + "/bottle.ply", geometry::shapes::makeNamedShape("bottle"));
  const CliRun run =
      runCli("bench scan2grasp " + dir + "/bottle.ply --hands parallel_gripper --views 1 " +
                 "--grasps 3 --true-samples 4 --robustness-samples 4 --json " + dir + "/b.json",
             dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("parallel_gripper"), std::string::npos) << run.out;
  const nlohmann::json b = readJsonFile(dir + "/b.json");
  EXPECT_EQ(b["schema"], "skelgrasp.bench_scan2grasp/1");
  EXPECT_EQ(b["surface_clearance"], true);  // run's default
  EXPECT_EQ(b["load_check"], true);
  ASSERT_EQ(b["cases"].size(), 1u);
  const auto& view = b["cases"][0];
  EXPECT_EQ(view["object"], "bottle");
  EXPECT_EQ(view["hand"], "parallel_gripper");
  EXPECT_GT(view["object_pixels"].get<int>(), 500);
  // The run's error bounds against the true surface: most vertices lie within theirs.
  const auto& error = view["reconstruction_error_mm"];
  ASSERT_FALSE(error["within_bound"].is_null());
  EXPECT_GT(error["within_bound"].get<double>(), 0.5);
  const double distance = view["camera"]["distance_m"].get<double>();
  EXPECT_GE(distance, 0.7);
  EXPECT_LE(distance, 0.9);
  ASSERT_EQ(b["summary"].size(), 1u);
  const auto& summary = b["summary"][0];
  EXPECT_EQ(summary["views"], 1);
  const std::size_t returned = view["returned"].get<std::size_t>();
  EXPECT_EQ(summary["views_with_grasps"].get<std::size_t>(), returned > 0 ? 1u : 0u);
  ASSERT_EQ(b["grasps"].size(), std::min<std::size_t>(returned, 3));
  ASSERT_EQ(summary["top_grasps"].get<std::size_t>(), b["grasps"].size());
  // One view: the medians are that view's means, the counts its grasps'.
  double true_sum = 0, claimed_sum = 0;
  std::size_t inside = 0, holds = 0, claimed = 0;
  for (const auto& g : b["grasps"]) {
    const double r = g["true_r"].get<double>();
    EXPECT_GE(r, 0.0);
    EXPECT_LE(r, 1.0);
    true_sum += r;
    if (g["starts_inside"].get<bool>()) {
      ++inside;
      EXPECT_EQ(r, 0.0);
      EXPECT_EQ(g["closing_failure"], "start_collision");
    }
    holds += g["nominal_holds"].get<bool>();
    if (!g["claimed_r"].is_null()) {
      claimed_sum += g["claimed_r"].get<double>();
      ++claimed;
    }
  }
  const double n = static_cast<double>(b["grasps"].size());
  EXPECT_EQ(summary["starts_inside"].get<std::size_t>(), inside);
  if (n > 0) {
    EXPECT_NEAR(summary["median_true_r"].get<double>(), true_sum / n, 1e-9);
    EXPECT_NEAR(summary["nominal_hold_rate"].get<double>(), holds / n, 1e-9);
  }
  if (claimed > 0) {
    EXPECT_NEAR(summary["median_claimed_r"].get<double>(), claimed_sum / claimed, 1e-9);
  }
  EXPECT_GT(summary["median_run_s"].get<double>(), 0.0);
}

TEST(BenchScanToGraspCli, ARealMeshIsReconstructedWhereItIs) {
  // A YCB mesh (metres) seen in one view: the run's mesh, mapped back with the view's transform,
  // lies on the true surface where the camera saw it (the sensor's noise and the reconstruction
  // are millimetres; a wrong frame would be centimetres).
  SKELGRASP_REQUIRE_SHARED_DATA();
  const std::string mesh = test::sharedDataDir() + "/objects/ycb/006_mustard_bottle.ply";
  if (!std::filesystem::exists(mesh)) GTEST_SKIP() << mesh << " not in the shared data";
  const std::string dir = test::tempDir("cli_bench_scan2grasp_ycb");
  const CliRun run = runCli("bench scan2grasp " + mesh +
                                " --hands parallel_gripper --views 1 --grasps 2 --true-samples 4 "
                                "--robustness-samples 4 --no-physics --json " +
                                dir + "/b.json",
                            dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json b = readJsonFile(dir + "/b.json");
  ASSERT_EQ(b["cases"].size(), 1u);
  const auto& error = b["cases"][0]["reconstruction_error_mm"];
  ASSERT_FALSE(error["observed_median"].is_null());
  EXPECT_LT(error["observed_median"].get<double>(), 4.0);
  EXPECT_GT(b["cases"][0]["returned"].get<int>(), 0);
  for (const auto& g : b["grasps"]) EXPECT_TRUE(g["nominal_holds"].is_null());  // --no-physics
}

TEST(BenchScanToGraspCli, BadInputIsOneLineAndWritesNothing) {
  const std::string dir = test::tempDir("cli_bench_scan2grasp_bad");
  const CliRun missing =
      runCli("bench scan2grasp " + dir + "/none.ply --json " + dir + "/b.json", dir);
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_EQ(test::countLines(missing.err), 1) << missing.err;
  EXPECT_NE(missing.err.find("none.ply"), std::string::npos) << missing.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/b.json"));
  saveMesh(dir + "/box.ply", geometry::shapes::makeNamedShape("box"));
  const CliRun hand =
      runCli("bench scan2grasp " + dir + " --hands nohand --json " + dir + "/b.json", dir);
  EXPECT_EQ(hand.exit_code, 2);
  EXPECT_FALSE(std::filesystem::exists(dir + "/b.json"));
}

}  // namespace
}  // namespace skelgrasp
