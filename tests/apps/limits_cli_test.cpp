// Resource guards through the CLI: parameters that would need more memory than the limit end with
// one error line naming the estimate and exit 2, before any work (issue 13's blow-up cases).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

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

// `count` contacts on a 5 cm sphere with outward normals, seeded.
void writeContacts(const std::string& path, int count) {
  std::mt19937 rng(13);
  std::normal_distribution<double> gauss;
  nlohmann::json contacts = nlohmann::json::array();
  for (int i = 0; i < count; ++i) {
    Eigen::Vector3d n(gauss(rng), gauss(rng), gauss(rng));
    n.normalize();
    const Eigen::Vector3d p = 0.05 * n;
    contacts.push_back({{"point", {p.x(), p.y(), p.z()}}, {"normal", {n.x(), n.y(), n.z()}}});
  }
  writeJsonFile(path, nlohmann::json{{"contacts", contacts}});
}

class LimitsCli : public ::testing::TestWithParam<BadCliInput> {};

TEST_P(LimitsCli, RefusesWithOneLineNamingTheEstimate) {
  const auto& c = GetParam();
  const std::string dir = test::tempDir("cli_limits_" + c.name);
  perception::savePointCloud(dir + "/scene.pcd",
                             test::renderTableScene(41, {0.55, 0.05, 0.6}, true).cloud);
  saveMesh(dir + "/capsule.ply", geometry::shapes::makeNamedShape("capsule"));
  // The most a contact file may hold (grasping::ContactFileLimits): its 6D hull needs ~120 MB.
  writeContacts(dir + "/contacts.json", 100);
  const CliRun r = runCli(withDir(c.args, dir), dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(countLines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("skelgrasp: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("(estimate), limit"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--memory-limit"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
  // Refused before anything was written.
  EXPECT_FALSE(std::filesystem::exists(dir + "/out"));
  EXPECT_TRUE(r.out.empty()) << r.out;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, LimitsCli,
    ::testing::Values(
        BadCliInput{"poisson_depth",
                    "reconstruct {dir}/scene.pcd --poisson-depth 14 --out {dir}/out/m.ply",
                    "--poisson-depth"},
        BadCliInput{"octree_resolution",
                    "run {dir}/scene.pcd --octree-resolution 1e-6 --out {dir}/out",
                    "--octree-resolution"},
        BadCliInput{"remesh", "skeleton {dir}/capsule.ply --remesh 1e-6 --out {dir}/out",
                    "--remesh"},
        BadCliInput{"alpha_divisor",
                    "skeleton {dir}/capsule.ply --alpha-divisor 1e6 --out {dir}/out",
                    "--alpha-divisor"},
        BadCliInput{"quality_contacts", "--memory-limit 64M quality {dir}/contacts.json",
                    "800 wrenches (100 contacts"},
        // A legal default run refuses under a limit far below its estimate.
        BadCliInput{"tiny_limit", "--memory-limit 1M skeleton {dir}/capsule.ply --out {dir}/out",
                    "limit 1 MiB"}),
    [](const auto& info) { return info.param.name; });

TEST(LimitsCli, RaisingTheLimitIsAcceptedAndDefaultsRun) {
  const std::string dir = test::tempDir("cli_limits_ok");
  saveMesh(dir + "/capsule.ply", geometry::shapes::makeNamedShape("capsule"));
  const CliRun r =
      runCli("-q skeleton " + dir + "/capsule.ply --memory-limit 0.5 --out " + dir + "/out", dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir + "/out/skeleton.json"));
}

TEST(LimitsCli, MalformedMemoryLimitIsOneErrorLine) {
  const std::string dir = test::tempDir("cli_limits_malformed");
  for (const std::string value : {"lots", "-4G", "0", "4X", "nan"}) {
    const CliRun r = runCli("--memory-limit " + value + " hands", dir);
    EXPECT_EQ(r.exit_code, 2) << value << ": " << r.err;
    EXPECT_EQ(countLines(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind("skelgrasp: error: --memory-limit", 0), 0u) << r.err;
  }
}

}  // namespace
}  // namespace skelgrasp
