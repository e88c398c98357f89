// Local refinement of grasp hypotheses: never worse than the seed, finds the centred power grasp
// on a cylinder, deterministic, and without it the planner is unchanged.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/planning/planners.h"
#include "skelgrasp/grasping/planning/refinement.h"
#include "skelgrasp/skeleton/extraction.h"
#include "test_support.h"

namespace skelgrasp::grasping {
namespace {

// A margin recomputed from the same contacts must match the recorded one up to LP rounding.
constexpr double kMarginTolerance = 1e-9;

HypothesisParams hypothesisParamsFor(const HandModel& hand, bool power) {
  HypothesisParams hp;
  hp.quality.torsional_friction_m = hand.closingDefaults().torsional_friction_m;
  hp.extra_retreat_m = power ? hand.thresholds().power_retreat_m : 0.0;
  return hp;
}

// The default parameters with refinement switched on (it is off by default).
RefinementParams enabledRefinement() {
  RefinementParams on;
  on.enabled = true;
  return on;
}

struct Tally {
  int hypotheses = 0, seeds_kept = 0, refined_kept = 0, rescued = 0, moved = 0;
  double margin_before = 0, margin_after = 0;  // sums over grasps kept both ways
};

// Hypotheses at skeleton vertices (approach across the local tangent, random direction and roll,
// seeded): the refined outcome is never worse than its seed's, and its record is honest.
Tally checkNeverWorse(const TriangleMesh& mesh, const HandModel& hand, int max_hypotheses) {
  const GraspObject object(mesh);
  const auto skel = skeleton::extractSkeleton(mesh);
  EXPECT_TRUE(skel.status.ok()) << skel.status.message;
  GraspSimulator simulator(hand, object);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> angle(0, 2 * 3.14159265358979);
  Tally tally;
  RefinementParams refinement;
  refinement.enabled = true;
  for (const auto& segment : skel.skeleton.segments) {
    for (std::size_t i = 0; i + 1 < segment.vertices.size(); ++i) {
      if (tally.hypotheses >= max_hypotheses) return tally;
      const auto& v = skel.skeleton.vertices[segment.vertices[i]];
      const auto& next = skel.skeleton.vertices[segment.vertices[i + 1]];
      const Eigen::Vector3d tangent = (next.position - v.position).normalized();
      if (!tangent.allFinite()) continue;
      const Eigen::Vector3d side = anyPerpendicular(tangent);
      const double a = angle(rng);
      const Eigen::Vector3d approach =
          -(std::cos(a) * side + std::sin(a) * tangent.cross(side)).normalized();
      const double roll = 0.3 * (angle(rng) - 3.14159265358979);
      const Eigen::Vector3d spread =
          std::cos(roll) * tangent + std::sin(roll) * approach.cross(tangent);
      const Pose gcp = poseFromZY(v.position, approach, spread);
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (int p : v.surface_points) centroid += mesh.vertices[p];
      centroid = v.surface_points.empty() ? v.position
                                          : Eigen::Vector3d(centroid / v.surface_points.size());
      const bool power = tally.hypotheses % 2 == 0;
      const Preshape& preshape = hand.preshape(power ? "power" : "precision");
      const HypothesisParams hp = hypothesisParamsFor(hand, power);
      ++tally.hypotheses;

      const HypothesisOutcome closed = closeHypothesis(simulator, gcp, preshape, hp);
      const HypothesisOutcome seed = evaluateHypothesis(simulator, gcp, preshape, hp);
      const HypothesisOutcome refined = evaluateRefinedHypothesis(
          simulator, gcp, preshape, hp, RefinementFrame{tangent, centroid}, refinement);
      if (!closed.generated) {
        // Not closed: not refined, the same rejection.
        EXPECT_FALSE(refined.grasp);
        EXPECT_STREQ(refined.reason, seed.reason);
        continue;
      }
      const double seed_margin = signedClosureMargin(closed.grasp->contacts, object, hp.quality);
      tally.seeds_kept += seed.grasp.has_value();
      if (seed.grasp) {
        EXPECT_TRUE(refined.grasp) << "a kept seed was lost by refinement";
      }
      if (!refined.grasp) continue;
      ++tally.refined_kept;
      tally.rescued += !seed.grasp;
      EXPECT_TRUE(refined.grasp->refinement);
      if (!refined.grasp->refinement) continue;
      const GraspRefinement& record = *refined.grasp->refinement;
      EXPECT_LE(record.evaluations, refinement.max_evaluations);
      tally.moved += record.refined;
      // The seed's margin as recorded; force closure makes it positive only with closure.
      if (seed.grasp) {
        EXPECT_NEAR(record.margin_before, seed_margin, kMarginTolerance);
      }
      EXPECT_GE(record.margin_after, record.margin_before);
      EXPECT_NEAR(signedClosureMargin(refined.grasp->contacts, object, hp.quality),
                  record.margin_after, kMarginTolerance);
      EXPECT_TRUE(refined.grasp->force_closure);
      if (seed.grasp) {
        EXPECT_GE(record.margin_after, seed_margin - kMarginTolerance);
        tally.margin_before += seed_margin;
        tally.margin_after += record.margin_after;
      }
    }
  }
  return tally;
}

void printTally(const char* what, const Tally& t) {
  std::printf(
      "%s: %d hypotheses, %d seeds kept, %d kept after refinement (%d rescued near-misses, "
      "%d moved), margin of seeds kept both ways %.4f -> %.4f (sum)\n",
      what, t.hypotheses, t.seeds_kept, t.refined_kept, t.rescued, t.moved, t.margin_before,
      t.margin_after);
}

TEST(Refinement, NeverWorseThanTheSeedOnACapsule) {
  const HandModel hand = loadBuiltinHand("armar3");
  const Tally t = checkNeverWorse(geometry::shapes::makeCapsule(0.03, 0.12, 32), hand, 40);
  printTally("capsule", t);
  EXPECT_GE(t.refined_kept, t.seeds_kept);
  EXPECT_GT(t.seeds_kept, 0);
}

TEST(Refinement, NeverWorseThanTheSeedOnARealMesh) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  const HandModel hand = loadBuiltinHand("sdh");
  const TriangleMesh mesh = loadMesh(test::sharedDataDir() + "/objects/ycb/006_mustard_bottle.ply");
  const Tally t = checkNeverWorse(mesh, hand, 40);
  printTally("006_mustard_bottle", t);
  EXPECT_GE(t.refined_kept, t.seeds_kept);
}

// The analytic case: on a long cylinder the power grasp across the axis is best centred on it. A
// hypothesis 15 mm off to the side (across the approach and the axis) is refined back to within a
// few millimetres of the axis, with a margin at least the centred grasp's (up to a tolerance).
// The SDH: its three fingers close symmetrically about the GCP, and its margin across a 35 mm
// cylinder is highest from the axis outwards to the side its single finger is on (0.63 centred,
// 0.21 at +15 mm; docs/planning.md). ARMAR-III's margin is not: its closed fingers' contacts jump
// with the offset (0.14 centred, 0.33 at +15 mm), so it is no analytic case.
TEST(Refinement, CentresAnOffCentrePowerGraspOnACylinder) {
  const HandModel hand = loadBuiltinHand("sdh");
  const TriangleMesh mesh = geometry::shapes::makeCylinder(0.035, 0.2, 48, 10);
  const GraspObject object(mesh);
  GraspSimulator simulator(hand, object);
  const Preshape& preshape = hand.preshape("power");
  const HypothesisParams hp = hypothesisParamsFor(hand, true);
  const Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d approach = -Eigen::Vector3d::UnitX();
  const Eigen::Vector3d side = approach.cross(axis);  // across approach and axis
  const RefinementFrame frame{axis, Eigen::Vector3d::Zero()};
  constexpr double kOffCentreM = 0.015;
  constexpr double kCentredWithinM = 0.005;
  constexpr double kMarginSlack = 0.02;  // n l*, of a centred margin of 0.63

  const HypothesisOutcome centred = evaluateHypothesis(
      simulator, poseFromZY(Eigen::Vector3d::Zero(), approach, axis), preshape, hp);
  ASSERT_TRUE(centred.grasp) << centred.reason;
  const double centred_margin = signedClosureMargin(centred.grasp->contacts, object, hp.quality);

  const Pose off = poseFromZY(kOffCentreM * side, approach, axis);
  const HypothesisOutcome closed_off = closeHypothesis(simulator, off, preshape, hp);
  ASSERT_TRUE(closed_off.generated) << closed_off.reason;
  const double off_margin = signedClosureMargin(closed_off.grasp->contacts, object, hp.quality);
  const HypothesisOutcome refined =
      evaluateRefinedHypothesis(simulator, off, preshape, hp, frame, enabledRefinement());
  ASSERT_TRUE(refined.grasp) << refined.reason;
  const auto& record = *refined.grasp->refinement;
  std::printf(
      "centred margin %.4f, off-centre %.4f, refined %.4f after %d evaluations; moves "
      "tangent %.4f lateral %.4f roll %.3f standoff %.4f\n",
      centred_margin, off_margin, record.margin_after, record.evaluations, record.tangent_m,
      record.lateral_m, record.roll_rad, record.standoff_m);
  EXPECT_TRUE(record.refined);
  const Eigen::Vector3d position = refined.grasp->gcp_pose.translation();
  EXPECT_LT(std::abs(position.dot(side)), kCentredWithinM) << position.transpose();
  EXPECT_GE(record.margin_after, centred_margin - kMarginSlack);
  EXPECT_GE(record.margin_after, off_margin);
}

std::vector<Grasp> planCapsule(const RefinementParams& refinement) {
  const HandModel hand = loadBuiltinHand("armar3");
  const TriangleMesh mesh = geometry::shapes::makeCapsule(0.03, 0.12, 32);
  const GraspObject object(mesh);
  const auto skel = skeleton::extractSkeleton(mesh);
  SkeletonPlannerParams params;
  params.vertex_distance_m = 0.02;
  params.refinement = refinement;
  params.centre_candidates = false;  // refinement works on the skeleton strategies' hypotheses
  params.surface_candidates = 0;
  return planSkeletonGrasps(hand, object, skel.skeleton, params).grasps;
}

TEST(Refinement, PlanningIsDeterministic) {
  const auto first = planCapsule(enabledRefinement());
  const auto second = planCapsule(enabledRefinement());
  ASSERT_EQ(first.size(), second.size());
  ASSERT_FALSE(first.empty());
  for (std::size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(first[i].epsilon, second[i].epsilon);
    EXPECT_TRUE(first[i].hand_pose.isApprox(second[i].hand_pose, 0));
    ASSERT_TRUE(first[i].refinement && second[i].refinement);
    EXPECT_EQ(first[i].refinement->margin_after, second[i].refinement->margin_after);
    EXPECT_EQ(first[i].refinement->evaluations, second[i].refinement->evaluations);
  }
}

// Off: no grasp carries a refinement record. A budget of 0 plans the same grasps (the seeds), each
// recording its margin and that it was not moved.
TEST(Refinement, OffPlansAsWithoutRefinement) {
  RefinementParams off;
  off.enabled = false;
  RefinementParams zero = enabledRefinement();
  zero.max_evaluations = 0;
  const auto a = planCapsule(off);
  const auto b = planCapsule(zero);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_FALSE(a.empty());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_FALSE(a[i].refinement);
    ASSERT_TRUE(b[i].refinement);
    EXPECT_FALSE(b[i].refinement->refined);
    EXPECT_EQ(b[i].refinement->evaluations, 0);
    EXPECT_EQ(b[i].refinement->margin_before, b[i].refinement->margin_after);
    EXPECT_GT(b[i].refinement->margin_after, 0);
    EXPECT_EQ(a[i].epsilon, b[i].epsilon);
    EXPECT_TRUE(a[i].hand_pose.isApprox(b[i].hand_pose, 0));
    EXPECT_EQ(a[i].contacts.size(), b[i].contacts.size());
  }
}

}  // namespace
}  // namespace skelgrasp::grasping
