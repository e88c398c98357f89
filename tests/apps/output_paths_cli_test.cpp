// Output paths on the command line: checked before any work, one error line, and a command that
// fails leaves no outputs and no temporary files behind.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "cli_support.h"
#include "perception/synthetic_scenes.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/perception/cloud_io.h"
#include "test_support.h"

namespace skelgrasp {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::countLines;
using test::runCli;
using test::withDir;

// Every entry below `dir` named like a temporary (".NAME.tmp.PID.N.EXT") or a probe.
std::vector<std::string> temporariesUnder(const std::string& dir) {
  std::vector<std::string> found;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.find(".tmp") != std::string::npos || name.find("probe") != std::string::npos) {
      found.push_back(entry.path().string());
    }
  }
  return found;
}

bool isEmptyDirectory(const std::string& dir) {
  return fs::is_directory(dir) && fs::directory_iterator(dir) == fs::directory_iterator();
}

void expectOneErrorLine(const CliRun& run, const std::string& path, const std::string& problem) {
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_EQ(countLines(run.err), 1) << run.err;
  EXPECT_EQ(run.err.rfind("skelgrasp: error: " + path + ": ", 0), 0u) << run.err;
  EXPECT_NE(run.err.find(problem), std::string::npos) << run.err;
}

TEST(OutputPathsCli, BadRenderPathFailsBeforeTheSkeletonIsComputed) {
  const std::string dir = test::tempDir("cli_out_render");
  saveMesh(dir + "/capsule.ply", geometry::shapes::makeNamedShape("capsule"));
  fs::create_directories(dir + "/out");
  const CliRun run = runCli("skeleton " + dir + "/capsule.ply --out " + dir +
                                "/out --render /no/such/dir/x.png --write-regularised",
                            dir);
  expectOneErrorLine(run, "/no/such/dir/x.png", "no such directory /no/such/dir");
  EXPECT_TRUE(run.out.empty()) << run.out;  // no summary line: nothing was computed
  EXPECT_TRUE(isEmptyDirectory(dir + "/out"));
  EXPECT_FALSE(fs::exists("/no"));
  EXPECT_TRUE(temporariesUnder(dir).empty());
}

TEST(OutputPathsCli, OutputBelowARegularFileOrOntoADirectoryIsRefused) {
  const std::string dir = test::tempDir("cli_out_bad_paths");
  saveMesh(dir + "/box.ply", geometry::shapes::makeNamedShape("box"));
  std::ofstream(dir + "/plain.txt") << "a file, not a directory";
  fs::create_directories(dir + "/a_directory.json");
  const struct {
    std::string args, path, problem;
  } cases[] = {
      {"skeleton {dir}/box.ply --out {dir}/plain.txt", "{dir}/plain.txt", "not a directory"},
      {"skeleton {dir}/box.ply --out {dir}/plain.txt/sub", "{dir}/plain.txt/sub",
       "{dir}/plain.txt is not a directory"},
      {"plan {dir}/box.ply --hand sdh --out {dir}/a_directory.json", "{dir}/a_directory.json",
       "is a directory"},
      {"plan {dir}/box.ply --hand sdh --out {dir}/g.json --render {dir}/plain.txt/g.png",
       "{dir}/plain.txt/g.png", "not a directory"},
      // The input does not even exist: the outputs are checked first, before any reading.
      {"reconstruct {dir}/none.pcd --out {dir}/m.ply --report {dir}/plain.txt/r.json",
       "{dir}/plain.txt/r.json", "not a directory"},
      {"ingest {dir}/none.pcd --out {dir}/plain.txt/c.pcd", "{dir}/plain.txt/c.pcd",
       "not a directory"},
      {"run {dir}/none.pcd --out {dir}/plain.txt/run", "{dir}/plain.txt/run", "not a directory"},
      {"demo --out {dir}/plain.txt", "{dir}/plain.txt", "not a directory"},
      {"close {dir}/box.ply --hand sdh --pose \"0 0 0.2 1 0 0 0\" --render {dir}/plain.txt/c.png",
       "{dir}/plain.txt/c.png", "not a directory"},
      {"shape mug --out {dir}/a_directory.json", "{dir}/a_directory.json", "is a directory"},
      {"evaluate --objects {dir}/box.ply --out {dir}/plain.txt", "{dir}/plain.txt",
       "not a directory"},
      {"bench skeleton {dir}/box.ply --json {dir}/plain.txt/b.json", "{dir}/plain.txt/b.json",
       "not a directory"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.args);
    const CliRun run = runCli(withDir(c.args, dir), dir);
    expectOneErrorLine(run, withDir(c.path, dir), withDir(c.problem, dir));
  }
  EXPECT_FALSE(fs::exists(dir + "/g.json"));
  EXPECT_FALSE(fs::exists(dir + "/m.ply"));
  EXPECT_TRUE(temporariesUnder(dir).empty());
}

TEST(OutputPathsCli, LaterOutputFailingLeavesNoneOfTheEarlierOnes) {
  // regularised.ply is a directory: the check of --out passes, segmentation.ply is written, then
  // regularised.ply fails. Neither it nor skeleton.json nor segmentation.ply may appear.
  const std::string dir = test::tempDir("cli_out_rollback");
  saveMesh(dir + "/capsule.ply", geometry::shapes::makeNamedShape("capsule"));
  fs::create_directories(dir + "/out/regularised.ply");
  const CliRun run = runCli("-q skeleton " + dir + "/capsule.ply --out " + dir +
                                "/out --write-regularised --render " + dir + "/render.png",
                            dir);
  expectOneErrorLine(run, dir + "/out/regularised.ply", "is a directory");
  EXPECT_FALSE(fs::exists(dir + "/out/segmentation.ply"));
  EXPECT_FALSE(fs::exists(dir + "/out/skeleton.json"));
  EXPECT_FALSE(fs::exists(dir + "/render.png"));
  EXPECT_TRUE(temporariesUnder(dir).empty());
}

TEST(OutputPathsCli, SuccessfulSkeletonWritesEverythingAndNoTemporaries) {
  const std::string dir = test::tempDir("cli_out_ok");
  saveMesh(dir + "/capsule.ply", geometry::shapes::makeNamedShape("capsule"));
  const CliRun run = runCli("skeleton " + dir + "/capsule.ply --out " + dir +
                                "/new/out --write-regularised --render " + dir + "/pics/r.png",
                            dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const char* file : {"/new/out/skeleton.json", "/new/out/segmentation.ply",
                           "/new/out/regularised.ply", "/pics/r.png"}) {
    EXPECT_TRUE(fs::is_regular_file(dir + file)) << file;
  }
  EXPECT_TRUE(temporariesUnder(dir).empty());
}

TEST(OutputPathsCli, FailedRunLeavesNoPartialOutputDirectory) {
  // scene.bt is taken by a directory: object.ply, the pictures and the report are already written
  // (to temporaries) when the occupancy tree fails; none of them may be left, nor grasps.json.
  const std::string dir = test::tempDir("cli_out_run_rollback");
  perception::savePointCloud(dir + "/scene.pcd", test::renderTableScene(41).cloud);
  fs::create_directories(dir + "/out/scene.bt");
  const CliRun run = runCli("-q run " + dir +
                                "/scene.pcd --hand sdh --object nearest:0.05,-0.09,0.05 "
                                "--max-grasps 2 --out " +
                                dir + "/out",
                            dir);
  expectOneErrorLine(run, dir + "/out/scene.bt", "is a directory");
  std::vector<std::string> left;
  for (const auto& entry : fs::directory_iterator(dir + "/out")) {
    left.push_back(entry.path().filename().string());
  }
  std::sort(left.begin(), left.end());
  // .lock: run's lock of --out, which stays (as evaluate's).
  EXPECT_EQ(left, (std::vector<std::string>{".lock", "scene.bt"}));
  EXPECT_TRUE(isEmptyDirectory(dir + "/out/scene.bt"));
  EXPECT_TRUE(temporariesUnder(dir).empty());
}

}  // namespace
}  // namespace skelgrasp
