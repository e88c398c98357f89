// skelgrasp score: re-scoring plan's own grasps gives plan's numbers back; several mu in one
// process; run files with several objects; bad input is one line, exit 2, nothing written.
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

constexpr double kRelativeEpsilonTolerance = 1e-9;

// Plan's grasps against score's: same contacts, force closure and epsilon at plan's mu (the first
// of score's), force closure kept at the larger mu, r inside its interval inside [0, 1].
void expectScoresMatchPlan(const nlohmann::json& plan, const nlohmann::json& scores) {
  ASSERT_EQ(scores["schema"], "skelgrasp.score/1");
  const auto& planned = plan["grasps"];
  const auto& scored = scores["grasps"];
  ASSERT_EQ(scored.size(), planned.size());
  for (std::size_t i = 0; i < planned.size(); ++i) {
    SCOPED_TRACE(::testing::Message() << "grasp " << i);
    const auto& p = planned[i];
    const auto& s = scored[i];
    EXPECT_EQ(s["id"], p["id"]);
    EXPECT_EQ(s["preshape"], p["preshape"]);
    EXPECT_TRUE(s["closed"].get<bool>());
    EXPECT_EQ(s["contacts"].get<std::size_t>(), p["contacts"].size());
    const auto& low = s["closure"][0];
    const auto& high = s["closure"][1];
    EXPECT_EQ(low["force_closure"], p["force_closure"]);
    const double epsilon = p["epsilon"].get<double>();
    EXPECT_NEAR(low["epsilon"].get<double>(), epsilon, kRelativeEpsilonTolerance * epsilon);
    if (low["force_closure"].get<bool>()) {
      EXPECT_TRUE(high["force_closure"].get<bool>());
    }
    for (const auto& at : s["closure"]) {
      const auto& r = at["robustness"];
      ASSERT_TRUE(r.is_object()) << at.dump();
      const double value = r["r"].get<double>();
      const double lo = r["ci95"][0].get<double>(), hi = r["ci95"][1].get<double>();
      EXPECT_LE(0.0, lo);
      EXPECT_LE(lo, value);
      EXPECT_LE(value, hi);
      EXPECT_LE(hi, 1.0);
    }
  }
}

class ScoreCli : public ::testing::TestWithParam<const char*> {};

// A real YCB mesh (the shared data's mustard bottle, else its first mesh): its facets are in
// general position. (On a generated capsule, whose facets meet the hand's axis-aligned frames in
// exact ties, the last bits a pose loses through grasps.json's quaternion can move a contact
// patch, so plan's numbers are not reproducible there to 1e-9.)
std::string ycbMesh() {
  const auto meshes = test::sharedFiles("objects/ycb", {".ply"});
  for (const auto& m : meshes) {
    if (m.find("006_mustard_bottle") != std::string::npos) return m;
  }
  return meshes.empty() ? std::string() : meshes.front();
}

TEST_P(ScoreCli, ReproducesPlansNumbersForPlansOwnGrasps) {
  const std::string hand = GetParam();
  const std::string mesh = ycbMesh();
  if (mesh.empty()) GTEST_SKIP() << "no ../shared/data/objects/ycb meshes";
  const std::string dir = test::tempDir("cli_score_" + hand);
  const CliRun plan =
      runCli("plan " + mesh + " --hand " + hand + " --max-grasps 3 --robustness-samples 8 --out " +
                 dir + "/grasps.json",
             dir);
  ASSERT_EQ(plan.exit_code, 0) << plan.err;
  const nlohmann::json grasps = readJsonFile(dir + "/grasps.json");
  ASSERT_FALSE(grasps["grasps"].empty()) << hand;
  const std::string score_args = "score " + dir + "/grasps.json " + mesh + " --hand " + hand +
                                 " --mu 0.35,0.5 --robustness-samples 8 --out ";
  const CliRun run = runCli(score_args + dir + "/scores.json", dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("scored"), std::string::npos) << run.out;
  const nlohmann::json scores = readJsonFile(dir + "/scores.json");
  expectScoresMatchPlan(grasps, scores);
  // The same r as plan's robust ranking: same seed, samples and mu, and every grasp faces the same
  // perturbations (grasp index 0). The pose read back from grasps.json may differ from plan's in
  // the last bits (its rotation is a quaternion), which could flip one sample at most.
  constexpr double kOneSampleOfEight = 1.0 / 8 + 1e-9;
  int compared = 0;
  for (std::size_t i = 0; i < grasps["grasps"].size(); ++i) {
    const auto& planned = grasps["grasps"][i];
    if (!planned.contains("robustness")) continue;
    const auto& scored = scores["grasps"][i]["closure"][0]["robustness"];
    ASSERT_FALSE(scored.is_null());
    EXPECT_NEAR(planned["robustness"]["r"].get<double>(), scored["r"].get<double>(),
                kOneSampleOfEight)
        << hand << " grasp " << i;
    ++compared;
  }
  EXPECT_GT(compared, 0) << "plan scored no grasp for robustness";
  EXPECT_EQ(scores["hand"], hand);
  EXPECT_EQ(scores["parameters"]["mu"], nlohmann::json({0.35, 0.5}));

  // Deterministic for a seed: a second run writes the same scores (times aside).
  const CliRun again = runCli(score_args + dir + "/again.json", dir);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  const nlohmann::json repeat = readJsonFile(dir + "/again.json");
  for (std::size_t i = 0; i < scores["grasps"].size(); ++i) {
    for (std::size_t k = 0; k < 2; ++k) {
      const auto& a = scores["grasps"][i]["closure"][k];
      const auto& b = repeat["grasps"][i]["closure"][k];
      EXPECT_EQ(a["robustness"]["force_closure"], b["robustness"]["force_closure"]);
      EXPECT_EQ(a["epsilon"], b["epsilon"]);
      EXPECT_EQ(a["margin"], b["margin"]);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Hands, ScoreCli, ::testing::Values("armar3", "sdh", "shadow"));

// Without the shared data: a generated capsule, scored at two mu; more friction never loses
// force closure and r stays inside its interval.
TEST(ScoreCliCapsule, TwoFrictionsInOneRun) {
  const std::string dir = test::tempDir("cli_score_capsule");
  saveMesh(dir + "/capsule.ply", geometry::shapes::makeNamedShape("capsule"));
  const CliRun plan = runCli(
      "plan " + dir + "/capsule.ply --hand sdh --max-grasps 3 --out " + dir + "/grasps.json", dir);
  ASSERT_EQ(plan.exit_code, 0) << plan.err;
  const CliRun run =
      runCli("score " + dir + "/grasps.json " + dir +
                 "/capsule.ply --mu 0.35,0.5 --robustness-samples 8 --out " + dir + "/scores.json",
             dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json scores = readJsonFile(dir + "/scores.json");
  ASSERT_FALSE(scores["grasps"].empty());
  for (const auto& s : scores["grasps"]) {
    ASSERT_EQ(s["closure"].size(), 2u);
    if (s["closure"][0]["force_closure"].get<bool>()) {
      EXPECT_TRUE(s["closure"][1]["force_closure"].get<bool>());
    }
    for (const auto& at : s["closure"]) {
      if (at["robustness"].is_null()) continue;
      const double r = at["robustness"]["r"].get<double>();
      EXPECT_LE(at["robustness"]["ci95"][0].get<double>(), r);
      EXPECT_LE(r, at["robustness"]["ci95"][1].get<double>());
    }
  }
}

// Soft-finger contacts (--torsional-friction) on plan and score: plan records the model with r,
// score reproduces plan's numbers with the same option, and soft contacts never hold less than
// point contacts on the same closings (each edge wrench w becomes w + t and w - t, whose hull
// holds w): epsilon and r at least as large, force closure kept. r is compared with the object
// held still (the paper variant), where every sample closes the same way under both models; in
// the settled variant the squeeze differs, so the object may settle along another path.
TEST(ScoreCliYcb, SoftFingerContactsOnPlanAndScore) {
  const std::string mesh = ycbMesh();
  if (mesh.empty()) GTEST_SKIP() << "no ../shared/data/objects/ycb meshes";
  const std::string dir = test::tempDir("cli_score_soft");
  const std::string torsion = " --torsional-friction 0.0023";
  const CliRun plan = runCli("plan " + mesh + " --hand sdh --max-grasps 3 --robustness-samples 8" +
                                 torsion + " --out " + dir + "/grasps.json",
                             dir);
  ASSERT_EQ(plan.exit_code, 0) << plan.err;
  const nlohmann::json grasps = readJsonFile(dir + "/grasps.json");
  ASSERT_FALSE(grasps["grasps"].empty());
  const std::string score = "score " + dir + "/grasps.json " + mesh +
                            " --hand sdh --mu 0.35,0.5 --robustness-samples 8 --out " + dir;
  const CliRun soft = runCli(score + "/soft.json" + torsion, dir);
  ASSERT_EQ(soft.exit_code, 0) << soft.err;
  const std::string held_still = " --robustness-variant paper";
  const CliRun soft_held = runCli(score + "/soft_held.json" + torsion + held_still, dir);
  ASSERT_EQ(soft_held.exit_code, 0) << soft_held.err;
  const CliRun point = runCli(score + "/point.json" + held_still, dir);
  ASSERT_EQ(point.exit_code, 0) << point.err;
  const nlohmann::json soft_scores = readJsonFile(dir + "/soft.json");
  const nlohmann::json soft_held_scores = readJsonFile(dir + "/soft_held.json");
  const nlohmann::json point_scores = readJsonFile(dir + "/point.json");
  EXPECT_DOUBLE_EQ(soft_scores["parameters"]["torsional_friction_m"].get<double>(), 0.0023);
  EXPECT_DOUBLE_EQ(point_scores["parameters"]["torsional_friction_m"].get<double>(), 0.0);
  expectScoresMatchPlan(grasps, soft_scores);
  constexpr double kOneSampleOfEight = 1.0 / 8 + 1e-9;
  for (std::size_t i = 0; i < grasps["grasps"].size(); ++i) {
    SCOPED_TRACE(::testing::Message() << "grasp " << i);
    const auto& planned = grasps["grasps"][i];
    const auto& s = soft_scores["grasps"][i]["closure"][0];
    const auto& held = soft_held_scores["grasps"][i]["closure"][0];
    const auto& p = point_scores["grasps"][i]["closure"][0];
    if (planned.contains("robustness")) {
      EXPECT_DOUBLE_EQ(planned["robustness"]["torsional_friction_m"].get<double>(), 0.0023);
      EXPECT_NEAR(planned["robustness"]["r"].get<double>(), s["robustness"]["r"].get<double>(),
                  kOneSampleOfEight);
    }
    if (p["force_closure"].get<bool>()) EXPECT_TRUE(s["force_closure"].get<bool>());
    const double point_epsilon = p["epsilon"].get<double>();
    EXPECT_GE(s["epsilon"].get<double>(), point_epsilon * (1 - 1e-7) - 1e-12);
    EXPECT_GE(held["robustness"]["r"].get<double>(), p["robustness"]["r"].get<double>());
  }
}

// Plan's grasps relabelled as one object of a two-object run file: --object picks them.
TEST(ScoreCliYcb, RunFileWithSeveralObjects) {
  const std::string mesh = ycbMesh();
  if (mesh.empty()) GTEST_SKIP() << "no ../shared/data/objects/ycb meshes";
  const std::string dir = test::tempDir("cli_score_run");
  const CliRun plan =
      runCli("plan " + mesh + " --hand sdh --max-grasps 2 --out " + dir + "/grasps.json", dir);
  ASSERT_EQ(plan.exit_code, 0) << plan.err;
  const nlohmann::json grasps = readJsonFile(dir + "/grasps.json");
  if (grasps["grasps"].empty()) GTEST_SKIP() << mesh << ": plan found no grasp";
  nlohmann::json run = grasps;
  run["schema"] = "skelgrasp.run/2";
  run["objects"] = {{{"id", 0}}, {{"id", 4}}};
  for (auto& g : run["grasps"]) g["object"] = 4;
  writeJsonFile(dir + "/run.json", run);
  const CliRun scored = runCli("score " + dir + "/run.json " + mesh + " --object 4 --mu 0.35,0.5 " +
                                   "--robustness-samples 6 --out " + dir + "/scores.json",
                               dir);  // the hand comes from the file
  ASSERT_EQ(scored.exit_code, 0) << scored.err;
  expectScoresMatchPlan(grasps, readJsonFile(dir + "/scores.json"));
}

TEST(ScoreCliErrors, BadInputIsOneLineAndExitTwoAndWritesNothing) {
  const std::string dir = test::tempDir("cli_score_bad");
  saveMesh(dir + "/capsule.ply", geometry::shapes::makeNamedShape("capsule"));
  const std::string pose =
      R"("hand_pose": {"position": [0, 0, 0.2], "quaternion_wxyz": [1, 0, 0, 0]})";
  std::ofstream(dir + "/broken.json") << "{\"schema\": \"skelgrasp.grasps/1\", \"grasps\": [";
  std::ofstream(dir + "/foreign.json") << R"({"schema": "other.tool/1", "grasps": []})";
  std::ofstream(dir + "/nopose.json")
      << R"({"schema": "skelgrasp.grasps/1", "hand": "sdh", "grasps": [{"id": 0}]})";
  std::ofstream(dir + "/tworun.json")
      << R"({"schema": "skelgrasp.run/2", "hand": "sdh", "objects": [{"id": 0}, {"id": 1}],
           "grasps": [{"id": 0, "object": 1, )"
      << pose << "}]}";
  std::ofstream(dir + "/good.json")
      << R"({"schema": "skelgrasp.grasps/1", "hand": "sdh", "grasps": [{"id": 0, )" << pose
      << "}]}";
  const std::string mesh = " " + dir + "/capsule.ply";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"score " + dir + "/missing.json" + mesh + " --hand sdh", "missing.json"},
      {"score " + dir + "/broken.json" + mesh + " --hand sdh", "broken.json: not valid JSON"},
      {"score " + dir + "/foreign.json" + mesh + " --hand sdh", "schema"},
      {"score " + dir + "/nopose.json" + mesh, "grasp 0 has no \"hand_pose\""},
      {"score " + dir + "/tworun.json" + mesh, "choose one"},
      {"score " + dir + "/tworun.json" + mesh + " --object 7", "no object 7"},
      {"score " + dir + "/good.json" + mesh + " --hand nohand", "nohand"},
      {"score " + dir + "/good.json" + mesh + " --hand armar3", "planned with hand"},
      {"score " + dir + "/good.json " + dir + "/missing.ply", "missing.ply"},
      {"score " + dir + "/good.json" + mesh + " --mu 0.35,-1", "--mu"},
      {"score " + dir + "/good.json" + mesh + " --robustness-samples 0", "--robustness-samples"},
  };
  for (const auto& [args, expected] : cases) {
    const CliRun run = runCli(args + " --out " + dir + "/out.json", dir);
    EXPECT_EQ(run.exit_code, 2) << args;
    EXPECT_EQ(countLines(run.err), 1) << args << ": " << run.err;
    EXPECT_NE(run.err.find("skelgrasp: error: "), std::string::npos) << args << ": " << run.err;
    EXPECT_NE(run.err.find(expected), std::string::npos) << args << ": " << run.err;
    EXPECT_FALSE(std::filesystem::exists(dir + "/out.json")) << args;
  }
  // The good file scores: a hand placed above the capsule, whatever it reaches.
  const CliRun good = runCli(
      "score " + dir + "/good.json" + mesh + " --no-robustness --out " + dir + "/out.json", dir);
  EXPECT_EQ(good.exit_code, 0) << good.err;
  EXPECT_TRUE(std::filesystem::exists(dir + "/out.json"));
}

}  // namespace
}  // namespace skelgrasp
