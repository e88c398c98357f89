// Grasps judged on the true object (evaluation/true_object.h): a grasp planned on the true mesh,
// sent into a table view's camera frame and mapped back with the view's transform, keeps its
// score; the figures of the scan-to-grasp benchmark follow their definitions.
#include "skelgrasp/evaluation/true_object.h"

#include <gtest/gtest.h>

#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/perception/table_view.h"
#include "skelgrasp/ranking/plan_grasps.h"

namespace skelgrasp::evaluation {
namespace {

constexpr int kSamples = 12;  // enough to exercise robustness, few enough for a unit test

// A generated bottle turned by an odd rotation, so that no facet meets the hand's frames in an
// exact tie that the last bits of a round trip could break.
TriangleMesh turnedBottle() {
  TriangleMesh mesh = geometry::shapes::makeNamedShape("bottle");
  mesh.transform(Pose(Eigen::AngleAxisd(0.37, Eigen::Vector3d(0.3, -0.5, 0.8).normalized())));
  return mesh;
}

TEST(TrueObject, AGraspSentToTheCameraFrameAndBackKeepsItsScore) {
  const TriangleMesh mesh = turnedBottle();
  const auto hand = grasping::loadBuiltinHand("parallel_gripper");
  const grasping::GraspObject object(mesh);
  ranking::PlanOptions options;
  options.skeleton_planner.max_grasps = 6;
  options.ranking.robustness.samples = kSamples;
  options.ranking.top_k = 3;
  const ranking::GraspPlan plan = ranking::planGrasps(object, hand, options);
  ASSERT_TRUE(plan.status.ok()) << plan.status.message;

  perception::TableViewParams views;
  views.views = 1;
  views.camera.noise.enabled = false;
  const auto scene = perception::renderTableViews(mesh, views);
  ASSERT_TRUE(scene.status.ok());
  const Pose object_from_scan = scene.views.front().object_from_scan;

  TrueObjectParams judge;
  judge.score.robustness.samples = kSamples;
  std::vector<ClaimedGrasp> direct, round_trip;
  for (const auto& g : plan.grasps) {
    if (!g.robustness) continue;
    ClaimedGrasp c;
    c.claimed_r = g.robustness->r;
    c.placement = {nlohmann::json(g.id), g.hand_pose, g.preshape};
    direct.push_back(c);
    // What a run on the view would report (the camera's frame), mapped back as the benchmark does.
    const Pose in_scan = object_from_scan.inverse() * g.hand_pose;
    c.placement.hand_pose = object_from_scan * in_scan;
    round_trip.push_back(c);
  }
  ASSERT_FALSE(direct.empty());
  // The camera is about a metre away: the round trip moves the pose in its last bits only.
  for (std::size_t i = 0; i < direct.size(); ++i) {
    EXPECT_LT((direct[i].placement.hand_pose.matrix() - round_trip[i].placement.hand_pose.matrix())
                  .cwiseAbs()
                  .maxCoeff(),
              1e-12);
  }
  const auto a = judgeOnTrueObject(hand, object, nullptr, direct, judge);
  const auto b = judgeOnTrueObject(hand, object, nullptr, round_trip, judge);
  ASSERT_EQ(a.size(), direct.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_FALSE(b[i].starts_inside);
    EXPECT_EQ(a[i].true_force_closure, b[i].true_force_closure);
    EXPECT_NEAR(a[i].true_r, b[i].true_r, 1.0 / kSamples + 1e-9);
    // The true mesh is the mesh planned on: the true r is the r the plan claimed (same criterion,
    // seed and grasp-index convention), up to a sample.
    EXPECT_NEAR(b[i].true_r, *b[i].claimed_r, 1.0 / kSamples + 1e-9);
    EXPECT_TRUE(b[i].true_force_closure);
  }
}

TEST(TrueObject, AHandInsideTheObjectStartsInside) {
  const TriangleMesh mesh = geometry::shapes::makeNamedShape("box");
  const auto hand = grasping::loadBuiltinHand("parallel_gripper");
  const grasping::GraspObject object(mesh);
  ClaimedGrasp c;
  c.placement = {nullptr, Pose(Eigen::Translation3d(mesh.bounds().center())),
                 hand.preshapes().begin()->first};
  c.claimed_r = 0.9;
  TrueObjectParams judge;
  judge.score.robustness.samples = 2;
  const auto judged = judgeOnTrueObject(hand, object, nullptr, {c}, judge);
  ASSERT_EQ(judged.size(), 1u);
  EXPECT_TRUE(judged[0].starts_inside);
  EXPECT_EQ(judged[0].true_r, 0.0);
  EXPECT_FALSE(judged[0].nominal_holds.has_value());  // no physics judge asked for
}

TEST(TrueObject, FiguresFollowTheirDefinitions) {
  auto grasp = [](std::optional<double> claimed, double truth, bool inside, bool holds) {
    TrueGraspJudgement j;
    j.claimed_r = claimed;
    j.true_r = truth;
    j.starts_inside = inside;
    j.nominal_holds = holds;
    return j;
  };
  ScanToGraspCase a, b, c;  // two views of a bottle, one of a plate
  a.object = b.object = "bottle";
  c.object = "plate";
  a.returned = 12;  // more returned than judged: the top two
  a.top = {grasp(0.9, 0.5, false, true), grasp(0.7, 0.3, true, false)};
  a.run_s = 2;
  b.view = 1;
  b.returned = 1;
  b.top = {grasp(std::nullopt, 1.0, false, true)};  // not scored by the run
  b.run_s = 4;
  c.run_s = 3;  // no grasp
  const ScanToGraspFigures f = scanToGraspFigures({a, b, c});
  EXPECT_EQ(f.objects, 2u);
  EXPECT_EQ(f.objects_with_grasps, 1u);
  EXPECT_EQ(f.cases, 3u);
  EXPECT_EQ(f.cases_with_grasps, 2u);
  // Claimed per view: 0.8, 0 (none scored), 0 (no grasp); true: 0.4, 1.0, 0. Per object: the
  // bottle 0.4 claimed and 0.7 true, the plate 0 and 0.
  EXPECT_DOUBLE_EQ(f.median_claimed_r, 0.2);
  EXPECT_DOUBLE_EQ(f.median_true_r, 0.35);
  EXPECT_EQ(f.top_grasps, 3u);
  EXPECT_EQ(f.starts_inside, 1u);
  ASSERT_TRUE(f.hold_rate);
  EXPECT_DOUBLE_EQ(*f.hold_rate, 2.0 / 3.0);
  ASSERT_TRUE(f.claimed_minus_true);
  EXPECT_EQ(f.claimed_pairs, 2u);
  EXPECT_NEAR(*f.claimed_minus_true, (0.9 + 0.7 - 0.5 - 0.3) / 2, 1e-12);
  EXPECT_DOUBLE_EQ(f.median_run_s, 3.0);
  EXPECT_DOUBLE_EQ(median({}), 0.0);
  EXPECT_DOUBLE_EQ(median({3, 1, 2, 10}), 2.5);
}

}  // namespace
}  // namespace skelgrasp::evaluation
