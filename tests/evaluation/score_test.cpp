#include "skelgrasp/evaluation/score.h"

#include <gtest/gtest.h>

#include <cmath>

#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/planning/planners.h"
#include "skelgrasp/skeleton/extraction.h"

namespace skelgrasp::evaluation {
namespace {

using grasping::GraspPlacement;

constexpr double kRelativeEpsilonTolerance = 1e-9;
constexpr int kSamples = 12;  // enough to exercise robustness, few enough for a unit test

// A plan of the skeleton planner with `hand` on `mesh`, a few grasps.
grasping::PlanResult planFew(const grasping::HandModel& hand, const grasping::GraspObject& object,
                             const TriangleMesh& mesh, std::size_t grasps) {
  const auto skeleton = skeleton::extractSkeleton(mesh);
  EXPECT_TRUE(skeleton.status.ok()) << skeleton.status.message;
  grasping::SkeletonPlannerParams params;
  params.max_grasps = grasps;
  return grasping::planSkeletonGrasps(hand, object, skeleton.skeleton, params);
}

// The plan's grasps with their exact poses. (Through grasps.json the rotation goes through a
// quaternion and changes in its last bits; on a generated capsule, whose facets meet the hand's
// axis-aligned frames in exact ties, that can move a contact patch: the CLI test compares plan and
// score on real meshes.)
std::vector<GraspPlacement> placementsOf(const grasping::PlanResult& plan) {
  std::vector<GraspPlacement> placements;
  for (const auto& g : plan.grasps) placements.push_back({g.id, g.hand_pose, g.preshape});
  return placements;
}

class ScorePlan : public ::testing::TestWithParam<const char*> {};

// score reproduces plan: the same contacts, force closure and epsilon for plan's own grasps at
// plan's friction, and ranking::evaluateRobustness' r with grasp index 0 and the same seed.
TEST_P(ScorePlan, ReproducesPlansNumbersForPlansGrasps) {
  const auto hand = grasping::loadBuiltinHand(GetParam());
  const TriangleMesh mesh = geometry::shapes::makeNamedShape("capsule");
  const grasping::GraspObject object(mesh);
  const auto plan = planFew(hand, object, mesh, 3);
  ASSERT_FALSE(plan.grasps.empty()) << GetParam();
  ScoreParams params;
  params.frictions = {grasping::QualityParams{}.friction, 0.5};
  params.robustness.samples = kSamples;
  const auto placements = placementsOf(plan);
  const ScoreResult result = scoreGrasps(hand, object, placements, params);
  ASSERT_TRUE(result.status.ok()) << result.status.message;
  ASSERT_EQ(result.grasps.size(), plan.grasps.size());
  EXPECT_EQ(result.closed, plan.grasps.size());
  grasping::GraspSimulator simulator(hand, object);
  for (std::size_t i = 0; i < plan.grasps.size(); ++i) {
    const auto& planned = plan.grasps[i];
    const GraspScore& scored = result.grasps[i];
    SCOPED_TRACE(::testing::Message() << GetParam() << " grasp " << i);
    EXPECT_EQ(scored.id, planned.id);
    EXPECT_EQ(scored.preshape, planned.preshape);
    EXPECT_TRUE(scored.closing_failure.empty()) << scored.closing_failure;
    EXPECT_EQ(scored.contacts.size(), planned.contacts.size());
    ASSERT_EQ(scored.by_friction.size(), 2u);
    const FrictionScore& at_plan = scored.by_friction[0];
    EXPECT_EQ(at_plan.force_closure, planned.force_closure);
    EXPECT_NEAR(at_plan.epsilon, planned.epsilon, kRelativeEpsilonTolerance * planned.epsilon);
    // More friction never loses force closure (wider cones hold every wrench the narrow ones do).
    if (at_plan.force_closure) {
      EXPECT_TRUE(scored.by_friction[1].force_closure);
    }
    for (const auto& at : scored.by_friction) {
      ASSERT_TRUE(at.robustness);
      const ranking::RobustnessResult& r = *at.robustness;
      EXPECT_EQ(r.samples, kSamples);
      EXPECT_LE(0.0, r.wilson_low);
      EXPECT_LE(r.wilson_low, r.score);
      EXPECT_LE(r.score, r.wilson_high);
      EXPECT_LE(r.wilson_high, 1.0);
    }
    // The r plan and run attach: ranking::evaluateRobustness of plan's grasp, index 0, the same
    // seed.
    ranking::RobustnessParams robustness = params.robustness;
    robustness.quality.friction = params.frictions[0];
    robustness.quality.torsional_friction_m = hand.closingDefaults().torsional_friction_m;
    const auto expected = ranking::evaluateRobustness(simulator, planned, robustness, 0);
    EXPECT_EQ(at_plan.robustness->force_closure, expected.force_closure);
    EXPECT_EQ(at_plan.robustness->collisions, expected.collisions);
  }
}

INSTANTIATE_TEST_SUITE_P(Hands, ScorePlan, ::testing::Values("armar3", "sdh", "shadow"));

TEST(Score, IsDeterministicForASeedAndSkipsRobustnessWhenAsked) {
  const auto hand = grasping::loadBuiltinHand("sdh");
  const TriangleMesh mesh = geometry::shapes::makeNamedShape("capsule");
  const grasping::GraspObject object(mesh);
  const auto placements = placementsOf(planFew(hand, object, mesh, 2));
  ASSERT_FALSE(placements.empty());
  ScoreParams params;
  params.robustness.samples = kSamples;
  params.robustness.seed = 7;
  const auto a = scoreGrasps(hand, object, placements, params);
  const auto b = scoreGrasps(hand, object, placements, params);
  for (std::size_t i = 0; i < placements.size(); ++i) {
    EXPECT_EQ(a.grasps[i].by_friction[0].robustness->force_closure,
              b.grasps[i].by_friction[0].robustness->force_closure);
    EXPECT_EQ(a.grasps[i].by_friction[0].robustness->collisions,
              b.grasps[i].by_friction[0].robustness->collisions);
  }
  params.compute_robustness = false;
  const auto quick = scoreGrasps(hand, object, placements, params);
  for (std::size_t i = 0; i < placements.size(); ++i) {
    EXPECT_FALSE(quick.grasps[i].by_friction[0].robustness);
    EXPECT_EQ(quick.grasps[i].by_friction[0].epsilon, a.grasps[i].by_friction[0].epsilon);
  }
  const nlohmann::json j = scoreToJson(quick, params, hand, "capsule.ply", "grasps.json");
  EXPECT_EQ(j["schema"], "skelgrasp.score/1");
  EXPECT_EQ(j["grasps"].size(), placements.size());
  EXPECT_TRUE(j["grasps"][0]["closure"][0]["robustness"].is_null());
  EXPECT_TRUE(j["parameters"]["robustness"].is_null());
}

TEST(Score, AHandInsideTheObjectIsAClosingFailureNotAnError) {
  const auto hand = grasping::loadBuiltinHand("sdh");
  const grasping::GraspObject object(geometry::shapes::makeNamedShape("capsule"));
  GraspPlacement inside;  // the hand's root at the object's centre: it starts in collision
  inside.id = "foreign-1";
  inside.preshape = grasping::defaultPreshapeName(hand);
  const auto result = scoreGrasps(hand, object, {inside});
  EXPECT_EQ(result.status.code, StatusCode::kNoResult);
  ASSERT_EQ(result.grasps.size(), 1u);
  EXPECT_EQ(result.grasps[0].closing_failure, "start_collision");
  EXPECT_EQ(result.grasps[0].id, "foreign-1");
  EXPECT_FALSE(result.grasps[0].by_friction[0].force_closure);
  EXPECT_FALSE(result.grasps[0].by_friction[0].robustness);
  EXPECT_EQ(scoreGrasps(hand, object, {}).status.code, StatusCode::kNoResult);
}

TEST(Score, RefusesBadParameters) {
  const auto hand = grasping::loadBuiltinHand("sdh");
  const grasping::GraspObject object(geometry::shapes::makeNamedShape("capsule"));
  ScoreParams none;
  none.frictions.clear();
  EXPECT_THROW(scoreGrasps(hand, object, {}, none), InvalidArgument);
  ScoreParams negative;
  negative.frictions = {0.35, -0.1};
  EXPECT_THROW(scoreGrasps(hand, object, {}, negative), InvalidArgument);
  ScoreParams too_many;
  too_many.frictions.assign(kMaxScoreFrictions + 1, 0.5);
  EXPECT_THROW(scoreGrasps(hand, object, {}, too_many), InvalidArgument);
  ScoreParams no_samples;
  no_samples.robustness.samples = 0;
  EXPECT_THROW(scoreGrasps(hand, object, {}, no_samples), InvalidArgument);
}

// The grasps-file reader score and export share.
TEST(GraspsFile, ReadsPlanAndRunFilesAndSaysWhatIsWrong) {
  const auto hand = grasping::loadBuiltinHand("sdh");
  const nlohmann::json pose = {{"position", {0.1, 0, 0}}, {"quaternion_wxyz", {1, 0, 0, 0}}};
  const nlohmann::json plan = {{"schema", "skelgrasp.grasps/1"},
                               {"hand", "sdh"},
                               {"grasps", {{{"id", 4}, {"hand_pose", pose}}}}};
  const auto read = grasping::readGraspPlacements(plan, hand);
  ASSERT_EQ(read.size(), 1u);
  EXPECT_EQ(read[0].id, 4);
  EXPECT_EQ(read[0].preshape, "power");  // the default preshape
  EXPECT_NEAR(read[0].hand_pose.translation().x(), 0.1, 1e-15);

  nlohmann::json run = {{"schema", "skelgrasp.run/2"},
                        {"objects", {{{"id", 0}}, {{"id", 3}}}},
                        {"grasps",
                         {{{"id", 0}, {"object", 0}, {"hand_pose", pose}},
                          {{"id", 1}, {"object", 3}, {"hand_pose", pose}},
                          {{"id", 2}, {"object", 3}, {"hand_pose", pose}}}}};
  const auto of3 = grasping::readGraspPlacements(run, hand, 3);
  ASSERT_EQ(of3.size(), 2u);
  EXPECT_EQ(of3[0].id, 1);
  auto message = [&](const nlohmann::json& file, std::optional<long long> object = {}) {
    try {
      grasping::readGraspPlacements(file, hand, object);
    } catch (const InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(run).find("2 objects (ids 0, 3)"), std::string::npos) << message(run);
  EXPECT_NE(message(run, 5).find("no object 5"), std::string::npos) << message(run, 5);
  EXPECT_NE(message(plan, 0).find("run files only"), std::string::npos);
  nlohmann::json foreign = plan;
  foreign["schema"] = "other.tool/1";
  EXPECT_NE(message(foreign).find("schema"), std::string::npos) << message(foreign);
  nlohmann::json other_hand = plan;
  other_hand["hand"] = "armar3";
  EXPECT_NE(message(other_hand).find("planned with hand"), std::string::npos);
  nlohmann::json no_pose = plan;
  no_pose["grasps"][0].erase("hand_pose");
  EXPECT_NE(message(no_pose).find("grasp 0 has no \"hand_pose\""), std::string::npos)
      << message(no_pose);
  nlohmann::json zero_quaternion = plan;
  zero_quaternion["grasps"][0]["hand_pose"]["quaternion_wxyz"] = {0, 0, 0, 0};
  EXPECT_NE(message(zero_quaternion).find("quaternion has length 0, not 1"), std::string::npos)
      << message(zero_quaternion);
  // The tolerance of --pose: a quaternion off unit length by more is refused, not normalised.
  nlohmann::json long_quaternion = plan;
  long_quaternion["grasps"][0]["hand_pose"]["quaternion_wxyz"] = {1.01, 0, 0, 0};
  EXPECT_NE(message(long_quaternion).find("length 1.01"), std::string::npos)
      << message(long_quaternion);
  nlohmann::json far = plan;
  far["grasps"][0]["hand_pose"]["position"] = {0, 0, 1001};
  EXPECT_NE(message(far).find("limit of 100 m"), std::string::npos) << message(far);
  nlohmann::json bad_preshape = plan;
  bad_preshape["grasps"][0]["preshape"] = "fist";
  EXPECT_NE(message(bad_preshape).find("grasp 0"), std::string::npos) << message(bad_preshape);
}

}  // namespace
}  // namespace skelgrasp::evaluation
