// Command-line numbers and poses: every bad value ends with exit 2 and one line
// "skelgrasp: error: <option>: <problem>"; legal values, thread counts above the machine's cores
// included, still work.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "cli_support.h"
#include "perception/synthetic_scenes.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/perception/cloud_io.h"
#include "test_support.h"

namespace skelgrasp {
namespace {

using test::BadCliInput;
using test::CliRun;
using test::countLines;
using test::runCli;
using test::withDir;

// Writes the small inputs the cases name: a box mesh, a contact file and an objects folder.
void writeInputs(const std::string& dir) {
  saveMesh(dir + "/box.ply", geometry::shapes::makeBox({0.05, 0.09, 0.16}, 2));
  std::filesystem::create_directories(dir + "/objects");
  saveMesh(dir + "/objects/box.ply", geometry::shapes::makeBox({0.05, 0.09, 0.16}, 2));
  std::ofstream(dir + "/contacts.json")
      << R"({"contacts": [{"point": [0.03, 0, 0], "normal": [1, 0, 0]},
                          {"point": [-0.03, 0, 0], "normal": [-1, 0, 0]}]})";
}

class CliBadOption : public ::testing::TestWithParam<BadCliInput> {};

TEST_P(CliBadOption, ExitsTwoWithOneErrorLineNamingTheOption) {
  const auto& c = GetParam();
  const std::string dir = test::tempDir("cli_bad_option_" + c.name);
  writeInputs(dir);
  const CliRun r = runCli(withDir(c.args, dir), dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(countLines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("skelgrasp: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out"));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, CliBadOption,
    ::testing::Values(
        // Item 1: parser errors in the house format, naming the option and its range.
        BadCliInput{"cone_edges", "quality {dir}/contacts.json --cone-edges 2",
                    "--cone-edges: 2 is outside [3, 64]"},
        BadCliInput{"poisson_depth",
                    "reconstruct {dir}/scan.pcd --out {dir}/out/m.ply --poisson-depth 100",
                    "--poisson-depth: 100 is outside [2, 14]"},
        BadCliInput{"unknown_option", "plan {dir}/box.ply --no-such-option 3 --out {dir}/out",
                    "--no-such-option"},
        BadCliInput{"missing_argument", "plan --hand sdh", "MESH is required"},
        BadCliInput{"missing_value", "plan {dir}/box.ply --out {dir}/out --timeout", "--timeout"},
        BadCliInput{"unknown_command", "no-such-command", "unknown command 'no-such-command'"},
        BadCliInput{"not_a_number", "plan {dir}/box.ply --mu abc --out {dir}/out",
                    "--mu: 'abc' is not a number"},
        BadCliInput{"choice", "run {dir}/scan.pcd --unknown-space maybe --out {dir}/out",
                    "--unknown-space"},
        // Item 2: finite numbers inside their documented range.
        BadCliInput{"voxel_nan", "ingest {dir}/scan.pcd --out {dir}/out/c.pcd --voxel nan",
                    "--voxel: 'nan' is not a finite number"},
        BadCliInput{"voxel_inf", "ingest {dir}/scan.pcd --out {dir}/out/c.pcd --voxel inf",
                    "--voxel: 'inf' is not a finite number"},
        BadCliInput{"timeout_nan", "plan {dir}/box.ply --timeout nan --out {dir}/out",
                    "--timeout: 'nan' is not a finite number"},
        BadCliInput{"evaluate_timeout_nan",
                    "evaluate --objects {dir}/objects --timeout NaN "
                    "--out {dir}/out",
                    "--timeout: 'NaN' is not a finite number"},
        BadCliInput{"max_grasps_negative", "plan {dir}/box.ply --max-grasps -1 --out {dir}/out",
                    "--max-grasps: '-1' is not a whole number in [0, "},
        BadCliInput{"max_grasps_fraction", "plan {dir}/box.ply --max-grasps 2.5 --out {dir}/out",
                    "--max-grasps: '2.5' is not a whole number"},
        BadCliInput{"seed_negative", "plan {dir}/box.ply --seed -3 --out {dir}/out", "--seed"},
        BadCliInput{"alpha_divisor_zero",
                    "skeleton {dir}/box.ply --alpha-divisor 0 --out {dir}/out",
                    "--alpha-divisor: 0 is outside (0, "},
        BadCliInput{"max_vertices_below_a_tetrahedron",
                    "skeleton {dir}/box.ply --max-vertices 3 --out {dir}/out",
                    "--max-vertices: a vertex budget must be 0 (never) or at least 4, not 3"},
        BadCliInput{"max_vertices_negative", "run {dir}/scan.pcd --max-vertices -5 --out {dir}/out",
                    "--max-vertices: '-5' is not a whole number"},
        BadCliInput{"mu_huge", "close {dir}/box.ply --pose \"0 0 0 1 0 0 0\" --mu 1e300",
                    "--mu: 1e300 is outside [0, 10]"},
        BadCliInput{"vertex_distance_negative",
                    "evaluate --objects {dir}/objects --vertex-distance -0.01 --out {dir}/out",
                    "--vertex-distance: -0.01 is outside [0, 1000]"},
        BadCliInput{"torsion_negative",
                    "score {dir}/grasps.json {dir}/box.ply --torsional-friction -0.002 --out "
                    "{dir}/out",
                    "--torsional-friction: -0.002 is outside [0, 1000]"},
        BadCliInput{"octree_nan", "run {dir}/scan.pcd --octree-resolution nan --out {dir}/out",
                    "--octree-resolution: 'nan' is not a finite number"},
        BadCliInput{"scene_lift_negative", "run {dir}/scan.pcd --scene-lift -0.01 --out {dir}/out",
                    "--scene-lift: -0.01 is outside [0, 1000]"},
        BadCliInput{"cameras", "reconstruct {dir} --cameras 1,7 --out {dir}/out/m.ply",
                    "--cameras: 7 is outside [1, 5]"},
        BadCliInput{"screen_samples_zero",
                    "evaluate --objects {dir}/objects --robust-ranking "
                    "--robustness-screen-samples 0 --out {dir}/out",
                    "--robustness-screen-samples: 0 is outside [1, "},
        BadCliInput{"confirm_samples_negative",
                    "evaluate --objects {dir}/objects --robust-ranking "
                    "--robustness-confirm-samples -1 --out {dir}/out",
                    "--robustness-confirm-samples"},
        BadCliInput{"screen_by", "plan {dir}/box.ply --robustness-screen-by random --out {dir}/out",
                    "--robustness-screen-by: random not in {preshapes,epsilon,travel}"},
        BadCliInput{"shard", "evaluate --objects {dir}/objects --shard 1x/4 --out {dir}/out",
                    "--shard '1x/4'"},
        // Item 3: thread and job counts.
        BadCliInput{"jobs_zero", "evaluate --objects {dir}/objects --jobs 0 --out {dir}/out",
                    "--jobs: 0 is outside [1, "},
        BadCliInput{"threads_negative",
                    "reconstruct {dir}/scan.pcd --threads -4 --out {dir}/out/m.ply",
                    "--threads: '-4' is not a whole number"},
        // Item 4: poses.
        BadCliInput{"pose_commas", "close {dir}/box.ply --pose 0,0,0,1,0,0,0",
                    "--pose: pose '0,0,0,1,0,0,0': separate the numbers with spaces, not commas"},
        BadCliInput{"pose_far", "close {dir}/box.ply --pose \"1e300 0 0 1 0 0 0\"",
                    "m from the origin, at most 1000 m allowed"},
        BadCliInput{"pose_nan", "close {dir}/box.ply --pose \"0 0 nan 1 0 0 0\"",
                    "'nan' is not a finite number"},
        BadCliInput{"pose_quaternion", "close {dir}/box.ply --pose \"0 0 0 0.5 0 0 0\"",
                    "quaternion (qw qx qy qz) has length 0.5"},
        BadCliInput{"pose_count", "close {dir}/box.ply --pose \"0 0 0 1 0 0\"",
                    "expected 7 numbers"},
        BadCliInput{"pose_matrix", "close {dir}/box.ply --pose \"1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 2\"",
                    "last row of the 4x4 matrix must be 0 0 0 1"}),
    [](const auto& info) { return info.param.name; });

TEST(CliOptions, HelpShowsRangesAndDefaults) {
  const std::string dir = test::tempDir("cli_options_help");
  const CliRun quality = runCli("quality --help", dir);
  EXPECT_EQ(quality.exit_code, 0) << quality.err;
  EXPECT_TRUE(quality.err.empty()) << quality.err;
  EXPECT_NE(quality.out.find("[3, 64]"), std::string::npos) << quality.out;
  const CliRun plan = runCli("plan --help", dir);
  EXPECT_EQ(plan.exit_code, 0) << plan.err;
  EXPECT_NE(plan.out.find("--max-grasps"), std::string::npos) << plan.out;
  EXPECT_NE(plan.out.find(">= 0"), std::string::npos) << plan.out;
  EXPECT_NE(plan.out.find("[0, 10]"), std::string::npos) << plan.out;  // --mu
}

TEST(CliOptions, LegalValuesStillWork) {
  const std::string dir = test::tempDir("cli_options_legal");
  writeInputs(dir);
  // Leading zeros are decimal (not octal: 010 would be 8), a count at its bound, the largest
  // seed, friction at its bound: the same plan as with "10".
  const std::string plan_args =
      " --hand parallel_gripper --planner surface --max-grasps "
      "1000000000 --seed 18446744073709551615 --timeout 0 --mu 10";
  const CliRun plan = runCli(
      "plan " + dir + "/box.ply --hypotheses 010 --out " + dir + "/grasps_010.json" + plan_args,
      dir);
  ASSERT_EQ(plan.exit_code, 0) << plan.err;
  const CliRun ten = runCli(
      "plan " + dir + "/box.ply --hypotheses 10 --out " + dir + "/grasps_10.json" + plan_args, dir);
  ASSERT_EQ(ten.exit_code, 0) << ten.err;
  EXPECT_EQ(readJsonFile(dir + "/grasps_010.json")["summary"]["hypotheses"],
            readJsonFile(dir + "/grasps_10.json")["summary"]["hypotheses"]);

  const CliRun quality = runCli("quality " + dir + "/contacts.json --cone-edges 64 --json", dir);
  EXPECT_EQ(quality.exit_code, 0) << quality.err;
}

TEST(CliOptions, CloseTakesSevenOrSixteenNumbersAndNormalisesANearUnitQuaternion) {
  const std::string dir = test::tempDir("cli_options_pose");
  writeInputs(dir);
  const std::string base = "close " + dir + "/box.ply --hand parallel_gripper --preshape precision";
  // The gripper approaching along -y (a rotation of 90 degrees about x), as 7 and as 16 numbers.
  const CliRun seven = runCli(base + " --json --pose \"0 0.035 0 0.7071068 0.7071068 0 0\"", dir);
  ASSERT_EQ(seven.exit_code, 0) << seven.err;
  const CliRun sixteen =
      runCli(base + " --json --pose \"1 0 0 0  0 0 -1 0.035  0 1 0 0  0 0 0 1\"", dir);
  ASSERT_EQ(sixteen.exit_code, 0) << sixteen.err;
  const auto a = nlohmann::json::parse(seven.out), b = nlohmann::json::parse(sixteen.out);
  EXPECT_EQ(a["status"], "closed");
  EXPECT_EQ(b["status"], "closed");
  EXPECT_NEAR(a["joints"]["finger_left"].get<double>(), b["joints"]["finger_left"].get<double>(),
              1e-6);
  // |q| = 1.0008: normalised, with a warning, same closing.
  const CliRun near = runCli(base + " --json --pose \"0 0.035 0 0.7076725 0.7076725 0 0\"", dir);
  ASSERT_EQ(near.exit_code, 0) << near.err;
  EXPECT_NE(near.err.find("normalised"), std::string::npos) << near.err;
  EXPECT_NEAR(nlohmann::json::parse(near.out)["joints"]["finger_left"].get<double>(),
              a["joints"]["finger_left"].get<double>(), 1e-6);
}

TEST(CliOptions, ThreadAndJobCountsAreCappedAtTheCores) {
  const std::string dir = test::tempDir("cli_options_threads");
  writeInputs(dir);
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  perception::savePointCloud(dir + "/scene.pcd",
                             test::renderTableScene(41, {0.55, 0.05, 0.6}).cloud);
  const CliRun ingest =
      runCli("ingest " + dir + "/scene.pcd --threads 100000 --out " + dir + "/object.pcd", dir);
  ASSERT_EQ(ingest.exit_code, 0) << ingest.err;
  EXPECT_NE(ingest.err.find("100000 threads requested, this machine has " + std::to_string(cores) +
                            ": using " + std::to_string(cores)),
            std::string::npos)
      << ingest.err;
  EXPECT_TRUE(std::filesystem::exists(dir + "/object.pcd"));

  const CliRun evaluate = runCli("-q evaluate --objects " + dir +
                                     "/objects --hands parallel_gripper --planners surface "
                                     "--jobs 100000 --timeout 1 --robustness-samples 2 "
                                     "--robustness-grasps 1 --out " +
                                     dir + "/evaluation",
                                 dir);
  ASSERT_EQ(evaluate.exit_code, 0) << evaluate.err;
  EXPECT_NE(evaluate.err.find("100000 threads requested"), std::string::npos) << evaluate.err;
  EXPECT_TRUE(std::filesystem::exists(dir + "/evaluation/summary.md"));
}

}  // namespace
}  // namespace skelgrasp
