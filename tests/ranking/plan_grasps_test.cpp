#include "skelgrasp/ranking/plan_grasps.h"

#include <gtest/gtest.h>

#include <vector>

#include "planned_object.h"
#include "skelgrasp/geometry/shapes.h"

namespace skelgrasp::ranking {
namespace {

using test_fixtures::cylinder;
using test_fixtures::fewSamples;
using test_fixtures::Planned;

// The cylinder's plan (planned_object.h) as one call: its planner parameters and a small ranking.
PlanOptions cylinderOptions(const Planned& p) {
  PlanOptions options;
  options.skeleton_planner = p.params;
  options.ranking = fewSamples(8, 2);
  options.ranking.refinement.enabled = false;
  return options;
}

void expectSameGrasps(const std::vector<grasping::Grasp>& a,
                      const std::vector<grasping::Grasp>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].id, b[i].id) << i;
    EXPECT_EQ(a[i].epsilon, b[i].epsilon) << i;
    EXPECT_TRUE(a[i].hand_pose.isApprox(b[i].hand_pose, 0.0)) << i;
    ASSERT_EQ(a[i].robustness.has_value(), b[i].robustness.has_value()) << i;
    if (a[i].robustness) EXPECT_EQ(a[i].robustness->r, b[i].robustness->r) << i;
  }
}

TEST(PlanGrasps, IsTheSkeletonThePlannerAndTheRankingInOneCall) {
  const Planned& p = cylinder();
  const PlanOptions options = cylinderOptions(p);
  const GraspPlan plan = planGrasps(p.mesh, p.hand, options);
  ASSERT_TRUE(plan.status.ok()) << plan.status.message;
  EXPECT_FALSE(plan.skeleton_failed);
  ASSERT_TRUE(plan.skeleton.has_value());
  EXPECT_TRUE(plan.skeleton->status.ok());
  EXPECT_EQ(plan.planner, p.plan.planner);
  EXPECT_EQ(plan.summary.poses, p.plan.summary.poses);
  // The same grasps as the stages called one by one.
  const auto ranked =
      rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, options.ranking);
  expectSameGrasps(plan.grasps, ranked.grasps);
  EXPECT_TRUE(plan.ranking.grasps.empty());
  EXPECT_EQ(plan.ranking.scored, 2u);
  EXPECT_EQ(plan.ranking.scores, ranked.scores);
  EXPECT_EQ(plan.ranking.order, ranked.order);
  EXPECT_TRUE(plan.timing.skeleton_s.has_value());
  EXPECT_TRUE(plan.timing.regularise_s.has_value());
  EXPECT_GT(plan.timing.planning_s, 0.0);
  EXPECT_GE(plan.timing.ranking_s, plan.ranking.time_s);
}

TEST(PlanGrasps, PlansOnAGivenSkeletonAndObject) {
  const Planned& p = cylinder();
  const auto skel = skeleton::extractSkeleton(p.mesh);
  ASSERT_TRUE(skel.status.ok());
  PlanInputs inputs;
  inputs.skeleton = &skel;
  const GraspPlan given = planGrasps(*p.object, p.hand, cylinderOptions(p), inputs);
  const GraspPlan own = planGrasps(p.mesh, p.hand, cylinderOptions(p));
  EXPECT_FALSE(given.skeleton.has_value()) << "the caller's skeleton is not copied";
  expectSameGrasps(given.grasps, own.grasps);
  // The given skeleton's times are the plan's.
  ASSERT_TRUE(given.timing.regularise_s.has_value());
  EXPECT_EQ(*given.timing.regularise_s, skel.timing.regularise_s);
}

TEST(PlanGrasps, SurfacePlannerNeedsNoSkeletonAndKeepsEpsilonOrderWithoutRanking) {
  const Planned& p = cylinder();
  PlanOptions options;
  options.planner = Planner::kSurface;
  options.surface_planner.max_hypotheses = 30;
  options.ranking.enabled = false;
  const GraspPlan plan = planGrasps(*p.object, p.hand, options);
  EXPECT_FALSE(plan.skeleton.has_value());
  EXPECT_FALSE(plan.timing.skeleton_s.has_value());
  EXPECT_FALSE(plan.timing.regularise_s.has_value());
  EXPECT_FALSE(plan.ranking.enabled);
  const auto planned = grasping::planSurfaceGrasps(p.hand, *p.object, options.surface_planner);
  expectSameGrasps(plan.grasps, planned.grasps);
}

TEST(PlanGrasps, AMeshTheSkeletonStageCannotProcessIsInTheStatus) {
  // One open triangle: without regularisation it has no skeleton.
  TriangleMesh flat;
  flat.vertices = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.05, 0, 0),
                   Eigen::Vector3d(0, 0.05, 0)};
  flat.faces = {Eigen::Vector3i(0, 1, 2)};
  PlanOptions options;
  options.skeleton.regularisation.method = geometry::RegularisationMethod::kNone;
  const GraspPlan plan = planGrasps(flat, cylinder().hand, options);
  EXPECT_TRUE(plan.skeleton_failed);
  EXPECT_EQ(plan.status.code, StatusCode::kInvalidInput);
  EXPECT_FALSE(plan.status.message.empty());
  ASSERT_TRUE(plan.skeleton.has_value());
  EXPECT_EQ(plan.skeleton->status.message, plan.status.message);
  EXPECT_TRUE(plan.grasps.empty());
}

TEST(PlanGrasps, TrustScalesTheRankScores) {
  const Planned& p = cylinder();
  PlanInputs inputs;
  std::size_t calls = 0;
  inputs.trust = [&](const grasping::Grasp&) {
    ++calls;
    return 0.5;
  };
  const GraspPlan trusted = planGrasps(*p.object, p.hand, cylinderOptions(p), inputs);
  const GraspPlan plain = planGrasps(*p.object, p.hand, cylinderOptions(p));
  EXPECT_GE(calls, p.plan.grasps.size());
  expectSameGrasps(trusted.grasps, plain.grasps);
  ASSERT_EQ(trusted.ranking.scores.size(), plain.ranking.scores.size());
  for (std::size_t i = 0; i < plain.ranking.scores.size(); ++i)
    EXPECT_DOUBLE_EQ(trusted.ranking.scores[i], 0.5 * plain.ranking.scores[i]) << i;
}

TEST(PlanGrasps, CallerMistakesThrowBeforeAnyWork) {
  PlanOptions options;
  options.ranking.robustness.samples = 0;
  EXPECT_THROW(options.validate(), InvalidArgument);
  EXPECT_THROW(planGrasps(cylinder().mesh, cylinder().hand, options), InvalidArgument);
  PlanOptions unknown;
  unknown.planner = static_cast<Planner>(7);
  EXPECT_THROW(unknown.validate(), InvalidArgument);
  EXPECT_THROW(planGrasps(TriangleMesh{}, cylinder().hand, PlanOptions{}), InvalidArgument);
}

TEST(PlanGrasps, HypothesisIsTheChosenPlanners) {
  PlanOptions options;
  options.skeleton_planner.hypothesis.min_epsilon = 0.01;
  options.surface_planner.hypothesis.min_epsilon = 0.02;
  EXPECT_EQ(options.hypothesis().min_epsilon, 0.01);
  options.planner = Planner::kSurface;
  EXPECT_EQ(options.hypothesis().min_epsilon, 0.02);
}

}  // namespace
}  // namespace skelgrasp::ranking
