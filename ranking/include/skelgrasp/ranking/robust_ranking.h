#pragma once
// Robust ranking: the planner's best grasps scored by their robustness r (robustness.h) and
// re-ranked by it, so the grasps a user gets first are the ones that survive positioning errors,
// each with its r attached (Grasp::robustness). docs/planning.md, "Robust ranking".
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/grasping/planning/hypothesis.h"
#include "skelgrasp/ranking/robust_refinement.h"
#include "skelgrasp/ranking/robustness.h"

namespace skelgrasp::ranking {

// Defaults chosen so that ranking one object costs one to two seconds with the paper hands on the
// YCB meshes (docs/planning.md has the measurements): up to 60 grasps screened with 10 samples
// each, the best 10 of them scored with 50.
inline constexpr std::size_t kDefaultRobustTopK = 10;
inline constexpr int kDefaultRankingSamples = 50;
inline constexpr std::size_t kDefaultScreenK = 60;
inline constexpr int kDefaultScreenSamples = 10;
// Confirmation (RobustRankingParams::confirm_samples): the best kConfirmCandidatesPerScored x top_k
// by screening get this many more screening samples before the top_k are chosen.
inline constexpr int kDefaultConfirmSamples = 10;
inline constexpr std::size_t kConfirmCandidatesPerScored = 2;

inline RobustnessParams defaultRankingRobustness() {
  RobustnessParams params;
  params.samples = kDefaultRankingSamples;
  params.load = defaultLoadCheck();
  return params;
}

enum class ScreeningPruning {
  kNone,  // every candidate gets its full screening r
  // Candidates in pre-score order; once top_k (with a confirmation: the count it confirms, here
  // and below) are screened, a later one must hold in more samples than the lowest of the best
  // top_k so far (ties go to the earlier candidate), and its samples stop when too many have
  // failed for that (the former default; kBestFirst chooses the same grasps for fewer samples).
  kInOrder,
  // One sample at a time, always of the candidate whose score could still be highest (holds so
  // far plus samples left; ties to the earlier candidate); a candidate whose samples are all run
  // and whose score is at least every other's bound is chosen. Stops when top_k (with a
  // confirmation: the count it confirms) are chosen.
  kBestFirst,
};

// Which grasps screening looks at (screen_k of them); a hand's description may choose
// (grasping::RankingBudget::screen_candidates).
using grasping::parseScreenCandidates;
using grasping::ScreenCandidates;
using grasping::toString;

// A clearance of a closed grasp (ScreenCandidates::kPreshapesInTurnByTravel's order): the least,
// over the hand's fingers, of the finger's travel from the grasp's preshape to its closed
// configuration, the summed absolute change of its drives' joints (radians for revolute joints).
// A grasp whose every finger closed some way before it touched has room for a pose error; one
// with a finger already at the object in the preshape has none. Throws InvalidArgument when the
// grasp's joints are not the hand's or its preshape is unknown.
double leastFingerTravel(const grasping::HandModel& hand, const grasping::Grasp& grasp);

// A hand's description may choose another (the Shadow hand's keeps the best by epsilon,
// docs/hands.md).
inline constexpr ScreenCandidates kDefaultScreenCandidates = ScreenCandidates::kPreshapesInTurn;

struct RobustRankingParams {
  bool enabled = true;  // false: the grasps keep the pre-score order and get no robustness
  // The grasps scored: the best top_k by the screening (below); 0 scores all of them.
  std::size_t top_k = kDefaultRobustTopK;
  // Screening: screen_k grasps (0: all of them; which ones: screen_candidates, by the pre-score
  // epsilon x trust) get a cheap r from screen_samples perturbed executions, and the top_k are
  // chosen by it (or by the confirmation, confirm_samples below). The
  // pre-score alone says little about robustness (epsilon favours fingertip pinches that fall
  // apart under pose error), so screening more candidates than are scored is what lifts the r of
  // the returned grasps. No screening when screen_k (0 read as all) is at most top_k.
  // Unset: the hand's ranking budget (grasping::RankingBudget, from its grasp description), else
  // kDefaultScreenK and kDefaultScreenSamples (rankingBudgetFor below).
  std::optional<std::size_t> screen_k;
  std::optional<int> screen_samples;
  // Unset: the hand's ranking budget (its "screen_by"), else kDefaultScreenCandidates. Applies
  // only when screening runs (screen_k above top_k); without it the top_k by pre-score are scored.
  // The candidates keep their turn order, so where screening scores tie, the earlier turn goes
  // first (a preshape's better grasp before another preshape's next one), not the larger epsilon:
  // ties then spread the scored grasps over the preshapes, which is what taking turns is for.
  std::optional<ScreenCandidates> screen_candidates;
  // Confirmation (0: none): screening picks the best kConfirmCandidatesPerScored x top_k, each of
  // them runs confirm_samples more screening samples (the same stream's next ones), and the top_k
  // are chosen by all of their screening samples (ties: the screening's order). Why: from 10
  // samples a grasp that holds in 7 of 10 executions shows 10 of 10 one time in 35, so among 60
  // candidates the best by screening include lucky ones; a second look at the contenders only
  // costs a fraction of screening every candidate with more samples, and takes most of its gain
  // (CHANGELOG.md has the measurement). Unset: the hand's ranking budget (its
  // "confirm_samples"), else kDefaultConfirmSamples. Applies only when screening runs.
  std::optional<int> confirm_samples;
  // How screening saves samples without changing its choice: the top_k chosen (with a
  // confirmation: the candidates confirmed), their order and their screening r are those of full
  // screening (kNone) under every setting (tested); only which of the other candidates get a full
  // screening r differs (the rest rank by pre-score, as unscreened grasps do). `skelgrasp bench
  // ranking` compares them.
  ScreeningPruning screening_pruning = ScreeningPruning::kBestFirst;
  // Samples, variant, pose error sigmas and seed of r. Its `quality` and `closing` are NOT used:
  // r is judged as the planner judged the grasp (rankByRobustness's `planner` argument), with the
  // friction replaced by `friction` when that is set.
  RobustnessParams robustness = defaultRankingRobustness();
  std::optional<double> friction;  // unset: the planner's QualityParams::friction (0.35)
  // Each scored grasp's neighbourhood is searched for a more robust pose (robust_refinement.h);
  // a pose found replaces the grasp when it holds at least as often in a check on samples of its
  // own (not r's, so that the r reported is not the one a pose was chosen for).
  RobustRefinementParams refinement;
};

// The budget a ranking ran with: the parameters' values, or where they were unset the hand's
// (grasping::RankingBudget), or the defaults above; and which grasps screening took.
struct RankingBudgetUsed {
  std::size_t screen_k = kDefaultScreenK;
  int screen_samples = kDefaultScreenSamples;
  double search_below_r = kDefaultSearchBelowR;
  ScreenCandidates screen_candidates = kDefaultScreenCandidates;
  int confirm_samples = kDefaultConfirmSamples;
};

// Throws InvalidArgument for a caller's mistake in `params`: fewer than one robustness or
// screening sample, confirm_samples below 0 (these only when ranking is enabled), a friction that
// is not a finite number >= 0, or the refinement's search_below_r outside [0, 1]. rankByRobustness
// checks its params with it; a batch checks its ranking with it before any work starts.
void checkRobustRankingParams(const RobustRankingParams& params);

// Each of params' unset screen_k, screen_samples, screen_candidates, confirm_samples and
// refinement.search_below_r from a hand's ranking budget (HandModel::rankingBudget(); none: {}),
// else from the defaults. The one rule (rankByRobustness applies it itself).
RankingBudgetUsed rankingBudgetFor(const RobustRankingParams& params,
                                   const grasping::RankingBudget& hand_budget = {});

struct RobustRankingResult {
  Status status;                        // kOk (also when disabled or there is no grasp)
  bool enabled = false;                 // the params' `enabled`: whether a ranking ran at all
  RankingBudgetUsed budget;             // what the screening and the refinement ran with
  std::vector<grasping::Grasp> grasps;  // best first, ids renumbered 0..n-1 (id = rank)
  std::vector<double> scores;           // each grasp's rank score (see rankByRobustness)
  std::vector<std::size_t> order;       // grasps[i] was input grasp order[i]
  // Candidates that ran every screening sample (0 without screening); with best-first screening
  // this count, and screen_pruned, may depend on the thread count (the grasps returned do not).
  std::size_t screened = 0;
  // Screened candidates that ran the confirmation's samples too (0 without confirmation).
  std::size_t confirmed = 0;
  std::size_t screen_pruned = 0;  // candidates whose screening stopped short (screening_pruning)
  // With the load check: the candidates whose planned closing carries the weight at the grasp's
  // own pose; they go first to the screening (or, without screening, to the scoring).
  std::size_t carryable = 0;
  std::size_t scored = 0;   // grasps that got a robustness
  std::size_t refined = 0;  // scored grasps replaced by a more robust pose
  double time_s = 0;
  // Where time_s went (their sum is at most time_s; the rest is sorting and moving grasps).
  double screening_s = 0, scoring_s = 0, refinement_s = 0;
};

// Screens screen_k grasps (rankingBudgetFor: params', or the hand's; which ones:
// params.screen_candidates, each preshape's best by pre-score in turn or the best by pre-score),
// scores the best `params.top_k` of them by robustness and re-ranks all grasps:
//  * pre-score = epsilon x trust[i] (trust empty: 1; scans: 1 - w + w x observed contact ratio);
//  * screening score = screening r x trust[i]; the top_k by it (ties: the earlier candidate, in
//    pre-score order or, with preshapes in turn, in turn order) are scored; with a confirmation
//    (budget confirm_samples > 0) the best kConfirmCandidatesPerScored x top_k by it run that many
//    more screening samples, their screening r is over all their samples, and the top_k are
//    chosen from them (ties: the first screening's order);
//  * rank score of a scored grasp = r x trust[i]; of a screened one that is not scored = its
//    screening score (the confirmed ones; with kInOrder or kNone the others too; best-first
//    screening gives the others none, so those rank by pre-score); of the others (beyond screen_k,
//    screening pruned, or ranking disabled) = its pre-score;
//  * refinement (params.refinement.enabled): of the best params.refinement.max_grasps scored
//    grasps by rank score, those with r below the budget's search_below_r are searched for
//    more robust poses (robust_refinement.h, own stream
//    grasp_index = 2); a pose found replaces its grasp when it holds in at least as many samples
//    of a check (own stream, grasp_index = 3, params.robustness.samples) as the grasp, and is then
//    scored on the scoring samples; its rank score is r x trust[i] of the input grasp (the caller
//    may recompute the trust of a moved grasp's contacts). Every searched grasp's robustness
//    records the search and the check (GraspRobustness::refinement);
//  * order: scored grasps first by rank score, ties by pre-score; then the screened ones (with
//    best-first screening the confirmed ones only), then the rest, each by rank score (the
//    planner's order when trust is empty). The sort is stable.
// Only scored grasps carry a robustness (Grasp::robustness): the screening r, from a handful of
// samples, is used for choosing and not reported.
// Common random numbers: every grasp is scored with evaluateRobustness(..., grasp_index = 0) and
// params.robustness.seed, so all grasps face the same perturbations and the differences in r
// between them are not sampling noise (`skelgrasp score` relies on this convention to reproduce
// plan's numbers). Screening draws its own stream (grasp_index = 1), so the reported r of a grasp
// chosen for a lucky screening is not biased by that luck (except in the reference variant, which
// draws one sequence whatever the grasp_index: there the screening samples are the first scoring
// ones, and refinement searches and checks on the scoring samples themselves). The grasps, their
// order, scores and r do not depend on the thread count (the counts screened and screen_pruned
// may). Grasps without contacts stay unscored. Throws InvalidArgument for samples or
// screen_samples < 1 (when enabled), a negative or non-finite friction or trust factor, a
// refinement search_below_r outside [0, 1], or a trust vector whose size is not the grasps'.
RobustRankingResult rankByRobustness(const grasping::HandModel& hand,
                                     const grasping::GraspObject& object,
                                     std::vector<grasping::Grasp> grasps,
                                     const grasping::HypothesisParams& planner,
                                     const RobustRankingParams& params,
                                     const std::vector<double>& trust = {});

// The robustness record a grasp carries, from a result and the parameters that produced it.
grasping::GraspRobustness graspRobustness(const RobustnessResult& result,
                                          const RobustnessParams& params);

}  // namespace skelgrasp::ranking
