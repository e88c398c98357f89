// The `skelgrasp` launcher (apps/launcher.cpp): it answers the top-level help itself with the full
// program's text, routes mesh commands to skelgrasp-mesh and everything else to skelgrasp-full,
// and keeps the house error format.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "cli_support.h"
#include "test_support.h"

namespace skelgrasp {
namespace {

namespace fs = std::filesystem;

const fs::path kLauncher = SKELGRASP_CLI_PATH;

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

// Runs `program` with argv[0] set to `name` and returns what it printed on stdout.
std::string helpOf(const fs::path& program, const std::string& name, const std::string& flag,
                   const std::string& dir) {
  const std::string out = dir + "/help.txt";
  const std::string command =
      "bash -c 'exec -a \"" + name + "\" \"" + program.string() + "\" " + flag + "' > " + out;
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  return readFile(out);
}

TEST(Launcher, TopLevelHelpIsTheFullProgramsHelp) {
  const std::string dir = test::tempDir("launcher_help");
  const fs::path full = kLauncher.parent_path() / "skelgrasp-full";
  const std::string expected = helpOf(full, "skelgrasp", "--help", dir);
  ASSERT_NE(expected.find("Subcommands:"), std::string::npos) << expected;
  EXPECT_EQ(helpOf(kLauncher, "skelgrasp", "--help", dir), expected);
  EXPECT_EQ(helpOf(kLauncher, "skelgrasp", "-h", dir), expected);
  // The machine-dependent default is filled in, not left as the build's placeholder.
  EXPECT_EQ(expected.find("@SKELGRASP"), std::string::npos);
}

// Without skelgrasp-full beside it, a mesh command still runs (in skelgrasp-mesh) and a scan
// command fails in one line naming the missing program: the routing is by command word.
TEST(Launcher, MeshCommandsRunWithoutTheFullProgram) {
  const std::string dir = test::tempDir("launcher_routing");
  for (const char* program : {"skelgrasp", "skelgrasp-mesh"}) {
    fs::copy_file(kLauncher.parent_path() / program, fs::path(dir) / program);
  }
  const std::string launcher = (fs::path(dir) / "skelgrasp").string();
  auto run = [&](const std::string& args) {
    const std::string command =
        launcher + " " + args + " > " + dir + "/out.txt 2> " + dir + "/err.txt";
    const int status = std::system(command.c_str());
    return std::make_pair(WEXITSTATUS(status), readFile(dir + "/err.txt"));
  };
  for (const char* command : {"plan", "skeleton", "shape", "hands", "close", "quality", "evaluate",
                              "merge", "export", "score", "simulate"}) {
    EXPECT_EQ(run(std::string(command) + " --help").first, 0) << command;
  }
  EXPECT_EQ(run("-q --memory-limit 4G plan --help").first, 0);
  const auto [code, err] = run("run --help");
  EXPECT_EQ(code, 2);
  EXPECT_EQ(test::countLines(err), 1) << err;
  EXPECT_NE(err.find("skelgrasp: error: cannot start"), std::string::npos) << err;
  EXPECT_NE(err.find("skelgrasp-full"), std::string::npos) << err;
}

TEST(Launcher, ErrorsKeepTheHouseFormat) {
  const std::string dir = test::tempDir("launcher_errors");
  for (const std::string args : {"", "frobnicate", "--memory-limit 4G", "plan --no-such-option"}) {
    const auto result = test::runCli(args, dir);
    EXPECT_EQ(result.exit_code, 2) << args;
    EXPECT_EQ(test::countLines(result.err), 1) << args << ": " << result.err;
    EXPECT_EQ(result.err.rfind("skelgrasp: error: ", 0), 0u) << args << ": " << result.err;
  }
  EXPECT_NE(test::runCli("frobnicate", dir).err.find("unknown command 'frobnicate'"),
            std::string::npos);
}

}  // namespace
}  // namespace skelgrasp
