#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <initializer_list>
#include <map>
#include <string>
#include <vector>

#include "planned_object.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/ranking/robust_ranking.h"

// The robust ranking's budget: which grasps screening takes (each preshape's best in turn, or the
// best by epsilon) and where the budget comes from (the parameters, the hand, the defaults).
namespace skelgrasp::ranking {
namespace {

using test_fixtures::cylinder;
using test_fixtures::fewSamples;
using test_fixtures::Planned;
using test_fixtures::planOn;

// With preshapes in turn, the screened candidates are, for every preshape, its best grasps by
// epsilon (a prefix of its epsilon order), and the preshapes share the screen_k places evenly: a
// preshape gets fewer places than another only when it has no grasp left. Whatever the order of
// the grasps given.
TEST(RobustRanking, ScreeningTakesEachPreshapesBestGraspsInTurn) {
  // A 60 mm ball: the SDH closes its power, precision and alternative preshapes on it.
  const Planned p = planOn("sdh", geometry::shapes::makeSphere(0.03), 0);
  const std::size_t n = p.plan.grasps.size();
  std::map<std::string, std::vector<double>> epsilons;  // of each preshape, all its grasps
  for (const auto& g : p.plan.grasps) epsilons[g.preshape].push_back(g.epsilon);
  ASSERT_GE(epsilons.size(), 3u) << "the ball should get several preshapes";
  auto params = fewSamples(4, 2);
  params.screen_k = 3 * epsilons.size() + 1;
  params.screen_samples = 2;
  params.refinement.enabled = false;
  params.screening_pruning = ScreeningPruning::kNone;  // every candidate keeps its screening score
  params.robustness.load.reset();  // the turns alone, without the carryable-first order
  // The order under test, and no confirmation, whatever the SDH's own budget says.
  params.screen_candidates = ScreenCandidates::kPreshapesInTurn;
  params.confirm_samples = 0;
  // The input in reverse too: the candidates may not depend on where a grasp stands.
  std::vector<grasping::Grasp> reversed(p.plan.grasps.rbegin(), p.plan.grasps.rend());
  for (const std::vector<grasping::Grasp>* grasps :
       std::initializer_list<const std::vector<grasping::Grasp>*>{&p.plan.grasps, &reversed}) {
    const auto result = rankByRobustness(p.hand, *p.object, *grasps, p.params.hypothesis, params);
    ASSERT_EQ(result.screened, *params.screen_k);
    EXPECT_EQ(result.budget.screen_candidates, ScreenCandidates::kPreshapesInTurn);
    // The screened are the scored and the screened-only grasps, ranked before all others.
    std::map<std::string, std::vector<double>> screened;
    for (std::size_t i = 0; i < *params.screen_k; ++i)
      screened[result.grasps[i].preshape].push_back(result.grasps[i].epsilon);
    std::size_t most = 0, fewest_with_more_left = n;
    for (auto& [preshape, all] : epsilons) {
      std::vector<double> taken = screened[preshape];
      std::sort(all.begin(), all.end(), std::greater<>());
      std::sort(taken.begin(), taken.end(), std::greater<>());
      // A prefix of the preshape's epsilon order (ties may swap equal epsilons only).
      for (std::size_t k = 0; k < taken.size(); ++k) EXPECT_EQ(taken[k], all[k]) << preshape;
      most = std::max(most, taken.size());
      if (taken.size() < all.size())
        fewest_with_more_left = std::min(fewest_with_more_left, taken.size());
    }
    // Even shares: no preshape with grasps left got two places fewer than another.
    EXPECT_LE(most, fewest_with_more_left + 1);
  }
  // By epsilon over all, the same budget screens one preshape's grasps more often than its share
  // here (else this test would not tell the rules apart).
  params.screen_candidates = ScreenCandidates::kByPreScore;
  const auto by_epsilon =
      rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, params);
  std::map<std::string, std::size_t> counts;
  for (std::size_t i = 0; i < *params.screen_k; ++i) ++counts[by_epsilon.grasps[i].preshape];
  std::size_t most_by_epsilon = 0;
  for (const auto& [preshape, count] : counts) most_by_epsilon = std::max(most_by_epsilon, count);
  EXPECT_GT(most_by_epsilon, 4u);
  EXPECT_EQ(parseScreenCandidates(toString(ScreenCandidates::kByPreScore)),
            ScreenCandidates::kByPreScore);
  EXPECT_EQ(parseScreenCandidates("preshapes"), ScreenCandidates::kPreshapesInTurn);
  EXPECT_THROW(parseScreenCandidates("random"), InvalidArgument);
}

// A budget the parameters leave unset comes from the hand (its grasp description's "ranking"),
// then from the defaults; one they set wins. A ranking under the hand's budget is the ranking
// under the same budget given as parameters.
TEST(RobustRanking, UnsetBudgetsComeFromTheHandThenTheDefaults) {
  RobustRankingParams unset;
  const RankingBudgetUsed shadow =
      rankingBudgetFor(unset, grasping::resolveHand("shadow").rankingBudget());
  EXPECT_EQ(shadow.screen_k, 40u);
  EXPECT_EQ(shadow.screen_samples, 8);
  EXPECT_DOUBLE_EQ(shadow.search_below_r, 0.5);
  EXPECT_EQ(shadow.screen_candidates, ScreenCandidates::kByPreScore);
  const RankingBudgetUsed armar =
      rankingBudgetFor(unset, grasping::resolveHand("armar3").rankingBudget());
  EXPECT_EQ(armar.screen_k, kDefaultScreenK);
  EXPECT_EQ(armar.screen_samples, kDefaultScreenSamples);
  EXPECT_DOUBLE_EQ(armar.search_below_r, kDefaultSearchBelowR);
  EXPECT_EQ(armar.screen_candidates, kDefaultScreenCandidates);
  // One option given, the others left to the hand.
  RobustRankingParams one;
  one.screen_k = 60;
  const RankingBudgetUsed mixed =
      rankingBudgetFor(one, grasping::resolveHand("shadow").rankingBudget());
  EXPECT_EQ(mixed.screen_k, 60u);
  EXPECT_EQ(mixed.screen_samples, 8);
  EXPECT_DOUBLE_EQ(mixed.search_below_r, 0.5);
  RobustRankingParams set;
  set.screen_k = 25;
  set.screen_samples = 5;
  set.refinement.search_below_r = 0.9;
  set.screen_candidates = ScreenCandidates::kPreshapesInTurn;
  for (const char* hand : {"shadow", "armar3"}) {
    const RankingBudgetUsed used =
        rankingBudgetFor(set, grasping::resolveHand(hand).rankingBudget());
    EXPECT_EQ(used.screen_k, 25u) << hand;
    EXPECT_EQ(used.screen_samples, 5) << hand;
    EXPECT_DOUBLE_EQ(used.search_below_r, 0.9) << hand;
    EXPECT_EQ(used.screen_candidates, ScreenCandidates::kPreshapesInTurn) << hand;
  }

  const Planned& p = cylinder();
  ASSERT_GE(p.plan.grasps.size(), 6u);
  grasping::HandModel budgeted = p.hand;
  grasping::RankingBudget budget;
  budget.screen_grasps = 6;
  budget.screen_samples = 4;
  budget.refine_below_r = 1.0;
  budgeted.setRankingBudget(budget);
  auto params = fewSamples(8, 2);
  params.screen_k.reset();
  params.refinement.max_evaluations = 1;
  const auto by_hand =
      rankByRobustness(budgeted, *p.object, p.plan.grasps, p.params.hypothesis, params);
  EXPECT_EQ(by_hand.budget.screen_k, 6u);
  EXPECT_EQ(by_hand.budget.screen_samples, 4);
  EXPECT_DOUBLE_EQ(by_hand.budget.search_below_r, 1.0);
  EXPECT_LE(by_hand.screened + by_hand.screen_pruned, 6u);
  params.screen_k = 6;
  params.screen_samples = 4;
  params.refinement.search_below_r = 1.0;
  const auto given =
      rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, params);
  ASSERT_EQ(by_hand.grasps.size(), given.grasps.size());
  EXPECT_EQ(by_hand.order, given.order);
  EXPECT_EQ(by_hand.refined, given.refined);
  for (std::size_t i = 0; i < given.grasps.size(); ++i) {
    ASSERT_EQ(by_hand.grasps[i].robustness.has_value(), given.grasps[i].robustness.has_value());
    if (given.grasps[i].robustness) {
      EXPECT_DOUBLE_EQ(by_hand.grasps[i].robustness->r, given.grasps[i].robustness->r) << i;
    }
  }
  // The plain hand runs the defaults.
  EXPECT_EQ(
      rankByRobustness(p.hand, *p.object, p.plan.grasps, p.params.hypothesis, fewSamples(8, 2))
          .budget.screen_samples,
      kDefaultScreenSamples);
}

}  // namespace
}  // namespace skelgrasp::ranking
