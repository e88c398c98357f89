// Grasps files and the work asked of them (issue 77): `score`, `simulate` and `export` refuse a
// file of more grasps than kMaxGraspsPerFile, and `score` and `simulate` a request of more
// closings or executions than their per-command limit, before any work: exit 2, one line naming
// the file and the limit, nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_support.h"
#include "hostile_files.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/evaluation/score.h"
#include "skelgrasp/evaluation/simulate.h"
#include "skelgrasp/grasping/io/grasps_file.h"
#include "skelgrasp/ranking/limits.h"
#include "test_support.h"

namespace skelgrasp {
namespace {

namespace fs = std::filesystem;
using test::BadCliInput;
using test::CliRun;
using test::countLines;
using test::lastLine;
using test::runCli;
using test::withDir;

// The valid grasp `copies` times.
nlohmann::json copiesOfValidGrasp(std::size_t copies) {
  nlohmann::json file = test::validGrasps();
  const nlohmann::json grasp = file["grasps"][0];
  file["grasps"] = nlohmann::json::array();
  for (std::size_t i = 0; i < copies; ++i) {
    file["grasps"].push_back(grasp);
    file["grasps"].back()["id"] = i;
  }
  return file;
}

// One grasp more than a file may hold, written as text: `{}` each, so that the count is refused
// before any grasp is read.
void writeTooManyGrasps(const std::string& path) {
  std::string text = R"({"schema": "skelgrasp.grasps/3", "hand": "sdh", "object": "o.ply", )"
                     R"("grasps": [)";
  text.reserve(text.size() + 3 * (grasping::kMaxGraspsPerFile + 1) + 4);
  for (std::size_t i = 0; i <= grasping::kMaxGraspsPerFile; ++i) text += i == 0 ? "{}" : ",{}";
  test::writeText(path, text + "]}");
}

void writeGraspsLimitFiles(const std::string& dir) {
  // 101 grasps at 100000 samples and one friction: 101 x (1 + 100000) closings.
  static_assert(101 * (1 + 100'000ull) > ranking::kMaxScoreClosings);
  writeJsonFile(dir + "/g101.json", copiesOfValidGrasp(101));
  // 11 grasps at one friction and 10000 samples: 11 x (1 + 10000) executions.
  static_assert(11 * (1 + 10'000ull) > evaluation::kMaxSimulatedExecutions);
  writeJsonFile(dir + "/g11.json", copiesOfValidGrasp(11));
  writeTooManyGrasps(dir + "/too_many.json");
}

class GraspsLimitsCli : public ::testing::TestWithParam<BadCliInput> {};

// The mesh argument names no file: the request is refused before the mesh is read.
TEST_P(GraspsLimitsCli, RefusedBeforeAnyWork) {
  const auto& c = GetParam();
  const std::string dir = test::tempDir("cli_grasps_limits_" + c.name);
  writeGraspsLimitFiles(dir);
  for (const std::string quiet : {"", "-q "}) {
    const CliRun r = runCli(quiet + withDir(c.args, dir), dir);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    const std::string line = lastLine(r.err);
    EXPECT_EQ(line.rfind("skelgrasp: error: ", 0), 0u) << r.err;
    EXPECT_NE(line.find(c.expected), std::string::npos) << r.err;
    if (!quiet.empty()) EXPECT_EQ(countLines(r.err), 1) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      EXPECT_NE(name.rfind("out", 0), 0u) << "output written: " << name;
      EXPECT_EQ(name.find(".tmp."), std::string::npos) << "temporary left: " << name;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, GraspsLimitsCli,
    ::testing::Values(
        BadCliInput{"score_too_many_closings",
                    "score {dir}/g101.json {dir}/absent.ply --robustness-samples 100000 "
                    "--out {dir}/out.json",
                    "g101.json: scoring 101 grasps at 1 friction(s) x 100000 robustness samples "
                    "is 10100101 hand closings, more than the limit of 10000000 per command"},
        BadCliInput{"score_too_many_closings_at_two_frictions",
                    "score {dir}/g101.json {dir}/absent.ply --mu 0.3,0.5 "
                    "--robustness-samples 50000 --out {dir}/out.json",
                    "g101.json: scoring 101 grasps at 2 friction(s) x 50000 robustness samples is "
                    "10100101 hand closings"},
        BadCliInput{"simulate_too_many_executions",
                    "simulate {dir}/g11.json {dir}/absent.ply --samples 10000 "
                    "--out {dir}/out.json",
                    "g11.json: simulating 11 grasps at 1 friction(s) x (1 + 10000 samples) is "
                    "110011 executions, more than the limit of 100000 per command"},
        BadCliInput{"score_too_many_grasps",
                    "score {dir}/too_many.json {dir}/absent.ply --out {dir}/out.json",
                    "too_many.json: grasps file holds 1000001 grasps, more than the 1000000"},
        BadCliInput{"simulate_too_many_grasps",
                    "simulate {dir}/too_many.json {dir}/absent.ply --out {dir}/out.json",
                    "too_many.json: grasps file holds 1000001 grasps, more than the 1000000"},
        BadCliInput{"export_too_many_grasps",
                    "export {dir}/too_many.json --format moveit --out {dir}/out.yaml",
                    "too_many.json: grasps file holds 1000001 grasps, more than the 1000000"}),
    [](const auto& info) { return info.param.name; });

// The limit counts the grasps left after --max-grasps: 1 x (1 + 10000) executions are within it,
// so the command goes on to read the mesh (absent here, which ends it).
TEST(GraspsLimitsCli, MaxGraspsBringsASimulationWithinTheLimit) {
  const std::string dir = test::tempDir("cli_grasps_limits_max_grasps");
  writeGraspsLimitFiles(dir);
  const CliRun within =
      runCli("simulate " + dir + "/g11.json " + dir +
                 "/absent.ply --samples 10000 --max-grasps 1 --out " + dir + "/out.json",
             dir);
  EXPECT_EQ(within.exit_code, 2) << within.err;
  EXPECT_NE(lastLine(within.err).find("absent.ply"), std::string::npos) << within.err;
  EXPECT_EQ(lastLine(within.err).find("executions"), std::string::npos) << within.err;
}

// The library refuses the same requests (the Python module's score_grasps and simulate).
TEST(GraspsLimits, LibraryCountsAndRefusesTheWork) {
  evaluation::ScoreParams score;
  score.robustness.samples = 100;
  score.frictions = {0.3, 0.5};
  EXPECT_EQ(evaluation::scoreClosings(10, score), 10u * (1 + 2 * 100));
  score.compute_robustness = false;
  EXPECT_EQ(evaluation::scoreClosings(10, score), 10u);
  EXPECT_NO_THROW(evaluation::checkScoreWork(ranking::kMaxScoreClosings, score));
  EXPECT_THROW(evaluation::checkScoreWork(ranking::kMaxScoreClosings + 1, score), InvalidArgument);
  evaluation::SimulateParams simulate;
  simulate.samples = 9;
  EXPECT_EQ(evaluation::simulatedExecutions(7, simulate), 7u * 10);
  EXPECT_NO_THROW(
      evaluation::checkSimulationWork(evaluation::kMaxSimulatedExecutions / 10, simulate));
  EXPECT_THROW(
      evaluation::checkSimulationWork(evaluation::kMaxSimulatedExecutions / 10 + 1, simulate),
      InvalidArgument);
}

// The nesting limit of JSON files is counted before parsing, brackets in strings aside: a file of
// a million grasps is read in about a second (the parser's own depth callback took minutes).
TEST(GraspsLimits, JsonNestingIsCountedOutsideStrings) {
  const std::string dir = test::tempDir("json_nesting");
  test::writeText(dir + "/64.json", std::string(64, '[') + std::string(64, ']'));
  test::writeText(dir + "/65.json", std::string(65, '[') + std::string(65, ']'));
  EXPECT_NO_THROW(readJsonFile(dir + "/64.json"));
  EXPECT_THROW(readJsonFile(dir + "/65.json"), IoError);
  // Brackets and an escaped quote inside a string, then a list of 100 empty strings.
  std::string quotes;
  for (int i = 0; i < 100; ++i) quotes += i == 0 ? R"("")" : R"(,"")";
  test::writeText(dir + "/strings.json", R"({"a": "[[[[\"{{{{", "b": [)" + quotes + "]}");
  const nlohmann::json strings = readJsonFile(dir + "/strings.json");
  EXPECT_EQ(strings["a"], "[[[[\"{{{{");
  EXPECT_EQ(strings["b"].size(), 100u);
}

}  // namespace
}  // namespace skelgrasp
