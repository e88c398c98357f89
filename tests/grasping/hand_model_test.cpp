#include "skelgrasp/grasping/hand_model.h"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <regex>

#include "skelgrasp/common/error.h"
#include "test_support.h"

namespace skelgrasp::grasping {
namespace {

std::string handFile(const std::string& hand, const std::string& file) {
  return std::string(SKELGRASP_SOURCE_DIR) + "/grasping/hands/" + hand + "/" + file;
}

TEST(HandModel, BuiltInHandsHaveTheirFingersAndDrives) {
  struct Expected {
    const char* name;
    std::size_t fingers;
    int drives;
  };
  // ARMAR-III: 10 actuated joints; SDH: 6 flexion joints; Shadow: J3 + coupled J2/J1 per finger
  // and five thumb joints; gripper: two jaws closing independently (the object slides until both
  // touch; parallel_gripper.urdf).
  for (const auto& e : {Expected{"armar3", 5, 10}, Expected{"sdh", 3, 6}, Expected{"shadow", 5, 13},
                        Expected{"parallel_gripper", 2, 2}}) {
    const HandModel hand = loadBuiltinHand(e.name);
    EXPECT_EQ(hand.fingers().size(), e.fingers) << e.name;
    EXPECT_EQ(hand.numDrives(), e.drives) << e.name;
    EXPECT_TRUE(hand.preshapes().count("power")) << e.name;
    EXPECT_TRUE(hand.preshapes().count("precision")) << e.name;
  }
  EXPECT_EQ(loadBuiltinHand("shadow").numMovingJoints(), 17);  // + J1 of four fingers
  EXPECT_EQ(builtinHandNames().size(), 4u);
}

// Grasp centre points at the preshapes, in the hand root frame, from the fact sheet (mm).
TEST(HandModel, GraspCentrePointsMatchTheReferenceFrames) {
  struct Case {
    const char* hand;
    const char* preshape;
    Eigen::Vector3d position_mm;
    Eigen::Vector3d z_axis;
  };
  const double s = std::sqrt(0.5);
  const std::vector<Case> cases = {
      {"armar3", "power", {-50, 16, 115}, {-s, 0, s}},
      {"armar3", "precision", {-84, 0, 144}, {-s, 0, s}},
      {"sdh", "power", {0, 0, 206.8}, {0, 0, 1}},
      {"sdh", "precision", {0, 0, 236.8}, {0, 0, 1}},
      {"shadow", "power", {0, -60, 327}, {0, -0.9063, 0.4226}},
      {"shadow", "precision", {20, -90, 327}, {0, -0.9063, 0.4226}},
      {"parallel_gripper", "power", {0, 0, 103.4}, {0, 0, 1}},
  };
  for (const auto& c : cases) {
    const HandModel hand = loadBuiltinHand(c.hand);
    const Pose gcp = hand.gcpInRoot(hand.preshape(c.preshape));
    EXPECT_LT((gcp.translation() * 1000 - c.position_mm).norm(), 0.1)
        << c.hand << " " << c.preshape;
    EXPECT_LT((gcp.rotation().col(2) - c.z_axis).norm(), 1e-3) << c.hand << " " << c.preshape;
  }
}

TEST(HandModel, ForwardKinematicsFollowsTheJoints) {
  const HandModel hand = loadBuiltinHand("armar3");
  Eigen::VectorXd q = hand.zeroConfiguration();
  // Straight fingers: the index distal frame sits 40.2 mm above the finger base at z 105.45 mm.
  auto poses = hand.linkPoses(q);
  const int distal = hand.linkIndex("index_distal");
  EXPECT_NEAR(poses[distal].translation().z(), 0.14565, 1e-6);
  // Bending J0 by 90 degrees about -y turns the finger towards -x.
  q[hand.jointIndex("index_j0")] = 3.14159265358979 / 2;
  poses = hand.linkPoses(q);
  EXPECT_NEAR(poses[distal].translation().x(), -0.0087 - 0.0402, 1e-6);
  EXPECT_NEAR(poses[distal].translation().z(), 0.10545, 1e-6);
  // Limits are enforced by normalise().
  q[hand.jointIndex("index_j1")] = 10;
  hand.normalise(q);
  EXPECT_NEAR(q[hand.jointIndex("index_j1")], 3.141593, 1e-6);
}

TEST(HandModel, MimicJointsFollowTheirLeader) {
  const HandModel sdh = loadBuiltinHand("sdh");
  Eigen::VectorXd q = sdh.zeroConfiguration();
  q[sdh.jointIndex("finger1_base_joint")] = 0.5;
  sdh.normalise(q);
  EXPECT_DOUBLE_EQ(q[sdh.jointIndex("finger2_base_joint")], 0.5);
  const HandModel gripper = loadBuiltinHand("parallel_gripper");
  Eigen::VectorXd g = gripper.preshape("power").joints;
  EXPECT_DOUBLE_EQ(g[gripper.jointIndex("finger_right")], 0.04);
}

TEST(HandModel, LoadsFromFilesThroughTheSamePathAsBuiltIns) {
  const HandModel hand = loadHand(handFile("sdh", "sdh.urdf"), handFile("sdh", "sdh.grasp.json"));
  EXPECT_EQ(hand.name(), "sdh");
  EXPECT_EQ(hand.numDrives(), 6);
  const HandModel resolved =
      resolveHand(handFile("shadow", "shadow.urdf"), handFile("shadow", "shadow.grasp.json"));
  EXPECT_EQ(resolved.fingers().size(), 5u);
}

TEST(HandModel, BadHandInputsNameTheFileAndTheProblem) {
  EXPECT_THROW(resolveHand("robotiq"), InvalidArgument);
  EXPECT_THROW(resolveHand("hand.urdf"), InvalidArgument);  // needs a description
  const std::string dir = test::tempDir("bad_hand");
  const std::string desc = handFile("armar3", "armar3.grasp.json");
  auto expectIoError = [](const std::function<void()>& load, const std::string& path,
                          const std::string& problem) {
    try {
      load();
      FAIL() << "expected IoError: " << problem;
    } catch (const IoError& e) {
      EXPECT_EQ(e.path(), path);
      EXPECT_NE(e.problem().find(problem), std::string::npos) << e.problem();
    }
  };
  expectIoError([&] { loadHand(dir + "/none.urdf", desc); }, dir + "/none.urdf", "no such file");
  std::ofstream(dir + "/broken.urdf") << "<robot name='x'><link name='a'>";
  expectIoError([&] { loadHand(dir + "/broken.urdf", desc); }, dir + "/broken.urdf",
                "invalid URDF");
  std::ofstream(dir + "/mesh.urdf")
      << "<robot name='m'><link name='base'><collision><geometry><mesh filename='missing.stl'/>"
         "</geometry></collision></link></robot>";
  expectIoError([&] { loadHand(dir + "/mesh.urdf", desc); }, dir + "/missing.stl", "not found");
  // A description naming a joint the URDF does not have.
  std::ifstream in(desc);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const std::string renamed = std::regex_replace(text, std::regex("\"index_j1\""), "\"index_j9\"");
  std::ofstream(dir + "/desc.json") << renamed;
  expectIoError([&] { loadHand(handFile("armar3", "armar3.urdf"), dir + "/desc.json"); },
                dir + "/desc.json", "unknown joint 'index_j9'");
  std::ofstream(dir + "/schema.json") << "{\"schema\": \"other\"}";
  expectIoError([&] { loadHand(handFile("armar3", "armar3.urdf"), dir + "/schema.json"); },
                dir + "/schema.json", "schema");
}

}  // namespace
}  // namespace skelgrasp::grasping
