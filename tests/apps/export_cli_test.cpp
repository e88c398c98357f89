// Grasps exported for robot stacks: MoveIt moveit_msgs/Grasp YAML and joint-state lists, read back
// with a YAML parser and checked against grasps.json and the hand's URDF.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>

#include "cli_support.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/hand/hand_model.h"
#include "test_support.h"

namespace skelgrasp {
namespace {

using test::CliRun;
using test::countLines;
using test::runCli;

constexpr double kTolerance = 1e-9;

// Movable joints of a URDF read from its XML text (not through skelgrasp's own loader), with
// whether each is a mimic joint.
std::map<std::string, bool> urdfMovableJoints(const std::string& urdf) {
  std::map<std::string, bool> joints;
  const std::regex joint(
      R"re(<joint\s+name="([^"]+)"\s+type="(revolute|prismatic|continuous)"[^>]*>([\s\S]*?)</joint>)re");
  for (auto it = std::sregex_iterator(urdf.begin(), urdf.end(), joint);
       it != std::sregex_iterator(); ++it) {
    joints[(*it)[1]] = (*it)[3].str().find("<mimic") != std::string::npos;
  }
  return joints;
}

class ExportCli : public ::testing::TestWithParam<std::string> {};

TEST_P(ExportCli, MoveItAndJointStatesMatchGraspsJsonAndTheUrdf) {
  const std::string hand = GetParam();
  const std::string dir = test::tempDir("cli_export_" + hand);
  saveMesh(dir + "/bottle.ply", geometry::shapes::makeNamedShape("bottle"));
  CliRun run = runCli("plan " + dir + "/bottle.ply --hand " + hand + " --out " + dir +
                          "/grasps.json --export moveit,joint_states",
                      dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto grasps = readJsonFile(dir + "/grasps.json")["grasps"];
  ASSERT_FALSE(grasps.empty()) << "no grasp planned for the bottle with " << hand;
  const auto urdf_joints = urdfMovableJoints(grasping::builtinHandFiles(hand).urdf);
  ASSERT_FALSE(urdf_joints.empty());
  const auto model = grasping::loadBuiltinHand(hand);

  const YAML::Node moveit = YAML::LoadFile(dir + "/grasps.moveit.yaml");
  ASSERT_TRUE(moveit.IsSequence());
  ASSERT_EQ(moveit.size(), grasps.size());
  for (std::size_t i = 0; i < grasps.size(); ++i) {
    const auto& g = grasps[i];
    const YAML::Node m = moveit[i];
    EXPECT_EQ(m["id"].as<std::string>(),
              "bottle.ply_" + hand + "_" + std::to_string(g["id"].get<int>()));
    // Pose: position and orientation (x, y, z, w) equal the grasps.json hand pose (w, x, y, z).
    const auto& position = g["hand_pose"]["position"];
    const auto& wxyz = g["hand_pose"]["quaternion_wxyz"];
    const YAML::Node pose = m["grasp_pose"]["pose"];
    EXPECT_EQ(m["grasp_pose"]["header"]["frame_id"].as<std::string>(), "bottle.ply");
    EXPECT_NEAR(pose["position"]["x"].as<double>(), position[0].get<double>(), kTolerance);
    EXPECT_NEAR(pose["position"]["z"].as<double>(), position[2].get<double>(), kTolerance);
    const double sign = pose["orientation"]["w"].as<double>() * wxyz[0].get<double>() < 0 ? -1 : 1;
    EXPECT_NEAR(pose["orientation"]["w"].as<double>(), sign * wxyz[0].get<double>(), 1e-6);
    EXPECT_NEAR(pose["orientation"]["x"].as<double>(), sign * wxyz[1].get<double>(), 1e-6);
    // Postures: actuated URDF joints only, closed values from grasps.json, open = preshape.
    const YAML::Node closed = m["grasp_posture"], open = m["pre_grasp_posture"];
    const auto names = closed["joint_names"].as<std::vector<std::string>>();
    ASSERT_FALSE(names.empty());
    EXPECT_EQ(open["joint_names"].as<std::vector<std::string>>(), names);
    const auto closed_q = closed["points"][0]["positions"].as<std::vector<double>>();
    const auto open_q = open["points"][0]["positions"].as<std::vector<double>>();
    ASSERT_EQ(closed_q.size(), names.size());
    const auto& preshape = model.preshape(g["preshape"].get<std::string>());
    for (std::size_t k = 0; k < names.size(); ++k) {
      ASSERT_TRUE(urdf_joints.count(names[k])) << names[k] << " is not a movable joint of the URDF";
      EXPECT_FALSE(urdf_joints.at(names[k])) << names[k] << " is a mimic joint";
      EXPECT_NEAR(closed_q[k], g["joints"][names[k]].get<double>(), kTolerance) << names[k];
      EXPECT_NEAR(open_q[k], preshape.joints[model.jointIndex(names[k])], kTolerance) << names[k];
    }
    // The approach is a unit vector in the hand's frame; the retreat goes back along it.
    const YAML::Node approach = m["pre_grasp_approach"];
    const Eigen::Vector3d a(approach["direction"]["vector"]["x"].as<double>(),
                            approach["direction"]["vector"]["y"].as<double>(),
                            approach["direction"]["vector"]["z"].as<double>());
    EXPECT_NEAR(a.norm(), 1.0, 1e-9);
    EXPECT_EQ(approach["direction"]["header"]["frame_id"].as<std::string>(),
              model.links()[model.rootLink()].name);
    EXPECT_NEAR(approach["min_distance"].as<double>(), g["retreat_m"].get<double>(), kTolerance);
    EXPECT_GT(approach["desired_distance"].as<double>(), approach["min_distance"].as<double>());
    EXPECT_NEAR(m["post_grasp_retreat"]["direction"]["vector"]["x"].as<double>(), -a.x(), 1e-9);
    EXPECT_NEAR(m["grasp_quality"].as<double>(), g["epsilon"].get<double>(), kTolerance);
  }

  // Joint states: every movable joint of grasps.json (mimics included), URDF names.
  const auto states = readJsonFile(dir + "/grasps.joint_states.json");
  EXPECT_EQ(states["schema"], "skelgrasp.joint_states/1");
  ASSERT_EQ(states["grasps"].size(), grasps.size());
  for (std::size_t i = 0; i < grasps.size(); ++i) {
    const auto& s = states["grasps"][i];
    ASSERT_EQ(s["name"].size(), grasps[i]["joints"].size());
    for (std::size_t k = 0; k < s["name"].size(); ++k) {
      const std::string name = s["name"][k];
      EXPECT_TRUE(urdf_joints.count(name)) << name;
      EXPECT_NEAR(s["position"][k].get<double>(), grasps[i]["joints"][name].get<double>(),
                  kTolerance);
    }
  }

  // `export` writes the same file from grasps.json afterwards.
  run = runCli("export " + dir + "/grasps.json --format moveit --out " + dir + "/again.yaml", dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  auto slurp = [](const std::string& p) {
    std::ifstream in(p);
    return std::string((std::istreambuf_iterator<char>(in)), {});
  };
  EXPECT_EQ(slurp(dir + "/again.yaml"), slurp(dir + "/grasps.moveit.yaml"));
}

INSTANTIATE_TEST_SUITE_P(Hands, ExportCli,
                         ::testing::Values("armar3", "sdh", "shadow", "parallel_gripper"));

TEST(ExportCliErrors, BadInputIsOneLineAndExitTwoAndWritesNothing) {
  const std::string dir = test::tempDir("cli_export_bad");
  std::ofstream(dir + "/broken.json") << "{\"hand\": \"sdh\", \"grasps\": [";
  // With a schema: files without one are refused before their fields are read.
  std::ofstream(dir + "/nograsps.json") << R"({"schema": "skelgrasp.grasps/3", "hand": "sdh"})";
  std::ofstream(dir + "/badjoint.json")
      << R"({"schema": "skelgrasp.grasps/3",
           "hand": "sdh", "grasps": [{"id": 0, "preshape": "power", "retreat_m": 0,
           "epsilon": 0.1, "hand_pose": {"position": [0, 0, 0], "quaternion_wxyz": [1, 0, 0, 0]},
           "joints": {"no_such_joint": 0.3}}]})";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"export " + dir + "/broken.json --format moveit", "broken.json"},
      {"export " + dir + "/nograsps.json --format moveit", "has no \"grasps\""},
      {"export " + dir + "/badjoint.json --format joint_states", "no_such_joint"},
      {"export " + dir + "/badjoint.json --format moveit --hand armar3", "planned with hand"},
      {"export " + dir + "/badjoint.json --format urdf", "--format"},
      {"export " + dir + "/missing.json --format moveit", "missing.json"},
  };
  for (const auto& [args, expected] : cases) {
    const CliRun run = runCli(args + " --out " + dir + "/out.yaml", dir);
    EXPECT_EQ(run.exit_code, 2) << args;
    EXPECT_EQ(countLines(run.err), 1) << args << ": " << run.err;
    EXPECT_NE(run.err.find(expected), std::string::npos) << args << ": " << run.err;
    EXPECT_FALSE(std::filesystem::exists(dir + "/out.yaml")) << args;
  }
}

}  // namespace
}  // namespace skelgrasp
