#include "skelgrasp/ranking/robust_ranking.h"
#include "skelgrasp/grasping/quality/load_capacity.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <utility>

#include "planned_object.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/planning/planners.h"
#include "skelgrasp/grasping/quality/load_capacity.h"
#include "skelgrasp/skeleton/extraction.h"
#include "test_support.h"

namespace skelgrasp::ranking {
namespace {

using test_fixtures::cylinder;
using test_fixtures::fewSamples;
using test_fixtures::Planned;
using test_fixtures::planOn;

// The robustness parameters rankByRobustness judges with, for `planned`.
RobustnessParams judgedAs(const Planned& p, const RobustRankingParams& ranking) {
  RobustnessParams rp = ranking.robustness;
  rp.quality = p.params.hypothesis.quality;
  if (ranking.friction) rp.quality.friction = *ranking.friction;
  rp.quality.torsional_friction_m = p.hand.closingDefaults().torsional_friction_m;
  rp.closing = p.params.hypothesis.closing;
  return rp;
}

TEST(RobustRanking, ScoresTheTopKAndRanksThemFirstByR) {
  const Planned& p = cylinder();
  ASSERT_GE(p.plan.grasps.size(), 4u);
  auto params = fewSamples(16, 3);
  // The order rule alone: the load check's carryable-first order is tested below.
  params.robustness.load.reset();
  const auto result =
      rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, params);
  EXPECT_TRUE(result.status.ok());
  ASSERT_EQ(result.grasps.size(), p.plan.grasps.size());
  EXPECT_EQ(result.scored, 3u);
  EXPECT_TRUE(result.enabled);
  // The parts' times are measured inside the whole (plan_record.h writes them).
  EXPECT_GT(result.scoring_s, 0.0);
  EXPECT_GE(result.screening_s, 0.0);
  EXPECT_GE(result.refinement_s, 0.0);
  EXPECT_LE(result.screening_s + result.scoring_s + result.refinement_s, result.time_s);
  for (std::size_t i = 0; i < result.grasps.size(); ++i) {
    const auto& g = result.grasps[i];
    EXPECT_EQ(g.id, static_cast<int>(i));
    // The scored grasps come first, each with a valid record.
    EXPECT_EQ(g.robustness.has_value(), i < 3) << i;
    if (g.robustness) {
      const auto& r = *g.robustness;
      EXPECT_EQ(r.samples, 16);
      EXPECT_LE(0.0, r.ci95_low);
      EXPECT_LE(r.ci95_low, r.r);
      EXPECT_LE(r.r, r.ci95_high);
      EXPECT_LE(r.ci95_high, 1.0);
      EXPECT_DOUBLE_EQ(r.mu, grasping::QualityParams{}.friction);
      EXPECT_EQ(r.variant, "settled");  // the default
      EXPECT_DOUBLE_EQ(r.sigma_m, 0.010);
      // Every failed sample has one cause.
      EXPECT_EQ(r.start_collisions + r.closing_failures + r.no_force_closure + r.too_weak,
                r.samples - static_cast<int>(std::lround(r.r * r.samples)));
      EXPECT_DOUBLE_EQ(result.scores[i], r.r);  // no trust factor: the score is r
    } else {
      EXPECT_DOUBLE_EQ(result.scores[i], g.epsilon);
    }
    // Non-increasing in the documented score within each group; ties by epsilon.
    if (i > 0 && result.grasps[i - 1].robustness.has_value() == g.robustness.has_value()) {
      EXPECT_GE(result.scores[i - 1], result.scores[i]);
      if (result.scores[i - 1] == result.scores[i]) {
        EXPECT_GE(result.grasps[i - 1].epsilon, g.epsilon);
      }
    }
  }
  // The scored grasps are the three best by epsilon.
  for (std::size_t i = 0; i < 3; ++i) EXPECT_LT(result.order[i], 3u);
}

TEST(RobustRanking, WithTheLoadCheckTheGraspsThatCarryTheWeightAreScoredFirst) {
  const Planned& p = cylinder();
  const std::size_t n = p.plan.grasps.size();
  auto params = fewSamples(4, 2);
  params.refinement.enabled = false;
  ASSERT_TRUE(params.robustness.load.has_value());  // the ranking's default
  // Which grasps carry the object's weight at their own pose, as the ranking's r judges it.
  const RobustnessParams rp = judgedAs(p, params);
  std::vector<bool> carries(n);
  std::size_t carrying = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& g = p.plan.grasps[i];
    const auto capacity = grasping::loadCapacity(p.hand, g.hand_pose, g.joints, g.contacts,
                                                 p.object->centerOfMass(), rp.quality, *rp.load);
    carries[i] = capacity.carries();
    carrying += carries[i];
  }
  // The cylinder has both kinds, and enough carrying grasps for the two scored.
  ASSERT_GE(carrying, params.top_k);
  ASSERT_LT(carrying, n);
  const auto result =
      rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, params);
  EXPECT_EQ(result.carryable, carrying);
  for (std::size_t i = 0; i < params.top_k; ++i) EXPECT_TRUE(carries[result.order[i]]) << i;
  // Without the load check the same budget scores the two best by epsilon.
  params.robustness.load.reset();
  const auto plain =
      rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, params);
  EXPECT_EQ(plain.carryable, 0u);
  for (std::size_t i = 0; i < params.top_k; ++i) EXPECT_LT(plain.order[i], params.top_k);
}

TEST(RobustRanking, ScreeningChoosesTheScoredGraspsByAScreeningROnItsOwnSamples) {
  const Planned& p = cylinder();
  const std::size_t n = p.plan.grasps.size();
  ASSERT_GE(n, 6u);
  auto params = fewSamples(12, 2);
  params.screen_k = 6;
  params.screen_samples = 8;
  params.robustness.seed = 3;
  // The screening r below is of the chosen grasps as planned: no search may move them. Every
  // candidate gets its full screening r (pruning is checked below).
  params.refinement.enabled = false;
  params.screening_pruning = ScreeningPruning::kNone;
  params.screen_candidates = ScreenCandidates::kByPreScore;
  params.confirm_samples = 0;  // the choice by the first look alone (confirmation: below)
  const auto result =
      rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, params);
  EXPECT_EQ(result.screened, 6u);
  EXPECT_EQ(result.confirmed, 0u);
  ASSERT_EQ(result.scored, 2u);
  grasping::GraspSimulator sim(p.hand, *p.object);
  const RobustnessParams rp = judgedAs(p, params);
  RobustnessParams screen = rp;
  screen.samples = 8;
  // The candidates are the six best by epsilon (the planner's order); the two scored have the
  // highest screening r, drawn from the screening stream (grasp_index 1).
  double lowest_chosen = 1, highest_other = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& g = result.grasps[i];
    if (i < 6) {
      EXPECT_LT(result.order[i], 6u) << i;
      const double screening_r = evaluateRobustness(sim, g, screen, 1).score;
      if (i < 2) {
        lowest_chosen = std::min(lowest_chosen, screening_r);
      } else {
        highest_other = std::max(highest_other, screening_r);
        EXPECT_DOUBLE_EQ(result.scores[i], screening_r) << i;
      }
    } else {
      EXPECT_GE(result.order[i], 6u) << i;
      EXPECT_DOUBLE_EQ(result.scores[i], g.epsilon) << i;
    }
    // Only the scored grasps carry a robustness, from the scoring stream (grasp_index 0).
    ASSERT_EQ(g.robustness.has_value(), i < 2) << i;
    if (g.robustness) {
      EXPECT_EQ(g.robustness->samples, 12);
      EXPECT_EQ(g.robustness->r, evaluateRobustness(sim, g, rp, 0).score) << i;
    }
  }
  EXPECT_GE(lowest_chosen, highest_other);
  // screen_k at most top_k: no screening.
  params.screen_k = 2;
  EXPECT_EQ(
      rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, params).screened, 0u);
  params.screen_samples = 0;
  EXPECT_THROW(rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, params),
               InvalidArgument);
}

// Confirmation, checked against an independent count: the best 2 x top_k by the first look (ties:
// the earlier candidate) run the confirmation's samples, the top_k scored are the best of them by
// all their screening samples, the other confirmed rank by that score and the rest of the screened
// by the first look's. A larger pose error than the paper's spreads the r apart.
TEST(RobustRanking, ConfirmationChoosesTheScoredGraspsByAllTheirScreeningSamples) {
  const Planned& p = cylinder();
  ASSERT_GE(p.plan.grasps.size(), 6u);
  auto params = fewSamples(12, 2);
  params.screen_k = 6;
  params.screen_samples = 8;
  params.confirm_samples = 4;
  params.robustness.seed = 3;
  params.robustness.position_sigma_m = 0.03;
  params.robustness.orientation_sigma_rad = 0.3;
  params.refinement.enabled = false;
  params.screening_pruning = ScreeningPruning::kNone;
  params.screen_candidates = ScreenCandidates::kByPreScore;
  const auto result =
      rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, params);
  ASSERT_EQ(result.scored, 2u);
  EXPECT_EQ(result.confirmed, 4u);
  EXPECT_EQ(result.budget.confirm_samples, 4);

  // The candidates: the six best by epsilon, the planner's order on ties.
  std::vector<std::size_t> candidates(p.plan.grasps.size());
  std::iota(candidates.begin(), candidates.end(), 0);
  std::stable_sort(candidates.begin(), candidates.end(), [&](std::size_t a, std::size_t b) {
    return p.plan.grasps[a].epsilon > p.plan.grasps[b].epsilon;
  });
  candidates.resize(6);
  grasping::GraspSimulator sim(p.hand, *p.object);
  RobustnessParams first = judgedAs(p, params), all = first;
  first.samples = 8;
  all.samples = 12;
  std::map<std::size_t, double> first_r, all_r;
  for (std::size_t i : candidates) {
    first_r[i] = evaluateRobustness(sim, p.plan.grasps[i], first, 1).score;
    all_r[i] = evaluateRobustness(sim, p.plan.grasps[i], all, 1).score;
  }
  std::vector<std::size_t> confirmed = candidates;
  std::stable_sort(confirmed.begin(), confirmed.end(),
                   [&](std::size_t a, std::size_t b) { return first_r[a] > first_r[b]; });
  confirmed.resize(4);
  std::vector<std::size_t> scored = confirmed;
  std::stable_sort(scored.begin(), scored.end(),
                   [&](std::size_t a, std::size_t b) { return all_r[a] > all_r[b]; });
  scored.resize(2);
  std::set<std::size_t> returned_scored = {result.order[0], result.order[1]};
  EXPECT_EQ(returned_scored, std::set<std::size_t>(scored.begin(), scored.end()));
  for (std::size_t rank = 2; rank < result.order.size(); ++rank) {
    const std::size_t i = result.order[rank];
    if (!first_r.count(i)) continue;  // not a candidate: ranks by epsilon
    const bool was_confirmed = std::find(confirmed.begin(), confirmed.end(), i) != confirmed.end();
    EXPECT_DOUBLE_EQ(result.scores[rank], was_confirmed ? all_r[i] : first_r[i]) << rank;
  }
  // The first look and all samples disagree somewhere, so the check above has teeth.
  bool differ = false;
  for (std::size_t i : candidates) differ = differ || first_r[i] != all_r[i];
  EXPECT_TRUE(differ);
  params.confirm_samples = -1;
  EXPECT_THROW(rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, params),
               InvalidArgument);
}

// Pruned screening, in pre-score order or best-first, chooses the grasps full screening chooses:
// the same scored grasps in the same order with the same r, with and without trust factors; only
// screening samples are saved. Best-first gives a screening score to the chosen only: the scored
// and, with a confirmation, the confirmed (twice top_k in all).
void expectPruningChoosesAsFullScreening(const Planned& p, const std::vector<double>& trust,
                                         ScreenCandidates candidates, int confirm_samples,
                                         const std::string& what) {
  auto params = fewSamples(12, 3);
  params.screen_candidates = candidates;
  params.confirm_samples = confirm_samples;
  params.screen_k = 0;  // every grasp is a candidate
  params.screen_samples = 10;
  params.refinement.enabled = false;
  params.screening_pruning = ScreeningPruning::kNone;
  const auto full =
      rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, params, trust);
  ASSERT_EQ(full.scored, 3u) << what;
  EXPECT_EQ(full.screen_pruned, 0u) << what;
  for (const ScreeningPruning pruning :
       {ScreeningPruning::kInOrder, ScreeningPruning::kBestFirst}) {
    params.screening_pruning = pruning;
    const std::string how =
        what + (pruning == ScreeningPruning::kInOrder ? " in order" : " best-first");
    const auto pruned =
        rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, params, trust);
    ASSERT_EQ(pruned.scored, 3u) << how;
    EXPECT_EQ(pruned.screened + pruned.screen_pruned, full.screened) << how;
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_EQ(pruned.order[i], full.order[i]) << how << " rank " << i;
      EXPECT_EQ(pruned.grasps[i].robustness->r, full.grasps[i].robustness->r) << how;
      EXPECT_EQ(pruned.scores[i], full.scores[i]) << how;
    }
    // Every grasp is still returned; best-first ranks the rest by pre-score (epsilon x trust).
    ASSERT_EQ(pruned.grasps.size(), full.grasps.size()) << how;
    const std::size_t confirmed =
        confirm_samples > 0 ? std::min(kConfirmCandidatesPerScored * 3, pruned.grasps.size()) : 0;
    EXPECT_EQ(pruned.confirmed, confirmed) << how;
    EXPECT_EQ(full.confirmed, confirmed) << how;
    if (pruning == ScreeningPruning::kBestFirst) {
      // The confirmed that are not scored next, by their score over all their screening samples
      // (a whole number of holds out of 10 + confirm_samples, x trust).
      const std::size_t rest = std::max<std::size_t>(3, confirmed);
      for (std::size_t i = 3; i < rest; ++i) {
        const std::size_t input = pruned.order[i];
        const double t = trust.empty() ? 1.0 : trust[input];
        const double holds = pruned.scores[i] / t * (10 + confirm_samples);
        EXPECT_NEAR(holds, std::round(holds), 1e-9) << how << " rank " << i;
        if (i > 3) {
          EXPECT_GE(pruned.scores[i - 1], pruned.scores[i]) << how << " rank " << i;
        }
      }
      // The rest by pre-score, epsilon x trust, the planner's order on ties.
      for (std::size_t i = rest; i < pruned.grasps.size(); ++i) {
        const std::size_t input = pruned.order[i];
        EXPECT_EQ(pruned.scores[i],
                  p.plan.grasps[input].epsilon * (trust.empty() ? 1.0 : trust[input]))
            << how << " rank " << i;
        if (i > rest) {
          EXPECT_GE(pruned.scores[i - 1], pruned.scores[i]) << how << " rank " << i;
          if (pruned.scores[i - 1] == pruned.scores[i]) {
            EXPECT_LT(pruned.order[i - 1], input) << how << " rank " << i;
          }
        }
      }
    }
  }
}

TEST(RobustRanking, PrunedScreeningChoosesTheGraspsFullScreeningChooses) {
  std::vector<std::pair<std::string, TriangleMesh>> meshes;
  meshes.emplace_back("cylinder", geometry::shapes::makeCylinder(0.035, 0.2, 48, 10));
  for (const char* name : {"011_banana.ply", "025_mug.ply"}) {
    const std::string path = test::sharedDataDir() + "/objects/ycb/" + name;
    if (!test::sharedDataDir().empty() && std::filesystem::exists(path))
      meshes.emplace_back(name, loadMesh(path));
  }
  if (meshes.size() == 1) GTEST_SKIP() << "no YCB meshes in ../shared/data: cylinder only";
  std::size_t pruned_any = 0, best_first_pruned_any = 0;
  for (const auto& [name, mesh] : meshes) {
    for (const char* hand : {"armar3", "sdh"}) {
      const Planned p = planOn(hand, mesh, 16);
      if (p.plan.grasps.size() < 4) continue;
      const std::string what = name + " " + hand;
      // Each way of choosing the candidates, once without and once with trust factors.
      expectPruningChoosesAsFullScreening(p, {}, ScreenCandidates::kPreshapesInTurn, 0, what);
      expectPruningChoosesAsFullScreening(p, {}, ScreenCandidates::kPreshapesInTurn,
                                          kDefaultConfirmSamples, what + " confirmed");
      expectPruningChoosesAsFullScreening(p, {}, ScreenCandidates::kPreshapesInTurnByTravel, 0,
                                          what + " by travel");
      // Trust factors between 0.5 and 1 (seeded): the bar is on r x trust.
      std::mt19937 rng(11);
      std::uniform_real_distribution<double> factor(0.5, 1.0);
      std::vector<double> trust(p.plan.grasps.size());
      for (double& t : trust) t = factor(rng);
      expectPruningChoosesAsFullScreening(p, trust, ScreenCandidates::kByPreScore,
                                          kDefaultConfirmSamples,
                                          what + " with trust, by epsilon, confirmed");
      auto params = fewSamples(4, 3);
      params.screen_k = 0;
      params.refinement.enabled = false;
      params.screening_pruning = ScreeningPruning::kInOrder;
      pruned_any += rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, params)
                        .screen_pruned;
      params.screening_pruning = ScreeningPruning::kBestFirst;
      best_first_pruned_any +=
          rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, params)
              .screen_pruned;
    }
  }
  // Each pruning happens at all on these objects (else the comparison above says nothing).
  EXPECT_GT(pruned_any, 0u);
  EXPECT_GT(best_first_pruned_any, 0u);
}

// The least finger travel is the smallest, over the fingers, of the summed joint change of a
// finger's drives from the preshape: 0 for a grasp closed where it opened, and the thumb's 0.25 rad
// here, where the other two fingers travelled 0.3 and 0.4 rad.
TEST(RobustRanking, LeastFingerTravelIsTheSmallestFingerTravelFromThePreshape) {
  const grasping::HandModel sdh = grasping::resolveHand("sdh");
  grasping::Grasp grasp;
  grasp.preshape = "power";
  grasp.joints = sdh.preshape("power").joints;
  EXPECT_EQ(leastFingerTravel(sdh, grasp), 0.0);
  std::map<std::string, const grasping::Finger*> fingers;
  for (const auto& finger : sdh.fingers()) fingers[finger.name] = &finger;
  ASSERT_EQ(fingers.size(), 3u);
  for (const char* name : {"finger1", "finger2", "thumb"}) {
    ASSERT_TRUE(fingers.count(name)) << name;
    ASSERT_EQ(fingers[name]->drives.size(), 2u) << name;  // proximal, distal
  }
  grasp.joints[fingers["finger1"]->drives[0].joint] += 0.3;
  grasp.joints[fingers["finger2"]->drives[0].joint] -= 0.2;  // a change either way is travel
  grasp.joints[fingers["finger2"]->drives[1].joint] += 0.2;
  grasp.joints[fingers["thumb"]->drives[1].joint] += 0.25;
  EXPECT_NEAR(leastFingerTravel(sdh, grasp), 0.25, 1e-12);
  grasp.joints.conservativeResize(grasp.joints.size() - 1);
  EXPECT_THROW(leastFingerTravel(sdh, grasp), InvalidArgument);
  grasp.preshape = "no such preshape";
  EXPECT_THROW(leastFingerTravel(sdh, grasp), InvalidArgument);
}

TEST(RobustRanking, DisabledKeepsTheEpsilonOrderWithoutRobustness) {
  const Planned& p = cylinder();
  RobustRankingParams params;
  params.enabled = false;
  const auto result =
      rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, params);
  EXPECT_EQ(result.scored, 0u);
  EXPECT_FALSE(result.enabled);  // what addPlanRecords writes as a null "ranking"
  ASSERT_EQ(result.grasps.size(), p.plan.grasps.size());
  for (std::size_t i = 0; i < result.grasps.size(); ++i) {
    EXPECT_EQ(result.order[i], i);
    EXPECT_FALSE(result.grasps[i].robustness.has_value());
    EXPECT_EQ(result.grasps[i].epsilon, p.plan.grasps[i].epsilon);
  }
}

TEST(RobustRanking, UsesCommonRandomNumbersAndTheGivenFriction) {
  // Every grasp is scored with grasp_index 0 and the params' seed: evaluateRobustness with those
  // reproduces each r (what `skelgrasp score` relies on).
  const Planned& p = cylinder();
  auto params = fewSamples(12, 2);
  params.robustness.seed = 7;
  params.friction = 0.5;
  const auto result =
      rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, params);
  grasping::GraspSimulator sim(p.hand, *p.object);
  RobustnessParams rp = params.robustness;
  rp.quality = p.params.hypothesis.quality;
  rp.quality.friction = 0.5;
  rp.quality.torsional_friction_m = p.hand.closingDefaults().torsional_friction_m;
  rp.closing = p.params.hypothesis.closing;
  ASSERT_EQ(result.scored, 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const auto& g = result.grasps[i];
    EXPECT_DOUBLE_EQ(g.robustness->mu, 0.5);
    EXPECT_EQ(g.robustness->r, evaluateRobustness(sim, g, rp, 0).score) << i;
  }
}

// The same order, scores and r at one, two and three threads, with and without screening (which
// runs best-first, as many candidates' next samples at once as there are threads).
TEST(RobustRanking, SameSeedSameRAtOneAndTwoThreads) {
  const Planned& p = cylinder();
  auto screened = fewSamples(20, 3);
  screened.screen_k = 0;  // all 8 planned grasps are candidates
  screened.screen_samples = 6;
  for (const RobustRankingParams& params : {fewSamples(20, 3), screened}) {
    std::vector<std::vector<double>> r_by_threads, score_by_threads;
    std::vector<std::vector<std::size_t>> order_by_threads;
    for (int threads : {1, 2, 3}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      const auto result =
          rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, params);
      std::vector<double> r;
      for (const auto& g : result.grasps) r.push_back(g.robustness ? g.robustness->r : -1);
      r_by_threads.push_back(r);
      score_by_threads.push_back(result.scores);
      order_by_threads.push_back(result.order);
    }
    for (std::size_t t = 1; t < r_by_threads.size(); ++t) {
      EXPECT_EQ(r_by_threads[t], r_by_threads[0]) << t + 1 << " threads";
      EXPECT_EQ(score_by_threads[t], score_by_threads[0]) << t + 1 << " threads";
      EXPECT_EQ(order_by_threads[t], order_by_threads[0]) << t + 1 << " threads";
    }
  }
}

TEST(RobustRanking, TrustScalesTheScoreAndMustMatchTheGrasps) {
  const Planned& p = cylinder();
  const std::size_t n = p.plan.grasps.size();
  std::vector<double> trust(n, 0.5);
  trust[0] = 1.0;
  const auto result = rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis,
                                       fewSamples(8, n), trust);
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_TRUE(result.grasps[i].robustness);
    EXPECT_DOUBLE_EQ(result.scores[i], result.grasps[i].robustness->r * trust[result.order[i]]);
    if (i > 0) {
      EXPECT_GE(result.scores[i - 1], result.scores[i]);
    }
  }
  // A factor below zero or not finite would turn screening's bounds: refused.
  for (double bad : {-0.5, std::numeric_limits<double>::quiet_NaN()}) {
    std::vector<double> wrong = trust;
    wrong[1] = bad;
    EXPECT_THROW(rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis,
                                  fewSamples(8, n), wrong),
                 InvalidArgument);
  }
  trust.pop_back();
  EXPECT_THROW(rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis,
                                fewSamples(8, n), trust),
               InvalidArgument);
  auto none = fewSamples(0, n);
  EXPECT_THROW(rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, none),
               InvalidArgument);
}

TEST(RobustRanking, TopRankedGraspsOfARealObjectAreMoreRobustThanTheAverage) {
  std::string path;
  for (const char* name : {"006_mustard_bottle.ply", "011_banana.ply"}) {
    const std::string candidate = test::sharedDataDir() + "/objects/ycb/" + name;
    if (!test::sharedDataDir().empty() && std::filesystem::exists(candidate)) {
      path = candidate;
      break;
    }
  }
  if (path.empty()) GTEST_SKIP() << "no YCB mustard bottle or banana in ../shared/data";
  const Planned p = planOn("sdh", loadMesh(path), 20);
  ASSERT_GE(p.plan.grasps.size(), 4u) << path;
  const auto ranking = fewSamples(40, 0);
  const auto result =
      rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, ranking);
  ASSERT_EQ(result.scored, result.grasps.size());
  // Ranked on one set of samples, judged on fresh ones (another seed): taking the top by the same
  // samples they were ranked on would be better by construction.
  grasping::GraspSimulator sim(p.hand, *p.object);
  RobustnessParams fresh = ranking.robustness;
  fresh.seed = 12345;
  fresh.quality = p.params.hypothesis.quality;
  fresh.quality.torsional_friction_m = p.hand.closingDefaults().torsional_friction_m;
  fresh.closing = p.params.hypothesis.closing;
  double all = 0, top = 0;
  for (std::size_t i = 0; i < result.grasps.size(); ++i) {
    const double r = evaluateRobustness(sim, result.grasps[i], fresh, 0).score;
    all += r / result.grasps.size();
    if (i < 3) top += r / 3;
  }
  EXPECT_GE(top, all) << path;
  EXPECT_GT(top, 0.0) << path;
}

}  // namespace
}  // namespace skelgrasp::ranking
