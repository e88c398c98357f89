// skelgrasp simulate: plan's grasps executed by the physics judge; the document says per grasp
// whether it held, why not and per direction how far the object moved; sim_r with --samples is
// the same for the same seed; bad input is one line, exit 2, nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cli_support.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "test_support.h"

namespace skelgrasp {
namespace {

using test::CliRun;
using test::countLines;
using test::runCli;

// A plan of the parallel gripper on a generated box, simulated with two frictions and samples.
TEST(SimulateCli, PlansGraspsOnABoxAreExecutedWithTheirOutcomes) {
  const std::string dir = test::tempDir("cli_simulate_box");
  saveMesh(dir + "/box.ply", geometry::shapes::makeNamedShape("box"));
  const CliRun plan = runCli("plan " + dir + "/box.ply --hand parallel_gripper --max-grasps 3 " +
                                 "--robustness-samples 4 --out " + dir + "/grasps.json",
                             dir);
  ASSERT_EQ(plan.exit_code, 0) << plan.err;
  const std::string args = "simulate " + dir + "/grasps.json " + dir +
                           "/box.ply --mu 0.35,0.5 --samples 4 --seed 3 --out ";
  const CliRun first = runCli(args + dir + "/a.json", dir);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_NE(first.out.find("simulated"), std::string::npos) << first.out;
  const nlohmann::json a = readJsonFile(dir + "/a.json");
  EXPECT_EQ(a["schema"], "skelgrasp.simulation/1");
  EXPECT_EQ(a["hand"], "parallel_gripper");
  EXPECT_EQ(a["engine"], "bullet");
  EXPECT_DOUBLE_EQ(a["parameters"]["mass_kg"].get<double>(), 0.1);
  const nlohmann::json plan_file = readJsonFile(dir + "/grasps.json");
  ASSERT_EQ(a["grasps"].size(), plan_file["grasps"].size());
  ASSERT_GT(a["grasps"].size(), 0u);
  for (const auto& g : a["grasps"]) {
    ASSERT_EQ(g["physics"].size(), 2u);
    for (const auto& at : g["physics"]) {
      const auto& nominal = at["nominal"];
      if (nominal["holds"].get<bool>()) {
        EXPECT_TRUE(nominal["failed_phase"].is_null());
        ASSERT_EQ(nominal["disturbances"].size(), 6u);
        for (const auto& d : nominal["disturbances"]) {
          EXPECT_TRUE(d["held"].get<bool>());
          EXPECT_LT(d["displacement_m"].get<double>(), 0.02);
        }
      } else {
        EXPECT_TRUE(nominal["reason"].is_string());
      }
      const auto& r = at["robustness"];
      ASSERT_TRUE(r.is_object());
      EXPECT_EQ(r["samples"], 4);
      const double sim_r = r["sim_r"].get<double>();
      EXPECT_GE(sim_r, r["ci95"][0].get<double>());
      EXPECT_LE(sim_r, r["ci95"][1].get<double>());
      EXPECT_EQ(r["holds"].get<int>() + r["start_failures"].get<int>() +
                    r["closing_failures"].get<int>() + r["disturbance_failures"].get<int>(),
                4);
    }
  }
  // The same seed, the same executions.
  const CliRun second = runCli(args + dir + "/b.json", dir);
  ASSERT_EQ(second.exit_code, 0) << second.err;
  const nlohmann::json b = readJsonFile(dir + "/b.json");
  for (std::size_t i = 0; i < a["grasps"].size(); ++i) {
    for (std::size_t k = 0; k < 2; ++k) {
      EXPECT_EQ(a["grasps"][i]["physics"][k]["robustness"],
                b["grasps"][i]["physics"][k]["robustness"]);
      EXPECT_EQ(a["grasps"][i]["physics"][k]["nominal"]["disturbances"],
                b["grasps"][i]["physics"][k]["nominal"]["disturbances"]);
    }
  }
}

// bench physics on a folder of one generated mesh: a row per executed grasp, a summary per hand
// whose counts agree with the rows.
TEST(BenchPhysicsCli, RowsAndSummaryAgree) {
  const std::string dir = test::tempDir("cli_bench_physics");
  std::filesystem::create_directories(dir + "/meshes");
  saveMesh(dir + "/meshes/box.ply", geometry::shapes::makeNamedShape("box"));
  const CliRun run =
      runCli("bench physics " + dir + "/meshes --hands parallel_gripper --grasps 2 " +
                 "--samples 2 --robustness-samples 4 --json " + dir + "/out.json",
             dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("rho(r,sr)"), std::string::npos) << run.out;
  const nlohmann::json out = readJsonFile(dir + "/out.json");
  EXPECT_EQ(out["schema"], "skelgrasp.bench_physics/1");
  ASSERT_EQ(out["summary"].size(), 1u);
  const auto& summary = out["summary"][0];
  EXPECT_EQ(summary["objects"], 1);
  EXPECT_EQ(summary["grasps"].get<std::size_t>(), out["grasps"].size());
  std::size_t holds = 0;
  for (const auto& g : out["grasps"]) {
    holds += g["nominal_holds"].get<bool>();
    ASSERT_TRUE(g["sim_r"].is_number());
    EXPECT_GE(g["sim_r"].get<double>(), 0.0);
    EXPECT_LE(g["sim_r"].get<double>(), 1.0);
  }
  if (!out["grasps"].empty()) {
    EXPECT_NEAR(summary["nominal_hold_rate"].get<double>(),
                static_cast<double>(holds) / static_cast<double>(out["grasps"].size()), 1e-12);
  }
}

TEST(SimulateCliErrors, BadInputIsOneLineAndExitTwoAndWritesNothing) {
  const std::string dir = test::tempDir("cli_simulate_bad");
  saveMesh(dir + "/capsule.ply", geometry::shapes::makeNamedShape("capsule"));
  std::ofstream(dir + "/good.json")
      << R"({"schema": "skelgrasp.grasps/1", "hand": "sdh", "grasps": [{"id": 0,
           "hand_pose": {"position": [0, 0, 0.3], "quaternion_wxyz": [1, 0, 0, 0]}}]})";
  std::ofstream(dir + "/broken.json") << "{\"schema\": \"skelgrasp.grasps/1\", \"grasps\": [";
  const std::string mesh = " " + dir + "/capsule.ply";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"simulate " + dir + "/missing.json" + mesh, "missing.json"},
      {"simulate " + dir + "/broken.json" + mesh + " --hand sdh", "broken.json: not valid JSON"},
      {"simulate " + dir + "/good.json " + dir + "/missing.ply", "missing.ply"},
      {"simulate " + dir + "/good.json" + mesh + " --hand armar3", "planned with hand"},
      {"simulate " + dir + "/good.json" + mesh + " --mass 0", "--mass"},
      {"simulate " + dir + "/good.json" + mesh + " --mass nan", "--mass"},
      {"simulate " + dir + "/good.json" + mesh + " --density -3", "--density"},
      {"simulate " + dir + "/good.json" + mesh + " --fingertip-force 1e9", "--fingertip-force"},
      {"simulate " + dir + "/good.json" + mesh + " --samples 100000", "--samples"},
      {"simulate " + dir + "/good.json" + mesh + " --time-step 0.5", "--time-step"},
      {"simulate " + dir + "/good.json" + mesh + " --mu -1", "--mu"},
  };
  for (const auto& [args, expected] : cases) {
    const CliRun run = runCli(args + " --out " + dir + "/out.json", dir);
    EXPECT_EQ(run.exit_code, 2) << args;
    EXPECT_EQ(countLines(run.err), 1) << args << ": " << run.err;
    EXPECT_NE(run.err.find("skelgrasp: error: "), std::string::npos) << args << ": " << run.err;
    EXPECT_NE(run.err.find(expected), std::string::npos) << args << ": " << run.err;
    EXPECT_FALSE(std::filesystem::exists(dir + "/out.json")) << args;
  }
  // A hand 30 cm above the capsule closes on nothing: a clear outcome, exit 0.
  const CliRun far =
      runCli("simulate " + dir + "/good.json" + mesh + " --out " + dir + "/out.json", dir);
  ASSERT_EQ(far.exit_code, 0) << far.err;
  const nlohmann::json out = readJsonFile(dir + "/out.json");
  const auto& nominal = out["grasps"][0]["physics"][0]["nominal"];
  EXPECT_FALSE(nominal["holds"].get<bool>());
  EXPECT_EQ(nominal["failed_phase"], "closing");
}

}  // namespace
}  // namespace skelgrasp
