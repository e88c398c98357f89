// Hostile input, round three (issue 77): degenerate meshes, capture intrinsics, oversized images,
// hand files and grasps files. Each ends with exit 2, one error line naming the file and the
// problem, and nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_support.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
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

// The single face of this mesh has zero area: its corners lie on one line.
const char* const kCollinearPly =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n0.05 0 0\n0.1 0 0\n3 0 1 2\n";

void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// Every file the cases below name, in the test's folder.
void writeHostileFiles(const std::string& dir) {
  writeText(dir + "/collinear.ply", kCollinearPly);
  saveMesh(dir + "/capsule.ply", geometry::shapes::makeNamedShape("capsule"));
}

class HostileInputCli : public ::testing::TestWithParam<BadCliInput> {};

TEST_P(HostileInputCli, ExitsTwoWithOneLineAndWritesNothing) {
  const auto& c = GetParam();
  const std::string dir = test::tempDir("cli_hostile_" + c.name);
  writeHostileFiles(dir);
  const std::string args = withDir(c.args, dir);
  for (const std::string quiet : {"", "-q "}) {
    const CliRun r = runCli(quiet + args, dir);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    const std::string line = lastLine(r.err);
    EXPECT_EQ(line.rfind("skelgrasp: error: ", 0), 0u) << r.err;
    EXPECT_NE(line.find(c.expected), std::string::npos) << r.err;
    if (!quiet.empty()) {
      EXPECT_EQ(countLines(r.err), 1) << r.err;
    }
    EXPECT_TRUE(r.out.empty()) << r.out;
    // Nothing named out* (the outputs and their hidden temporaries) is left behind.
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      EXPECT_NE(name.rfind("out", 0), 0u) << "half-written output " << name;
      EXPECT_EQ(name.find(".tmp."), std::string::npos) << "temporary left " << name;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, HostileInputCli,
    ::testing::Values(
        BadCliInput{"skeleton_collinear_mesh", "skeleton {dir}/collinear.ply --out {dir}/out",
                    "collinear.ply: degenerate mesh: no face has a positive area"},
        BadCliInput{"plan_collinear_mesh",
                    "plan {dir}/collinear.ply --hand sdh --out {dir}/out --render {dir}/out.png",
                    "collinear.ply: degenerate mesh: no face has a positive area"},
        // The surface planner sampled such a mesh until its time limit, logging every sample.
        BadCliInput{"plan_surface_collinear_mesh",
                    "plan {dir}/collinear.ply --hand sdh --planner surface --out {dir}/out",
                    "collinear.ply: degenerate mesh: no face has a positive area"}),
    [](const auto& info) { return info.param.name; });

TEST(HostileInputCli, EvaluateRecordsADegenerateMeshAsAFailedRunAndFinishes) {
  const std::string dir = test::tempDir("cli_hostile_evaluate_degenerate");
  const std::string objects = dir + "/objects", out = dir + "/out";
  fs::create_directories(objects);
  writeText(objects + "/collinear.ply", kCollinearPly);
  saveMesh(objects + "/capsule.ply", geometry::shapes::makeNamedShape("capsule"));
  const std::string args = "evaluate --objects " + objects + " --out " + out +
                           " --hands sdh --planners skeleton --robustness-samples 4"
                           " --robustness-grasps 2 --timeout 0 --vertex-distance 0.01";
  // The first run and a resume with --retry-failed both finish; the failure names the file.
  for (const std::string extra : {"", " --retry-failed"}) {
    const CliRun r = runCli(args + extra, dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::ifstream runs(out + "/runs.jsonl");
    const std::string text((std::istreambuf_iterator<char>(runs)), {});
    EXPECT_NE(text.find("collinear.ply: degenerate mesh"), std::string::npos) << text;
    EXPECT_NE(text.find("\"capsule.ply\""), std::string::npos) << text;
  }
}

}  // namespace
}  // namespace skelgrasp
