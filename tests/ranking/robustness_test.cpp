#include "skelgrasp/ranking/robustness.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <set>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/pose.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/planning/planners.h"
#include "skelgrasp/skeleton/extraction.h"

namespace skelgrasp::ranking {
namespace {

using grasping::Grasp;

// A kept grasp at a known pose: closes the hand there and scores it.
Grasp graspAt(grasping::GraspSimulator& sim, const Pose& gcp, const std::string& preshape_name) {
  const auto& preshape = sim.hand().preshape(preshape_name);
  Grasp g;
  g.preshape = preshape_name;
  g.gcp_pose = gcp;
  g.hand_pose = sim.handPoseForGcp(gcp, preshape);
  const auto closed = sim.close(g.hand_pose, preshape);
  g.joints = closed.joints;
  g.contacts = closed.contacts;
  return g;
}

// The skeleton planner's best `max_grasps` grasps of `hand` on `mesh` (`object` built from it).
std::vector<Grasp> plannedGrasps(const grasping::HandModel& hand,
                                 const grasping::GraspObject& object, const TriangleMesh& mesh,
                                 std::size_t max_grasps) {
  grasping::SkeletonPlannerParams params;
  params.max_grasps = max_grasps;
  return grasping::planSkeletonGrasps(hand, object, skeleton::extractSkeleton(mesh).skeleton,
                                      params)
      .grasps;
}

TEST(Robustness, WilsonIntervalBracketsTheRate) {
  const auto [low, high] = wilsonInterval(90, 100);
  EXPECT_LT(low, 0.9);
  EXPECT_GT(high, 0.9);
  EXPECT_NEAR(low, 0.825, 0.005);  // textbook value for 90/100
  EXPECT_NEAR(high, 0.945, 0.005);
  EXPECT_EQ(wilsonInterval(0, 10).first, 0.0);
  EXPECT_NEAR(wilsonInterval(10, 10).second, 1.0, 1e-12);
}

// The interval contains the rate exactly, also at 0 and 1 where its bound is the rate itself
// (rounding once put the upper bound of 10/10 an ulp below 1).
TEST(Robustness, WilsonIntervalContainsTheRateExactly) {
  for (int trials : {1, 3, 10, 30, 50, 100, 1000}) {
    for (int k = 0; k <= trials; ++k) {
      const double rate = static_cast<double>(k) / trials;
      const auto [low, high] = wilsonInterval(k, trials);
      EXPECT_LE(low, rate) << k << "/" << trials;
      EXPECT_GE(high, rate) << k << "/" << trials;
      EXPECT_GE(low, 0.0);
      EXPECT_LE(high, 1.0);
    }
    EXPECT_EQ(wilsonInterval(trials, trials).second, 1.0);
    EXPECT_EQ(wilsonInterval(0, trials).first, 0.0);
  }
}

TEST(Robustness, UnsetSigmasAreTheVariantsDefaults) {
  const auto hand = grasping::loadBuiltinHand("parallel_gripper");
  const grasping::GraspObject box(geometry::shapes::makeBox({0.05, 0.09, 0.16}, 2));
  grasping::GraspSimulator sim(hand, box);
  const Grasp g = graspAt(sim, poseFromZY({0, 0.035, 0}, {0, -1, 0}, {0, 0, 1}), "precision");
  RobustnessParams unset;
  unset.samples = 12;
  RobustnessParams paper = unset;  // the paper variant's 10 mm and 5 degrees, stated
  paper.position_sigma_m = 0.010;
  paper.orientation_sigma_rad = radiansFromDegrees(5.0);
  const auto a = evaluateRobustness(sim, g, unset), b = evaluateRobustness(sim, g, paper);
  EXPECT_EQ(a.force_closure, b.force_closure);
  EXPECT_EQ(a.collisions, b.collisions);
  RobustnessParams negative = unset;
  negative.position_sigma_m = -0.001;
  EXPECT_THROW(evaluateRobustness(sim, g, negative), InvalidArgument);
}

TEST(Robustness, DeepPowerGraspAroundACylinderIsRobust) {
  const auto hand = grasping::loadBuiltinHand("armar3");
  const TriangleMesh mesh = geometry::shapes::makeCylinder(0.035, 0.2, 48, 10);
  const grasping::GraspObject object(mesh);
  const auto skel = skeleton::extractSkeleton(mesh);
  grasping::SkeletonPlannerParams params;
  params.max_grasps = 1;
  params.power = true;
  params.precision = false;
  const auto plan = grasping::planSkeletonGrasps(hand, object, skel.skeleton, params);
  ASSERT_FALSE(plan.grasps.empty());
  grasping::GraspSimulator sim(hand, object);
  RobustnessParams rp;
  rp.samples = 60;
  const auto r = evaluateRobustness(sim, plan.grasps.front(), rp);
  EXPECT_GT(r.score, 0.7) << r.force_closure << " of " << r.samples << ", " << r.collisions
                          << " collisions";
  EXPECT_LE(r.wilson_low, r.score);
  EXPECT_GE(r.wilson_high, r.score);
}

TEST(Robustness, FingertipGraspOnAThinEdgeIsFragile) {
  // Gripper jaws overlapping a 6 mm plate by only 4 mm at its edge: a 10 mm error loses it.
  const auto hand = grasping::loadBuiltinHand("parallel_gripper");
  const grasping::GraspObject plate(geometry::shapes::makeBox({0.12, 0.12, 0.006}, 4));
  grasping::GraspSimulator sim(hand, plate);
  const double tip_beyond_gcp = 0.1121 - 0.1034;  // fingertip reach past the gcp (m)
  const Grasp g = graspAt(
      sim, poseFromZY({0.06 - 0.004 + tip_beyond_gcp, 0, 0}, {-1, 0, 0}, {0, 1, 0}), "precision");
  std::set<std::string> jaws;  // each jaw's patch corners, or its single contact
  for (const auto& c : g.contacts) jaws.insert(c.link);
  ASSERT_EQ(jaws.size(), 2u);
  grasping::QualityParams soft;
  soft.torsional_friction_m = hand.closingDefaults().torsional_friction_m;
  ASSERT_TRUE(grasping::evaluateGrasp(g.contacts, plate, soft).force_closure);
  RobustnessParams rp;
  rp.samples = 60;
  rp.quality = soft;
  rp.variant = RobustnessVariant::kPaper;  // the object held still
  const auto r = evaluateRobustness(sim, g, rp);
  EXPECT_LT(r.score, 0.5) << r.force_closure << " of " << r.samples;
  // Free to move, the plate is pushed by the first jaw onto the other one: never less robust.
  rp.variant = RobustnessVariant::kSettled;
  EXPECT_GE(evaluateRobustness(sim, g, rp).score, r.score);
}

TEST(Robustness, IsZeroWhenEveryPerturbedPoseCollides) {
  // The hand sits in the middle of a large block: every perturbation still intersects it.
  const auto hand = grasping::loadBuiltinHand("sdh");
  const grasping::GraspObject block(geometry::shapes::makeBox({1.0, 1.0, 1.0}));
  grasping::GraspSimulator sim(hand, block);
  Grasp g;
  g.preshape = "power";
  g.hand_pose = Pose::Identity();
  grasping::Contact c;
  c.point = Eigen::Vector3d(0.5, 0, 0);
  g.contacts = {c};
  RobustnessParams rp;
  rp.samples = 25;
  const auto r = evaluateRobustness(sim, g, rp);
  EXPECT_EQ(r.collisions, 25);
  EXPECT_EQ(r.closing_failures + r.no_force_closure, 0);
  EXPECT_EQ(r.score, 0.0);
}

// ARMAR-III's best planned grasp on a capsule (`g`), with a simulator over it (`sim`): the subject
// of the tests that compare evaluations of one grasp.
class CapsuleGrasp : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_FALSE(grasps_.empty()); }
  const grasping::HandModel hand_ = grasping::loadBuiltinHand("armar3");
  const grasping::GraspObject object_{geometry::shapes::makeCapsule(0.025, 0.12)};
  const std::vector<Grasp> grasps_ = plannedGrasps(hand_, object_, object_.mesh(), 1);
  grasping::GraspSimulator sim{hand_, object_};
  // Empty only until SetUp's assertion stops the test.
  const Grasp g = grasps_.empty() ? Grasp{} : grasps_.front();
};

// Seeded samples at twice the paper's position error, so that some of them fail on the capsule.
RobustnessParams samplesThatSometimesFail(int samples) {
  RobustnessParams params;
  params.samples = samples;
  params.seed = 5;
  params.position_sigma_m = 0.02;
  return params;
}

TEST_F(CapsuleGrasp, RobustnessIsIdenticalForTheSameSeed) {
  RobustnessParams rp;
  rp.samples = 30;
  rp.seed = 11;
  const auto a = evaluateRobustness(sim, g, rp, 3), b = evaluateRobustness(sim, g, rp, 3);
  EXPECT_EQ(a.force_closure, b.force_closure);
  EXPECT_EQ(a.collisions, b.collisions);
  rp.variant = RobustnessVariant::kReference;  // the reference's smaller errors on the object
  const auto ref = evaluateRobustness(sim, g, rp, 3);
  EXPECT_EQ(ref.samples, 30);
  EXPECT_EQ(ref.force_closure,
            evaluateRobustness(sim, g, rp, 4).force_closure);  // same samples per grasp
}

TEST_F(CapsuleGrasp, RobustnessIsIdenticalAtOneAndTwoThreadsAndTheClosingsAgree) {
  RobustnessParams rp;
  rp.samples = 40;
  rp.seed = 5;
  const auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return evaluateRobustness(sim, g, rp, 2);
  };
  const auto one = run(1), two = run(2);
  EXPECT_EQ(one.force_closure, two.force_closure);
  EXPECT_EQ(one.collisions, two.collisions);
  EXPECT_EQ(one.score, two.score);
  // The stepwise closing (the old path) gives r within the fast closing's Wilson interval.
  rp.closing.method = grasping::ClosingMethod::kStepwise;
  const auto stepwise = evaluateRobustness(sim, g, rp, 2);
  EXPECT_GE(stepwise.score, one.wilson_low);
  EXPECT_LE(stepwise.score, one.wilson_high);
}

// A caller asking only whether r reaches a bar (max_failures) gets the full result when it does,
// and gave_up exactly when the full run fails more often, at one thread and at two.
TEST_F(CapsuleGrasp, RobustnessGivesUpExactlyWhenTheBarIsMissed) {
  RobustnessParams rp = samplesThatSometimesFail(40);
  for (const auto variant : {RobustnessVariant::kPaper, RobustnessVariant::kGuarded}) {
    rp.variant = variant;
    const auto full = evaluateRobustness(sim, g, rp, 2);
    const int failures = full.samples - full.force_closure;
    ASSERT_GT(failures, 0) << toString(variant);
    ASSERT_LT(failures, full.samples) << toString(variant);
    EXPECT_FALSE(full.gave_up);
    for (int threads : {1, 2}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      const auto met = evaluateRobustness(sim, g, rp, 2, failures);
      EXPECT_FALSE(met.gave_up) << toString(variant) << threads;
      EXPECT_EQ(met.force_closure, full.force_closure) << toString(variant) << threads;
      EXPECT_EQ(met.collisions, full.collisions) << toString(variant) << threads;
      const auto missed = evaluateRobustness(sim, g, rp, 2, failures - 1);
      EXPECT_TRUE(missed.gave_up) << toString(variant) << threads;
      EXPECT_LE(missed.force_closure, full.force_closure) << toString(variant) << threads;
      const auto unreachable = evaluateRobustness(sim, g, rp, 2, -1);
      EXPECT_TRUE(unreachable.gave_up);
      EXPECT_EQ(unreachable.force_closure, 0);
    }
  }
}

// A grasp's samples run a few at a time (best-first screening) hold exactly where the same
// samples of one full run hold, in every variant, one at a time and in ranges.
TEST_F(CapsuleGrasp, RobustnessSampleRangesHoldWhereTheFullRunHolds) {
  RobustnessParams rp = samplesThatSometimesFail(24);
  for (const auto variant : {RobustnessVariant::kPaper, RobustnessVariant::kGuarded,
                             RobustnessVariant::kSettled, RobustnessVariant::kReference}) {
    rp.variant = variant;
    const auto full = evaluateRobustness(sim, g, rp, 1);
    int holds = 0;
    for (int i = 0; i < rp.samples; ++i) {
      const auto one = evaluateRobustnessSamples(sim, g, rp, 1, i, i + 1);
      ASSERT_EQ(one.samples, 1);
      EXPECT_EQ(one.force_closure == 1, static_cast<bool>(full.held[i])) << toString(variant) << i;
      holds += one.force_closure;
    }
    EXPECT_EQ(holds, full.force_closure) << toString(variant);
    const auto tail = evaluateRobustnessSamples(sim, g, rp, 1, 10, rp.samples);
    ASSERT_EQ(tail.held.size(), static_cast<std::size_t>(rp.samples - 10));
    for (int i = 10; i < rp.samples; ++i)
      EXPECT_EQ(tail.held[i - 10], full.held[i]) << toString(variant) << i;
  }
  // One sample against a bar already missed (below zero failures): skipped, as in a longer run.
  rp.samples = 1;
  const auto skipped = evaluateRobustness(sim, g, rp, 1, -1);
  EXPECT_TRUE(skipped.gave_up);
  EXPECT_EQ(skipped.force_closure, 0);
  rp.samples = 24;
  EXPECT_THROW(evaluateRobustnessSamples(sim, g, rp, 1, 3, 3), InvalidArgument);
  EXPECT_THROW(evaluateRobustnessSamples(sim, g, rp, 1, -1, 2), InvalidArgument);
  EXPECT_THROW(evaluateRobustnessSamples(sim, g, rp, 1, 0, rp.samples + 1), InvalidArgument);
}

// held names the samples that held, and samplePoseError is the error each of them faced: closing
// the hand at the grasp moved by that error (about the contacts' centre) agrees sample by sample.
TEST_F(CapsuleGrasp, RobustnessHeldNamesTheSamplesThatHeldUnderTheirPoseErrors) {
  RobustnessParams rp = samplesThatSometimesFail(40);
  rp.variant = RobustnessVariant::kPaper;  // each sample is one closing at the perturbed pose
  constexpr std::uint64_t kStream = 2;
  const auto full = evaluateRobustness(sim, g, rp, kStream);
  ASSERT_EQ(full.held.size(), 40u);
  EXPECT_EQ(std::count(full.held.begin(), full.held.end(), true), full.force_closure);
  ASSERT_GT(full.force_closure, 0);
  ASSERT_LT(full.force_closure, full.samples);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& c : g.contacts) centre += c.point / static_cast<double>(g.contacts.size());
  const auto& preshape = sim.hand().preshape(g.preshape);
  for (int i = 0; i < rp.samples; ++i) {
    const PoseError e = samplePoseError(rp, kStream, i);
    Pose error = Pose::Identity();
    error.linear() = e.rotation;
    error.translation() = e.translation;
    const Pose hand_pose =
        Eigen::Translation3d(centre) * error * Eigen::Translation3d(-centre) * g.hand_pose;
    const auto closed = sim.close(hand_pose, preshape, rp.closing);
    const bool held =
        closed.status.ok() &&
        grasping::evaluateGrasp(closed.contacts, sim.object(), rp.quality).force_closure;
    EXPECT_EQ(held, static_cast<bool>(full.held[i])) << i;
  }
  // The errors have the variant's spread (2000 draws: a standard error of about 1.6 %).
  RobustnessParams paper;
  Eigen::Vector3d sum_sq = Eigen::Vector3d::Zero();
  constexpr int kDraws = 2000;
  for (int i = 0; i < kDraws; ++i) sum_sq += samplePoseError(paper, 0, i).translation.cwiseAbs2();
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_NEAR(std::sqrt(sum_sq[axis] / kDraws), positionSigmaM(paper),
                0.1 * positionSigmaM(paper));
}

// The robustness of the capsule's first planned grasps (up to 3 per hand) under two variants,
// with the same samples (seed 9, 30 per grasp): the pairs the variant comparisons below examine.
struct VariantPair {
  RobustnessResult weaker, stronger;
};
std::vector<VariantPair> scoredTwice(const std::string& hand_name, RobustnessVariant weaker,
                                     RobustnessVariant stronger) {
  const TriangleMesh mesh = geometry::shapes::makeCapsule(0.03, 0.14);
  const grasping::GraspObject object(mesh);
  const auto hand = grasping::loadBuiltinHand(hand_name);
  const auto grasps = plannedGrasps(hand, object, mesh, 3);
  grasping::GraspSimulator sim(hand, object);
  std::vector<VariantPair> pairs;
  for (std::size_t i = 0; i < grasps.size(); ++i) {
    RobustnessParams rp;
    rp.samples = 30;
    rp.seed = 9;
    rp.variant = weaker;
    VariantPair pair;
    pair.weaker = evaluateRobustness(sim, grasps[i], rp, i);
    rp.variant = stronger;
    pair.stronger = evaluateRobustness(sim, grasps[i], rp, i);
    pairs.push_back(std::move(pair));
  }
  return pairs;
}

// The guarded variant executes the paper's samples; the ones whose open hand starts clear are
// closed exactly as in the paper variant, so it can only add holding samples, never lose one.
TEST(Robustness, GuardedHoldsWhereverThePaperVariantHolds) {
  int collisions = 0, guarded_holds = 0, slipped = 0;
  for (const std::string hand_name : {"shadow", "sdh"}) {
    SCOPED_TRACE(hand_name);
    const auto pairs =
        scoredTwice(hand_name, RobustnessVariant::kPaper, RobustnessVariant::kGuarded);
    ASSERT_FALSE(pairs.empty());
    for (const auto& [paper, guarded] : pairs) {
      EXPECT_EQ(guarded.collisions, paper.collisions);  // the same samples
      EXPECT_EQ(paper.guarded_holds, 0);
      EXPECT_EQ(guarded.force_closure, paper.force_closure + guarded.guarded_holds);
      EXPECT_LE(guarded.guarded_holds, guarded.collisions);
      // The free starts close alike in both variants, and every sample has exactly one outcome.
      EXPECT_EQ(guarded.closing_failures, paper.closing_failures);
      EXPECT_EQ(guarded.no_force_closure, paper.no_force_closure);
      for (const auto& r : {paper, guarded}) {
        EXPECT_EQ(r.collisions - r.guarded_holds + r.closing_failures + r.no_force_closure +
                      r.force_closure,
                  r.samples);
      }
      slipped += paper.no_force_closure;
      collisions += guarded.collisions;
      guarded_holds += guarded.guarded_holds;
    }
  }
  // The comparison says something only if some samples started in collision and some of those
  // held after the guarded approach.
  EXPECT_GT(collisions, 0);
  EXPECT_GT(guarded_holds, 0);
  EXPECT_GT(slipped, 0);  // and the sum covers a third kind of failure
  std::cout << "[ guarded  ] " << collisions << " samples started in collision, " << guarded_holds
            << " of them held" << std::endl;
}

TEST(Robustness, GuardedBacksAHandStartingInsideTheObjectOffAndHolds) {
  // A kept grasp pushed along its approach 5 mm past where its open hand first touches the
  // capsule: most perturbed open hands start in collision. The paper variant counts those as
  // failures; the guarded approach stops where the hand touches, as the planner placed the grasp.
  const auto hand = grasping::loadBuiltinHand("armar3");
  const TriangleMesh mesh = geometry::shapes::makeCapsule(0.03, 0.14);
  const grasping::GraspObject object(mesh);
  const auto grasps = plannedGrasps(hand, object, mesh, 1);
  ASSERT_FALSE(grasps.empty());
  grasping::GraspSimulator sim(hand, object);
  const auto& preshape = hand.preshape(grasps.front().preshape);
  const auto pushedBy = [&](double push_m) {
    Grasp pushed = grasps.front();
    pushed.gcp_pose.translation() += push_m * pushed.gcp_pose.rotation().col(2);
    pushed.hand_pose = sim.handPoseForGcp(pushed.gcp_pose, preshape);
    return pushed;
  };
  constexpr double kStepM = 0.001, kPastTouchM = 0.005, kMaxPushM = 0.1;
  double touch_m = 0;
  while (touch_m < kMaxPushM && !sim.inCollision(pushedBy(touch_m).hand_pose, preshape.joints))
    touch_m += kStepM;
  ASSERT_LT(touch_m, kMaxPushM);
  const Grasp pushed = pushedBy(touch_m + kPastTouchM);
  RobustnessParams rp;
  rp.samples = 40;
  rp.variant = RobustnessVariant::kPaper;
  const auto paper = evaluateRobustness(sim, pushed, rp);
  rp.variant = RobustnessVariant::kGuarded;
  const auto guarded = evaluateRobustness(sim, pushed, rp);
  EXPECT_GE(paper.collisions, 30);
  EXPECT_GT(guarded.guarded_holds, 10);
  EXPECT_GT(guarded.score, paper.score + 0.25);
  EXPECT_EQ(parseRobustnessVariant("guarded"), RobustnessVariant::kGuarded);
  EXPECT_STREQ(toString(RobustnessVariant::kGuarded), "guarded");
  EXPECT_THROW(parseRobustnessVariant("gaurded"), InvalidArgument);
}

// The settled variant executes the guarded variant's samples and settles the ones that do not
// hold still: sample by sample it holds wherever the guarded variant holds, and the samples it
// adds are the settled holds.
TEST(Robustness, SettledHoldsWhereverTheGuardedVariantHolds) {
  int settled_holds = 0, samples = 0;
  for (const std::string hand_name : {"sdh", "shadow", "armar3"}) {
    SCOPED_TRACE(hand_name);
    const auto pairs =
        scoredTwice(hand_name, RobustnessVariant::kGuarded, RobustnessVariant::kSettled);
    ASSERT_FALSE(pairs.empty());
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      const auto& [guarded, settled] = pairs[i];
      ASSERT_EQ(settled.held.size(), guarded.held.size());
      for (std::size_t k = 0; k < settled.held.size(); ++k) {
        if (guarded.held[k]) {
          EXPECT_TRUE(settled.held[k]) << "grasp " << i << " sample " << k;
        }
      }
      EXPECT_EQ(guarded.settled_holds, 0);
      EXPECT_EQ(settled.force_closure, guarded.force_closure + settled.settled_holds);
      EXPECT_EQ(settled.collisions - settled.guarded_holds + settled.closing_failures +
                    settled.no_force_closure + settled.force_closure,
                settled.samples);
      settled_holds += settled.settled_holds;
      samples += settled.samples;
    }
  }
  // Settling matters on these grasps: it adds holds.
  EXPECT_GT(settled_holds, samples / 20);
  std::cout << "[ settled  ] " << settled_holds << " of " << samples
            << " samples held only after the object settled" << std::endl;
  EXPECT_EQ(parseRobustnessVariant("settled"), RobustnessVariant::kSettled);
  EXPECT_STREQ(toString(RobustnessVariant::kSettled), "settled");
}

}  // namespace
}  // namespace skelgrasp::ranking
