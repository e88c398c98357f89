// skelgrasp evaluate / merge as a batch system sees them: locks, changed options, kills.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

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

// Few samples and a fixed hypothesis budget keep a run short and independent of machine speed.
const char* const kFastOptions =
    " --hands sdh --robustness-samples 4 --robustness-grasps 2 --timeout 0 --vertex-distance 0.01";

std::vector<nlohmann::json> jsonLines(const std::string& path) {
  std::vector<nlohmann::json> out;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) out.push_back(nlohmann::json::parse(line));
  }
  return out;
}

// A folder with the named shapes as PLY meshes.
std::string objectsDir(const std::string& dir, const std::vector<std::string>& shapes) {
  const std::string objects = dir + "/objects";
  std::filesystem::create_directories(objects);
  for (const auto& shape : shapes) {
    saveMesh(objects + "/" + shape + ".ply", geometry::shapes::makeNamedShape(shape));
  }
  return objects;
}

TEST(EvaluateCli, ASecondProcessOnALockedOutputExitsTwo) {
  const std::string dir = test::tempDir("cli_eval_locked");
  const std::string objects = objectsDir(dir, {"capsule"}), out = dir + "/out";
  std::filesystem::create_directories(out);
  // This test process holds the lock as a first, still running evaluate would.
  const int fd = ::open((out + "/.lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  const std::string pid = std::to_string(::getpid());
  ASSERT_EQ(::write(fd, pid.data(), pid.size()), static_cast<ssize_t>(pid.size()));
  const std::string args = "evaluate --objects " + objects + " --out " + out + kFastOptions;
  CliRun run = runCli(args, dir);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(countLines(run.err), 1) << run.err;
  EXPECT_EQ(run.err, "skelgrasp: error: " + out + ": is in use by process " + pid + "\n");
  EXPECT_FALSE(std::filesystem::exists(out + "/runs.jsonl"));
  // merge refuses to read a shard that is still being written.
  std::ofstream(out + "/runs.jsonl");
  run = runCli("merge " + out + " --out " + dir + "/merged", dir);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("is in use by process " + pid), std::string::npos) << run.err;
  std::filesystem::remove(out + "/runs.jsonl");
  ::close(fd);
  run = runCli(args, dir);
  EXPECT_EQ(run.exit_code, 0) << run.err;
}

TEST(EvaluateCli, AResumeWithAnotherMuRefusesInOneLineAndRestartStartsAfresh) {
  const std::string dir = test::tempDir("cli_eval_mu");
  const std::string objects = objectsDir(dir, {"capsule"}), out = dir + "/out";
  const std::string args = "evaluate --objects " + objects + " --out " + out + kFastOptions;
  ASSERT_EQ(runCli(args, dir).exit_code, 0);
  const auto before = jsonLines(out + "/runs.jsonl");
  CliRun run = runCli(args + " --mu 0.5", dir);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(countLines(run.err), 1) << run.err;
  EXPECT_EQ(run.err.rfind("skelgrasp: error: " + out + ": ", 0), 0u) << run.err;
  EXPECT_NE(run.err.find("mu 0.35 -> 0.5"), std::string::npos) << run.err;
  EXPECT_EQ(jsonLines(out + "/runs.jsonl"), before);
  run = runCli(args + " --mu 0.5 --restart", dir);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("evaluated 1 object(s) (0 already done"), std::string::npos) << run.out;
  EXPECT_EQ(readJsonFile(out + "/batch.json")["options"]["mu"], 0.5);
}

// Killed with SIGKILL in the middle of a batch, evaluate resumes to exactly the results of an
// uninterrupted batch.
// The robust ranking's screening (how many grasps, how many samples each) and the wrench volume
// reach the batch and are among its recorded options; the kept grasps then carry a volume.
TEST(EvaluateCli, RecordsTheScreeningSamplesOfTheRobustRanking) {
  const std::string dir = test::tempDir("cli_eval_screen");
  const std::string objects = objectsDir(dir, {"capsule"}), out = dir + "/out";
  const CliRun run = runCli("evaluate --objects " + objects + " --out " + out + kFastOptions +
                                " --robust-ranking --robustness-screen 12"
                                " --robustness-screen-samples 3 --wrench-volume",
                            dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto batch = readJsonFile(out + "/batch.json");
  EXPECT_EQ(batch["options"]["ranking"]["screen_k"], 12) << batch.dump();
  EXPECT_EQ(batch["options"]["ranking"]["screen_samples"], 3) << batch.dump();
  EXPECT_EQ(batch["options"]["quality"]["compute_volume"], true) << batch.dump();
  const auto grasps = jsonLines(out + "/results.jsonl");
  ASSERT_FALSE(grasps.empty());
  for (const auto& g : grasps) EXPECT_GT(g["volume"].get<double>(), 0) << g.dump();
}

// --judge physics: each run's first grasps are executed by the physics judge; the run records
// judged, held and the failed ones by phase (adding up), its grasps whether they held, the
// summary a table of it; a resume without the judge is refused (other results).
TEST(EvaluateCli, ThePhysicsJudgeExecutesEachRunsFirstGrasps) {
  const std::string dir = test::tempDir("cli_eval_physics");
  const std::string objects = objectsDir(dir, {"box"}), out = dir + "/out";
  const std::string options =
      " --hands parallel_gripper --planners skeleton"
      " --robustness-samples 2 --robustness-grasps 1 --timeout 0"
      " --vertex-distance 0.01 --physics-grasps 2";
  const CliRun run =
      runCli("evaluate --objects " + objects + " --out " + out + options + " --judge physics", dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto batch = readJsonFile(out + "/batch.json");
  EXPECT_EQ(batch["options"]["physics"]["grasps"], 2) << batch.dump();
  const auto runs = jsonLines(out + "/runs.jsonl");
  ASSERT_EQ(runs.size(), 1u);
  ASSERT_TRUE(runs[0].contains("physics")) << runs[0].dump();
  const auto& physics = runs[0]["physics"];
  const std::size_t kept = runs[0]["kept"];
  ASSERT_GT(kept, 0u);
  EXPECT_EQ(physics["judged"].get<std::size_t>(), std::min<std::size_t>(kept, 2));
  const auto& failed = physics["failed"];
  EXPECT_EQ(physics["holds"].get<std::size_t>() + failed["start"].get<std::size_t>() +
                failed["closing"].get<std::size_t>() + failed["disturbance"].get<std::size_t>(),
            physics["judged"].get<std::size_t>());
  EXPECT_GT(physics["cpu_s"].get<double>(), 0.0);
  std::size_t judged = 0, held = 0;
  for (const auto& g : jsonLines(out + "/results.jsonl")) {
    if (!g.contains("physics_holds")) continue;
    ++judged;
    held += g["physics_holds"].get<bool>();
    EXPECT_LT(g["grasp"].get<int>(), 2) << g.dump();  // the run's first grasps
  }
  EXPECT_EQ(judged, physics["judged"].get<std::size_t>());
  EXPECT_EQ(held, physics["holds"].get<std::size_t>());
  std::ifstream summary(out + "/summary.md");
  const std::string md{std::istreambuf_iterator<char>(summary), {}};
  EXPECT_NE(md.find("## Physics judge"), std::string::npos) << md;
  const CliRun resume = runCli("evaluate --objects " + objects + " --out " + out + options, dir);
  EXPECT_EQ(resume.exit_code, 2) << resume.err;
  EXPECT_NE(resume.err.find("physics"), std::string::npos) << resume.err;
}

// Left unset, the screening and the search run with each hand's ranking budget; batch.json records
// the defaults and, for a hand with its own budget, that budget, so that a batch from before the
// hands had budgets resumes only for the hands whose budget did not change.
TEST(EvaluateCli, RecordsEachHandsOwnRankingBudget) {
  const std::string dir = test::tempDir("cli_eval_budget");
  const std::string objects = objectsDir(dir, {"capsule"}), out = dir + "/out";
  const std::string args = "evaluate --objects " + objects + " --out " + out +
                           " --hands sdh,shadow --robustness-samples 4 --robustness-grasps 2"
                           " --timeout 0 --vertex-distance 0.01 --robust-ranking";
  const CliRun run = runCli(args, dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto ranking = readJsonFile(out + "/batch.json")["options"]["ranking"];
  EXPECT_EQ(ranking["screen_k"], 60) << ranking.dump();
  EXPECT_EQ(ranking["screen_samples"], 10) << ranking.dump();
  EXPECT_DOUBLE_EQ(ranking["refinement"]["search_below_r"].get<double>(), 0.7);
  ASSERT_TRUE(ranking.contains("hand_budgets")) << ranking.dump();
  // The SDH's own budget differs in its screening order (by finger travel) and its r bar, so that
  // is all it records besides the three fields every hand budget records.
  EXPECT_EQ(ranking["hand_budgets"]["sdh"]["screen_by"], "travel") << ranking.dump();
  EXPECT_EQ(ranking["hand_budgets"]["sdh"]["screen_k"], 60) << ranking.dump();
  EXPECT_DOUBLE_EQ(ranking["hand_budgets"]["sdh"]["search_below_r"].get<double>(), 0.5);
  EXPECT_FALSE(ranking["hand_budgets"]["sdh"].contains("confirm_samples")) << ranking.dump();
  EXPECT_EQ(ranking["hand_budgets"]["shadow"]["screen_k"], 40) << ranking.dump();
  EXPECT_EQ(ranking["hand_budgets"]["shadow"]["screen_samples"], 8) << ranking.dump();
  EXPECT_DOUBLE_EQ(ranking["hand_budgets"]["shadow"]["search_below_r"].get<double>(), 0.5);
  // Screening: each preshape's best in turn by default, the best by epsilon for the Shadow hand.
  EXPECT_EQ(ranking["screen_by"], "preshapes") << ranking.dump();
  EXPECT_EQ(ranking["hand_budgets"]["shadow"]["screen_by"], "epsilon") << ranking.dump();
  std::ifstream summary_file(out + "/summary.md");
  const std::string summary((std::istreambuf_iterator<char>(summary_file)), {});
  EXPECT_NE(summary.find("shadow's own ranking budget: 40 screened with 8 samples, the best by "
                         "epsilon, no confirmation, refined below r = 0.5"),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find("with 10 samples, the best 20 of them confirmed with 10 more, the best 10 "
                         "scored with 50"),
            std::string::npos)
      << summary;
  EXPECT_EQ(ranking["confirm_samples"], 10) << ranking.dump();
  EXPECT_EQ(ranking["hand_budgets"]["shadow"]["confirm_samples"], 0) << ranking.dump();
  EXPECT_NE(summary.find("sdh's own ranking budget: 60 screened with 10 samples, each preshape's "
                         "best by finger travel in turn, refined below r = 0.5"),
            std::string::npos)
      << summary;
  // A batch from before the hands had budgets (no hand_budgets) ranked the Shadow hand with the
  // defaults: it does not resume into this one. The batch as written resumes.
  auto batch = readJsonFile(out + "/batch.json");
  const auto written = batch;
  batch["options"]["ranking"].erase("hand_budgets");
  std::ofstream(out + "/batch.json") << batch.dump(2);
  CliRun resumed = runCli(args, dir);
  EXPECT_EQ(resumed.exit_code, 2) << resumed.err;
  EXPECT_NE(resumed.err.find("hand_budgets.shadow"), std::string::npos) << resumed.err;
  std::ofstream(out + "/batch.json") << written.dump(2);
  resumed = runCli(args, dir);
  EXPECT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find("already done"), std::string::npos) << resumed.out;
  // A batch from before a ranking option was recorded (`forget` takes its record out of the
  // ranking's options) does not resume into the default, the refusal naming `key`, and resumes
  // with `old_ranking`, the option that gives the ranking it was started with.
  const auto expectOldBatchResumesOnlyWith = [&](const auto& forget, const std::string& key,
                                                 const std::string& old_ranking) {
    auto old = written;
    forget(old["options"]["ranking"]);
    std::ofstream(out + "/batch.json") << old.dump(2);
    CliRun again = runCli(args, dir);
    EXPECT_EQ(again.exit_code, 2) << again.err;
    EXPECT_NE(again.err.find(key), std::string::npos) << again.err;
    again = runCli(args + " " + old_ranking, dir);
    EXPECT_EQ(again.exit_code, 0) << again.err;
    EXPECT_NE(again.out.find("already done"), std::string::npos) << again.out;
  };
  // Before screening took the preshapes in turn (no screen_by anywhere) it screened by epsilon.
  // (The SDH's r bar stays: a batch from before the SDH had a budget of its own searched below
  // r = 0.7, which no single option gives both it and the Shadow hand today.)
  expectOldBatchResumesOnlyWith(
      [](nlohmann::json& ranking) {
        ranking.erase("screen_by");
        ranking["hand_budgets"]["shadow"].erase("screen_by");
        ranking["hand_budgets"]["sdh"].erase("screen_by");
      },
      "screen_by", "--robustness-screen-by epsilon");
  // A batch whose record names no confirmation (no confirm_samples anywhere, as before the
  // screening's contenders were confirmed) confirmed nothing.
  expectOldBatchResumesOnlyWith(
      [](nlohmann::json& ranking) {
        ranking.erase("confirm_samples");
        ranking["hand_budgets"]["shadow"].erase("confirm_samples");
      },
      "confirm_samples", "--robustness-confirm-samples 0");
}

TEST(EvaluateCli, ABatchKilledMidwayResumesToTheUninterruptedResults) {
  const std::string dir = test::tempDir("cli_eval_kill");
  const std::string objects = objectsDir(dir, {"capsule", "bottle", "hammer", "mug"});
  const std::string all = dir + "/all", out = dir + "/out";
  ASSERT_EQ(runCli("evaluate --objects " + objects + " --out " + all + kFastOptions, dir).exit_code,
            0);
  const std::string command = std::string(SKELGRASP_CLI_PATH) + " evaluate --objects " + objects +
                              " --out " + out + kFastOptions + " > " + dir +
                              "/bg.log 2>&1 & echo $! > " + dir + "/pid";
  ASSERT_EQ(std::system(command.c_str()), 0);
  pid_t pid = 0;
  std::ifstream(dir + "/pid") >> pid;
  ASSERT_GT(pid, 0);
  // Kill it once the first object is on disk (or it finished: then nothing is left to resume).
  // The waits are bounded so a stuck process cannot hang the test; they assert nothing.
  const int kPolls = 30000, kPollMicroseconds = 20000;
  auto nothingWritten = [&] {
    std::error_code ec;
    return std::filesystem::file_size(out + "/runs.jsonl", ec) == 0 || ec;
  };
  for (int i = 0; i < kPolls && ::kill(pid, 0) == 0 && nothingWritten(); ++i)
    ::usleep(kPollMicroseconds);
  ::kill(pid, SIGKILL);
  for (int i = 0; i < kPolls && ::kill(pid, 0) == 0; ++i) ::usleep(kPollMicroseconds);
  const CliRun run = runCli("evaluate --objects " + objects + " --out " + out + kFastOptions, dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const char* file : {"/runs.jsonl", "/results.jsonl"}) {
    auto a = jsonLines(all + file), b = jsonLines(out + file);
    ASSERT_EQ(a.size(), b.size()) << file;
    for (std::size_t i = 0; i < a.size(); ++i) {
      for (auto* j : {&a[i], &b[i]}) {
        for (const char* key : {"planning_s", "regularise_s", "skeleton_s", "robustness_s",
                                "ms_per_valid_grasp", "time_ms", "timed_out"})
          j->erase(key);
      }
      EXPECT_EQ(a[i], b[i]) << file << " line " << i;
    }
  }
}

}  // namespace
}  // namespace skelgrasp
