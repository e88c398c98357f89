#include "skelgrasp/grasping/hand/hand_model.h"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/error.h"
#include "test_support.h"

namespace skelgrasp::grasping {
namespace {

std::string handFile(const std::string& hand, const std::string& file) {
  return std::string(SKELGRASP_SOURCE_DIR) + "/grasping/hands/" + hand + "/" + file;
}

// A hand file's text, for tests that write a changed copy.
std::string handFileText(const std::string& hand, const std::string& file) {
  std::ifstream in(handFile(hand, file));
  return std::string((std::istreambuf_iterator<char>(in)), {});
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

TEST(HandModel, PlannersCloseEachTypesPreshapeThenItsAlternatives) {
  const HandModel sdh = loadBuiltinHand("sdh");
  const auto names = [](const std::vector<const Preshape*>& preshapes) {
    std::vector<std::string> out;
    for (const Preshape* p : preshapes) out.push_back(p->name);
    return out;
  };
  using Names = std::vector<std::string>;
  EXPECT_EQ(names(sdh.plannerPreshapes(GraspType::kPower)),
            (Names{"power", "claw", "lateral_power"}));
  EXPECT_EQ(names(sdh.plannerPreshapes(GraspType::kPower, false)), (Names{"power"}));
  EXPECT_EQ(names(sdh.plannerPreshapes(GraspType::kPrecision)),
            (Names{"precision", "lateral_precision", "narrow_tripod", "precision_tripod"}));
  EXPECT_EQ(names(sdh.plannerPreshapes(GraspType::kPrecision, false)), (Names{"precision"}));
  // The narrow tripod is for small objects: left out for an object larger than its limit.
  ASSERT_TRUE(sdh.preshape("narrow_tripod").max_object_length_m);
  const double limit_m = *sdh.preshape("narrow_tripod").max_object_length_m;
  EXPECT_EQ(names(sdh.plannerPreshapes(GraspType::kPrecision, true, limit_m)),
            (Names{"precision", "lateral_precision", "narrow_tripod", "precision_tripod"}));
  EXPECT_EQ(names(sdh.plannerPreshapes(GraspType::kPrecision, true, limit_m + 1e-3)),
            (Names{"precision", "lateral_precision", "precision_tripod"}));
  EXPECT_EQ(names(sdh.plannerPreshapes(GraspType::kPower, true, 10 * limit_m)),
            (Names{"power", "claw", "lateral_power"}));
  for (const auto& [name, preshape] : sdh.preshapes())
    EXPECT_EQ(preshape.max_object_length_m.has_value(), name == "narrow_tripod") << name;
  EXPECT_EQ(sdh.preshape("claw").grasp_type, GraspType::kPower);
  EXPECT_EQ(sdh.preshape("lateral_power").grasp_type, GraspType::kPower);
  EXPECT_EQ(sdh.preshape("lateral_precision").grasp_type, GraspType::kPrecision);
  EXPECT_EQ(sdh.preshape("precision").grasp_type, GraspType::kPrecision);
  EXPECT_EQ(sdh.preshape("precision_tripod").grasp_type, GraspType::kPrecision);
  EXPECT_EQ(sdh.preshape("narrow_tripod").grasp_type, GraspType::kPrecision);
  // The paper's hands keep their two preshapes.
  for (const char* name : {"armar3", "shadow", "parallel_gripper"}) {
    const HandModel hand = loadBuiltinHand(name);
    EXPECT_EQ(names(hand.plannerPreshapes(GraspType::kPower)), (Names{"power"})) << name;
    EXPECT_EQ(names(hand.plannerPreshapes(GraspType::kPrecision)), (Names{"precision"})) << name;
  }
}

// The SDH's tripods (claw, precision_tripod, narrow_tripod) turn fingers 1 and 2 by 60
// degrees about their bases. The three finger bases lie on a circle about the palm axis (the fact
// sheet's 38.1 mm), so then every finger closes towards that axis (a tripod, 120 degrees apart); in
// the power preshape fingers 1 and 2 close side by side towards the thumb's side; in its lateral
// grips (90 degrees) they close against each other.
TEST(HandModel, SdhTripodsCloseTowardsThePalmAxisAndLateralGripsAgainstEachOther) {
  const HandModel sdh = loadBuiltinHand("sdh");
  const auto closingDirections = [&](const Preshape& preshape) {
    std::vector<Eigen::Vector2d> out;
    for (const char* finger : {"finger1", "finger2", "thumb"}) {
      const int proximal = sdh.jointIndex(std::string(finger) + "_proximal_joint");
      const int distal = sdh.linkIndex(std::string(finger) + "_distal");
      Eigen::VectorXd q = preshape.joints;
      const Eigen::Vector3d before = sdh.linkPoses(q)[distal].translation();
      q[proximal] += 0.01;  // the closing direction of every SDH drive is +1
      const Eigen::Vector3d after = sdh.linkPoses(q)[distal].translation();
      const Eigen::Vector3d base =
          sdh.linkPoses(q)[sdh.linkIndex(std::string(finger) + "_knuckle")].translation();
      EXPECT_NEAR(base.head<2>().norm(), 0.0381, 2e-4) << finger;
      out.push_back((after - before).head<2>().normalized());
      out.push_back(-base.head<2>().normalized());  // towards the palm axis
    }
    return out;
  };
  for (const char* tripod : {"claw", "precision_tripod", "narrow_tripod"}) {
    const auto directions = closingDirections(sdh.preshape(tripod));
    for (std::size_t f = 0; f < 3; ++f)
      EXPECT_GT(directions[2 * f].dot(directions[2 * f + 1]), std::cos(2 * kPi / 180))
          << tripod << " " << f;
  }
  const auto power = closingDirections(sdh.preshape("power"));
  EXPECT_GT(power[0].dot(power[2]), std::cos(2 * kPi / 180));   // fingers 1 and 2 parallel
  EXPECT_LT(power[0].dot(power[4]), -std::cos(2 * kPi / 180));  // against the thumb
  // The lateral grips turn fingers 1 and 2 by 90 degrees, the joint's limit: they close against
  // each other, and the thumb closes across the line between them.
  for (const char* lateral : {"lateral_power", "lateral_precision"}) {
    const auto directions = closingDirections(sdh.preshape(lateral));
    EXPECT_LT(directions[0].dot(directions[2]), -std::cos(2 * kPi / 180)) << lateral;
    EXPECT_LT(std::abs(directions[0].dot(directions[4])), std::sin(2 * kPi / 180)) << lateral;
  }
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
  const std::string text = handFileText("armar3", "armar3.grasp.json");
  const std::string renamed = std::regex_replace(text, std::regex("\"index_j1\""), "\"index_j9\"");
  std::ofstream(dir + "/desc.json") << renamed;
  expectIoError([&] { loadHand(handFile("armar3", "armar3.urdf"), dir + "/desc.json"); },
                dir + "/desc.json", "unknown joint 'index_j9'");
  // A preshape's grasp type: one of the two, and its own name's for "power" and "precision".
  // `entry` ("key": value) written first into the preshape's object.
  const auto withPreshapeEntry = [&](const std::string& preshape, const std::string& entry) {
    const std::string changed = std::regex_replace(
        text, std::regex("\"" + preshape + "\": \\{"), "\"" + preshape + "\": {" + entry + ", ",
        std::regex_constants::format_first_only);  // not the thresholds after it
    std::ofstream(dir + "/changed.json") << changed;
    return dir + "/changed.json";
  };
  const auto withPreshapeType = [&](const std::string& preshape, const std::string& type) {
    return withPreshapeEntry(preshape, "\"grasp_type\": \"" + type + "\"");
  };
  const std::string urdf = handFile("armar3", "armar3.urdf");
  expectIoError([&] { loadHand(urdf, withPreshapeType("power", "x")); }, dir + "/changed.json",
                "grasp_type must be \"power\" or \"precision\"");
  expectIoError([&] { loadHand(urdf, withPreshapeType("power", "precision")); },
                dir + "/changed.json", "its own name's type");
  EXPECT_EQ(
      loadHand(urdf, withPreshapeType("power", "power")).plannerPreshapes(GraspType::kPower).size(),
      1u);
  // A size limit: on an alternative preshape only (the main ones are closed where no size is
  // asked), and a positive number of metres.
  expectIoError(
      [&] { loadHand(urdf, withPreshapeEntry("power", "\"max_object_length_m\": 0.05")); },
      dir + "/changed.json", "only an alternative preshape can have a size limit");
  const std::string sdh_text = handFileText("sdh", "sdh.grasp.json");
  for (const char* bad : {"0", "-0.05", "true", "\"70 mm\""}) {
    std::ofstream(dir + "/sdh.json")
        << std::regex_replace(sdh_text, std::regex("\"max_object_length_m\": [0-9.]+"),
                              std::string("\"max_object_length_m\": ") + bad);
    expectIoError([&] { loadHand(handFile("sdh", "sdh.urdf"), dir + "/sdh.json"); },
                  dir + "/sdh.json", "max_object_length_m must be a positive number of metres");
  }
  std::ofstream(dir + "/schema.json") << "{\"schema\": \"other\"}";
  expectIoError([&] { loadHand(handFile("armar3", "armar3.urdf"), dir + "/schema.json"); },
                dir + "/schema.json", "schema");
}

// The Shadow hand's closings cost twice the SDH's, so its description carries a smaller ranking
// budget (docs/hands.md, "Ranking budget"); the paper's other hands leave it to the ranking.
TEST(HandModel, DescriptionsCarryTheirRankingBudget) {
  const RankingBudget shadow = resolveHand("shadow").rankingBudget();
  ASSERT_TRUE(shadow.screen_grasps && shadow.screen_samples && shadow.refine_below_r &&
              shadow.screen_candidates && shadow.confirm_samples);
  EXPECT_EQ(*shadow.screen_grasps, 40u);
  EXPECT_EQ(*shadow.screen_samples, 8);
  EXPECT_DOUBLE_EQ(*shadow.refine_below_r, 0.5);
  EXPECT_EQ(*shadow.screen_candidates, ScreenCandidates::kByPreScore);  // "screen_by": "epsilon"
  EXPECT_EQ(*shadow.confirm_samples, 0);                                // no confirmation
  // The SDH's says that it screens by finger travel and searches grasps below r = 0.5, as the
  // Shadow hand (docs/hands.md, "Ranking budget").
  const RankingBudget sdh = resolveHand("sdh").rankingBudget();
  EXPECT_FALSE(sdh.screen_grasps || sdh.screen_samples || sdh.confirm_samples);
  EXPECT_EQ(sdh.screen_candidates, ScreenCandidates::kPreshapesInTurnByTravel);
  ASSERT_TRUE(sdh.refine_below_r);
  EXPECT_DOUBLE_EQ(*sdh.refine_below_r, 0.5);
  for (const char* name : {"armar3", "parallel_gripper"}) {
    const RankingBudget none = resolveHand(name).rankingBudget();
    EXPECT_FALSE(none.screen_grasps || none.screen_samples || none.refine_below_r ||
                 none.screen_candidates || none.confirm_samples)
        << name;
  }

  const std::string dir = test::tempDir("ranking_budget");
  const std::string text = handFileText("armar3", "armar3.grasp.json");
  const auto withRanking = [&](const std::string& ranking) {
    const std::string path = dir + "/ranking.json";
    std::ofstream(path) << std::regex_replace(text, std::regex("\\{"),
                                              "{\"ranking\": " + ranking + ", ",
                                              std::regex_constants::format_first_only);
    return path;
  };
  const std::string urdf = handFile("armar3", "armar3.urdf");
  const RankingBudget partial =
      loadHand(urdf, withRanking("{\"screen_samples\": 6}")).rankingBudget();
  EXPECT_FALSE(partial.screen_grasps);
  EXPECT_EQ(partial.screen_samples, 6);
  EXPECT_FALSE(partial.refine_below_r);
  EXPECT_EQ(loadHand(urdf, withRanking("{\"screen_grasps\": 0}")).rankingBudget().screen_grasps,
            0u);  // 0: screen every candidate
  EXPECT_EQ(loadHand(urdf, withRanking("{\"screen_by\": \"preshapes\"}"))
                .rankingBudget()
                .screen_candidates,
            ScreenCandidates::kPreshapesInTurn);
  EXPECT_EQ(
      loadHand(urdf, withRanking("{\"screen_by\": \"epsilon\"}")).rankingBudget().screen_candidates,
      ScreenCandidates::kByPreScore);
  EXPECT_EQ(
      loadHand(urdf, withRanking("{\"screen_by\": \"travel\"}")).rankingBudget().screen_candidates,
      ScreenCandidates::kPreshapesInTurnByTravel);
  for (const auto candidates : {ScreenCandidates::kByPreScore, ScreenCandidates::kPreshapesInTurn,
                                ScreenCandidates::kPreshapesInTurnByTravel})
    EXPECT_EQ(parseScreenCandidates(toString(candidates)), candidates);
  EXPECT_EQ(loadHand(urdf, withRanking("{\"confirm_samples\": 6}")).rankingBudget().confirm_samples,
            6);
  const RankingBudget none = loadHand(urdf, withRanking("null")).rankingBudget();  // as absent
  EXPECT_FALSE(none.screen_grasps || none.screen_samples || none.refine_below_r);
  for (const auto& [ranking, problem] : std::vector<std::pair<std::string, std::string>>{
           {"{\"screen_grasps\": -1}", "'screen_grasps' must be a whole number in [0, "},
           {"{\"screen_grasps\": 2.5}", "'screen_grasps' must be a whole number in [0, "},
           {"{\"screen_grasps\": 18446744073709551615}", "'screen_grasps' must be a whole number"},
           {"{\"screen_samples\": 0}", "'screen_samples' must be a whole number in [1, 1000000]"},
           {"{\"screen_samples\": 1000001}", "'screen_samples' must be a whole number"},
           {"{\"screen_samples\": 4294967297}", "'screen_samples' must be a whole number"},
           {"{\"screen_samples\": 1e30}", "'screen_samples' must be a whole number"},
           {"{\"refine_below_r\": 1.5}", "ranking refine_below_r must be in [0, 1]"},
           {"{\"refine_below_r\": \"low\"}", "'refine_below_r' must be a number"},
           {"{\"screen_k\": 40}", "unknown key 'screen_k'"},
           {"{\"screen_by\": \"random\"}",
            "'screen_by' must be \"preshapes\", \"epsilon\" or \"travel\""},
           {"{\"screen_by\": true}",
            "'screen_by' must be \"preshapes\", \"epsilon\" or \"travel\""},
           {"{\"confirm_samples\": -1}", "'confirm_samples' must be a whole number in [0, "},
           {"{\"confirm_samples\": 2.5}", "'confirm_samples' must be a whole number in [0, "},
           {"[40]", "'ranking' must be an object"}}) {
    try {
      loadHand(urdf, withRanking(ranking));
      ADD_FAILURE() << "expected IoError for " << ranking;
    } catch (const IoError& e) {
      EXPECT_EQ(e.path(), dir + "/ranking.json");
      EXPECT_NE(e.problem().find(problem), std::string::npos) << e.problem();
    }
  }
}

}  // namespace
}  // namespace skelgrasp::grasping
