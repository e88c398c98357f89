// The skelgrasp executable: exit codes and error lines for bad input, outputs for good input.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/common/primitives.h"
#include "test_support.h"

namespace skelgrasp {
namespace {

struct CliRun {
  int exit_code;
  std::string out;
  std::string err;
};

CliRun runCli(const std::string& args, const std::string& dir) {
  const std::string out = dir + "/stdout.txt", err = dir + "/stderr.txt";
  const std::string cmd = std::string(SKELGRASP_CLI_PATH) + " " + args + " > " + out + " 2> " + err;
  const int status = std::system(cmd.c_str());
  auto slurp = [](const std::string& p) {
    std::ifstream in(p);
    return std::string((std::istreambuf_iterator<char>(in)), {});
  };
  return {WEXITSTATUS(status), slurp(out), slurp(err)};
}

int countLines(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

TEST(Cli, SkeletonWritesOutputsAndOneSummaryLine) {
  const std::string dir = test::tempDir("cli_ok");
  saveMesh(dir + "/capsule.ply", primitives::makeNamedShape("capsule"));
  const CliRun run = runCli("skeleton " + dir + "/capsule.ply --out " + dir + "/out", dir);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(countLines(run.out), 1);
  EXPECT_NE(run.out.find("2 endpoint"), std::string::npos) << run.out;
  const auto j = readJsonFile(dir + "/out/skeleton.json");
  EXPECT_EQ(j["summary"]["endpoint"], 2);
  EXPECT_GT(loadMesh(dir + "/out/segmentation.ply").numVertices(), 0u);
}

struct BadCliInput {
  std::string name;
  std::string file;
  std::string content;
  std::string expected;
};

class CliBadInput : public ::testing::TestWithParam<BadCliInput> {};

TEST_P(CliBadInput, ExitsTwoWithOneErrorLineNamingTheFile) {
  const auto& c = GetParam();
  const std::string dir = test::tempDir("cli_bad_" + c.name);
  const std::string path = dir + "/" + c.file;
  if (c.name != "missing") std::ofstream(path) << c.content;
  const CliRun run = runCli("skeleton " + path + " --out " + dir + "/out", dir);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(countLines(run.err), 1) << run.err;
  EXPECT_NE(run.err.find("error"), std::string::npos);
  EXPECT_NE(run.err.find(path), std::string::npos) << run.err;
  EXPECT_NE(run.err.find(c.expected), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out/skeleton.json"));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, CliBadInput,
    ::testing::Values(BadCliInput{"missing", "none.ply", "", "no such file"},
                      BadCliInput{"unknown_format", "mesh.abc", "x", "unknown mesh format"},
                      BadCliInput{"empty_mesh", "empty.off", "OFF\n0 0 0\n", "no vertices"},
                      BadCliInput{"nan", "nan.obj", "v 0 0 0\nv 0 nan 0\nv 1 0 0\nf 1 2 3\n",
                                  "non-finite"},
                      BadCliInput{"garbage", "junk.ply", "ply\nformat nonsense\n", "cannot parse"}),
    [](const auto& info) { return info.param.name; });

TEST(Cli, UsageErrorsExitTwo) {
  const std::string dir = test::tempDir("cli_usage");
  EXPECT_EQ(runCli("skeleton", dir).exit_code, 2);
  EXPECT_EQ(runCli("no-such-command", dir).exit_code, 2);
  EXPECT_EQ(runCli("--help", dir).exit_code, 0);
}

}  // namespace
}  // namespace skelgrasp
