// `--help` fits a screen (the detailed options are left to `--help-all`), and --ranking-budget
// sets the robust ranking's counts together: `default` is the plan without the option, a detailed
// option given overrides its preset's value.
#include <gtest/gtest.h>

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

constexpr int kMaxHelpLines = 40;

TEST(CliHelp, HelpFitsAScreenAndHelpAllShowsEveryOption) {
  const std::string dir = test::tempDir("cli_help_lines");
  for (const char* command : {"plan", "run", "demo", "evaluate", "score"}) {
    const CliRun help = runCli(std::string(command) + " --help", dir);
    ASSERT_EQ(help.exit_code, 0) << command << ": " << help.err;
    EXPECT_LE(countLines(help.out), kMaxHelpLines) << command << ":\n" << help.out;
    EXPECT_NE(help.out.find("--help-all"), std::string::npos) << command;
  }
  const CliRun help = runCli("plan --help", dir);
  const CliRun all = runCli("plan --help-all", dir);
  ASSERT_EQ(all.exit_code, 0) << all.err;
  EXPECT_GT(countLines(all.out), countLines(help.out));
  // Detailed options: only in --help-all; the groups they are in are named by --help.
  for (const char* hidden : {"--robust-refine-mean-shift", "--robustness-screen-samples",
                             "--closing", "--spur-factor"}) {
    EXPECT_EQ(help.out.find(hidden), std::string::npos) << hidden;
    EXPECT_NE(all.out.find(hidden), std::string::npos) << hidden;
  }
  EXPECT_NE(help.out.find("Ranking details"), std::string::npos) << help.out;
  // The common options stay in --help.
  for (const char* shown : {"--hand", "--out", "--ranking-budget", "--no-robustness", "--mu"}) {
    EXPECT_NE(help.out.find(shown), std::string::npos) << shown;
  }
}

bool endsWith(const std::string& text, const std::string& end) {
  return text.size() >= end.size() && text.compare(text.size() - end.size(), end.size(), end) == 0;
}

// The document without its wall-clock times (keys ending in "_s" or "_ms", and the time per
// valid grasp).
nlohmann::json withoutTimes(nlohmann::json j) {
  if (j.is_object()) {
    nlohmann::json out = nlohmann::json::object();
    for (auto it = j.begin(); it != j.end(); ++it) {
      const std::string& key = it.key();
      if (endsWith(key, "_s") || endsWith(key, "_ms") || key == "ms_per_valid_grasp") continue;
      out[key] = withoutTimes(it.value());
    }
    return out;
  }
  if (j.is_array()) {
    for (auto& item : j) item = withoutTimes(item);
  }
  return j;
}

TEST(CliHelp, RankingBudgetPresetsSetTheRankingsCounts) {
  const std::string dir = test::tempDir("cli_ranking_budget");
  saveMesh(dir + "/box.ply", geometry::shapes::makeBox({0.05, 0.09, 0.16}, 2));
  const auto plan = [&](const std::string& name, const std::string& options) {
    const std::string out = dir + "/" + name + ".json";
    const CliRun r = runCli("plan " + dir +
                                "/box.ply --hand parallel_gripper --planner surface "
                                "--hypotheses 20 --out " +
                                out + " " + options,
                            dir);
    EXPECT_EQ(r.exit_code, 0) << options << ": " << r.err;
    return readJsonFile(out);
  };
  const auto none = plan("none", "");
  const auto by_default = plan("default", "--ranking-budget default");
  const auto small = plan("small", "--ranking-budget small");
  const auto overridden = plan("overridden", "--ranking-budget small --robustness-screen 60");
  EXPECT_EQ(withoutTimes(by_default), withoutTimes(none));
  const auto& budget = small["ranking"]["budget"];
  EXPECT_NE(budget, none["ranking"]["budget"]);
  EXPECT_EQ(budget["screen_grasps"], 30);
  EXPECT_EQ(budget["screen_samples"], 5);
  EXPECT_EQ(budget["confirm_samples"], 0);
  EXPECT_EQ(none["ranking"]["budget"]["screen_grasps"], 60);
  // A detailed option given overrides its preset's value, and only that one.
  EXPECT_EQ(overridden["ranking"]["budget"]["screen_grasps"], 60);
  EXPECT_EQ(overridden["ranking"]["budget"]["screen_samples"], 5);
}

TEST(CliHelp, UnknownRankingBudgetExitsTwoWithOneLine) {
  const std::string dir = test::tempDir("cli_ranking_budget_unknown");
  const CliRun r = runCli("plan box.ply --ranking-budget huge", dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(countLines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("skelgrasp: error: --ranking-budget: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("huge"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

}  // namespace
}  // namespace skelgrasp
