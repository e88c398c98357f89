#include "skelgrasp/ranking/robust_ranking.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <queue>
#include <string>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "skelgrasp/common/logging.h"

namespace skelgrasp::ranking {
namespace {

// evaluateRobustness's grasp_index: every scored grasp faces the same perturbations (common
// random numbers, the header's convention), and screening faces others.
constexpr std::uint64_t kScoreStream = 0;
constexpr std::uint64_t kScreenStream = 1;
// Refinement for robustness searches on its own stream too, so that the reported r of a moved
// grasp is not the r it was chosen for.
constexpr std::uint64_t kRefineStream = 2;

// The choice between a scored grasp and the pose its refinement found is made on samples of its
// own: were it made on the scoring samples, the r reported for whichever is kept would be the
// better of two noisy estimates: over the 58 YCB meshes the moved grasps' reported r then stood
// 0.7-2.6 points further above their r on fresh samples than the other returned grasps' did
// (CHANGELOG.md has the measurement).
constexpr std::uint64_t kCheckStream = 3;

// Refinement for robustness of one scored grasp (its robustness set): the search runs on its own
// stream, and its choice is checked on the check stream against the planner's pose, so a moved pose
// that does not hold there as often as the planner's is not taken. A moved pose taken is then
// scored on the scoring samples, which chose nothing. Records the search and the check in the
// grasp's robustness; true when the grasp was replaced by a moved pose.
bool refineScoredGrasp(grasping::GraspSimulator& simulator, grasping::Grasp& grasp,
                       const grasping::HypothesisParams& planner, const RobustnessParams& rp,
                       const RobustRefinementParams& params, double search_below_r) {
  grasping::GraspRobustRefinement record;
  record.search_samples = params.samples;
  record.r_before = grasp.robustness->r;
  record.preshape_before = grasp.preshape;
  // A grasp that held in (nearly) every scoring sample is not searched: its r is at most a few
  // samples short of 1, which the search's few samples cannot tell apart.
  if (grasp.robustness->r >= search_below_r) {
    grasp.robustness->refinement = record;
    return false;
  }
  RobustRefinementOutcome refined =
      refineForRobustness(simulator, grasp, planner, rp, params, kRefineStream);
  record.evaluations = refined.evaluations;
  if (refined.refined) {
    // The moved pose must hold in at least as many check samples as the planner's; its check stops
    // as soon as it has failed in more.
    const RobustnessResult before = evaluateRobustness(simulator, grasp, rp, kCheckStream);
    const RobustnessResult moved = evaluateRobustness(simulator, refined.grasp, rp, kCheckStream,
                                                      rp.samples - before.force_closure);
    record.check_samples = rp.samples;
    record.check_holds_before = before.force_closure;
    record.check_holds_after =
        moved.gave_up ? std::nullopt : std::optional<int>(moved.force_closure);
    log().debug("robust refinement: check {} -> {}{} of {} (search r {:.2f} -> {:.2f})",
                before.force_closure, moved.gave_up ? "< " : "",
                moved.gave_up ? before.force_closure : moved.force_closure, rp.samples,
                refined.search_r_before, refined.search_r_after);
    // The record's rule, read from the record: refined == (holds_after >= holds_before).
    if (record.check_holds_after && *record.check_holds_after >= record.check_holds_before) {
      grasp = std::move(refined.grasp);
      grasp.robustness =
          graspRobustness(evaluateRobustness(simulator, grasp, rp, kScoreStream), rp);
      record.refined = true;
      record.shift_x_m = refined.shift_x_m;
      record.shift_y_m = refined.shift_y_m;
      record.standoff_m = refined.standoff_m;
      record.roll_rad = refined.roll_rad;
      record.mean_shift_steps = refined.mean_shift_steps;
      record.mean_shift_m = refined.mean_shift_m;
      record.mean_shift_rad = refined.mean_shift_rad;
    }
  }
  grasp.robustness->refinement = record;
  return record.refined;
}

// The fewest holds out of `samples` whose screening score (holds / samples x trust) beats `bar`
// strictly, computed as the screening computes its scores; none when not even all samples do.
// Strictly: a later candidate that only ties the top_k's lowest ranks below it (stable sort).
std::optional<int> holdsToBeat(double bar, double trust, int samples) {
  for (int holds = 0; holds <= samples; ++holds) {
    if (static_cast<double>(holds) / samples * trust > bar) return holds;
  }
  return std::nullopt;
}

// Best-first screening (ScreeningPruning::kBestFirst) of `candidates` (pre-score order): runs the
// next sample of the candidate whose screening score could still be highest, its bound (holds so
// far plus the samples left, x trust; ties to the earlier candidate), until top_k candidates have
// run every sample with a score at least every other's bound. Those are the top_k of full
// screening, in its order: a score is its bound once every sample has run, computed as full
// screening computes it. With several threads, the next sample of each of the (at most) that many
// best candidates runs at once; the choice does not change. It runs fewer samples than screening
// in pre-score order, which must run a later candidate until it falls short of the best so far,
// however many better ones follow.
// What a screening of `candidates` gives the ranking: the candidates that get a screening score.
// Every other candidate was pruned (stopped short or never run).
struct Screening {
  std::vector<std::size_t> chosen;  // indices into `candidates`
  std::vector<double> scores;       // their screening scores (r x trust)
  std::vector<int> holds;           // their samples that held
  std::size_t finished = 0;         // candidates that ran every sample, the chosen included
};
Screening screenBestFirst(grasping::GraspSimulator& simulator,
                          const std::vector<grasping::Grasp>& grasps,
                          const std::vector<std::size_t>& candidates,
                          const std::vector<double>& trust, const RobustnessParams& screen,
                          std::size_t top_k) {
  const int samples = screen.samples;
  const std::size_t m = candidates.size();
  std::vector<int> run(m, 0), holds(m, 0);
  const auto bound = [&](std::size_t c) {
    return static_cast<double>(holds[c] + samples - run[c]) / samples * trust[c];
  };
  struct Entry {
    double bound;
    std::size_t candidate;
  };
  // The top is the highest bound, the earliest candidate on ties.
  const auto lower_priority = [](const Entry& a, const Entry& b) {
    return a.bound != b.bound ? a.bound < b.bound : a.candidate > b.candidate;
  };
  std::priority_queue<Entry, std::vector<Entry>, decltype(lower_priority)> queue(lower_priority);
  for (std::size_t c = 0; c < m; ++c) queue.push({bound(c), c});
  // One simulator per sample run at once (a simulator moves its hand's collision objects): the
  // caller's, and one more per further thread.
  const std::size_t batch =
      static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
  std::vector<std::unique_ptr<grasping::GraspSimulator>> more_simulators;
  std::vector<grasping::GraspSimulator*> simulators = {&simulator};
  for (std::size_t b = 1; b < batch; ++b) {
    more_simulators.push_back(
        std::make_unique<grasping::GraspSimulator>(simulator.hand(), simulator.object()));
    simulators.push_back(more_simulators.back().get());
  }
  Screening out;
  std::vector<std::size_t> running;
  while (!queue.empty() && out.chosen.size() < top_k) {
    // A finished candidate on top scores at least every other's bound, its own score: chosen.
    if (run[queue.top().candidate] == samples) {
      out.chosen.push_back(queue.top().candidate);
      out.scores.push_back(queue.top().bound);
      out.holds.push_back(holds[queue.top().candidate]);
      queue.pop();
      continue;
    }
    running.clear();
    while (running.size() < batch && !queue.empty() && run[queue.top().candidate] < samples) {
      running.push_back(queue.top().candidate);
      queue.pop();
    }
    std::vector<int> held(running.size());
    tbb::parallel_for(std::size_t{0}, running.size(), [&](std::size_t k) {
      const std::size_t c = running[k];
      held[k] = evaluateRobustnessSamples(*simulators[k], grasps[candidates[c]], screen,
                                          kScreenStream, run[c], run[c] + 1)
                    .force_closure;
    });
    for (std::size_t k = 0; k < running.size(); ++k) {
      const std::size_t c = running[k];
      holds[c] += held[k];
      ++run[c];
      queue.push({bound(c), c});
    }
  }
  out.finished = static_cast<std::size_t>(std::count(run.begin(), run.end(), samples));
  return out;
}

// Screening in pre-score order (ScreeningPruning::kNone and kInOrder): every candidate that runs
// all its samples is chosen, best first or not. With `prune`, once top_k are screened a later
// candidate must hold in more samples than the lowest of the best top_k so far (ties go to the
// earlier candidate), and its samples stop when too many have failed for that.
Screening screenInOrder(grasping::GraspSimulator& simulator,
                        const std::vector<grasping::Grasp>& grasps,
                        const std::vector<std::size_t>& candidates,
                        const std::vector<double>& trust, const RobustnessParams& screen,
                        std::size_t top_k, bool prune) {
  Screening out;
  // The top_k screening scores so far, lowest first: the bar a later candidate must beat.
  std::priority_queue<double, std::vector<double>, std::greater<>> best_scores;
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    std::optional<int> max_failures;
    if (prune && best_scores.size() == top_k) {
      const std::optional<int> needed = holdsToBeat(best_scores.top(), trust[c], screen.samples);
      if (!needed) continue;
      max_failures = screen.samples - *needed;
    }
    const RobustnessResult r =
        evaluateRobustness(simulator, grasps[candidates[c]], screen, kScreenStream, max_failures);
    if (r.gave_up) continue;
    out.chosen.push_back(c);
    out.scores.push_back(r.score * trust[c]);
    out.holds.push_back(r.force_closure);
    best_scores.push(out.scores.back());
    if (best_scores.size() > top_k) best_scores.pop();
  }
  out.finished = out.chosen.size();
  return out;
}

// Confirmation (RobustRankingParams::confirm_samples) of a screening: its best `picked` by score
// (ties: the earlier candidate, which is best-first screening's own order) each run
// `confirm_samples` more samples of the screening stream (sample indices screen.samples on: the
// ones a screening with that many more samples would run) and score holds over all their samples
// x trust. `screening` is reordered: the confirmed first, in that order, then the others (only the
// in-order screenings have others), and the count confirmed is returned; the caller chooses the
// top_k from the confirmed.
std::size_t confirmScreening(grasping::GraspSimulator& simulator,
                             const std::vector<grasping::Grasp>& grasps,
                             const std::vector<std::size_t>& candidates,
                             const std::vector<double>& trust, const RobustnessParams& screen,
                             int confirm_samples, std::size_t picked, Screening& screening) {
  std::vector<std::size_t> order(screening.chosen.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (screening.scores[a] != screening.scores[b])
      return screening.scores[a] > screening.scores[b];
    return screening.chosen[a] < screening.chosen[b];
  });
  Screening sorted;
  sorted.finished = screening.finished;
  for (std::size_t k : order) {
    sorted.chosen.push_back(screening.chosen[k]);
    sorted.scores.push_back(screening.scores[k]);
    sorted.holds.push_back(screening.holds[k]);
  }
  RobustnessParams longer = screen;
  longer.samples = screen.samples + confirm_samples;
  const std::size_t confirmed = std::min(picked, sorted.chosen.size());
  for (std::size_t k = 0; k < confirmed; ++k) {
    const std::size_t c = sorted.chosen[k];
    const int more = evaluateRobustnessSamples(simulator, grasps[candidates[c]], longer,
                                               kScreenStream, screen.samples, longer.samples)
                         .force_closure;
    sorted.holds[k] += more;
    sorted.scores[k] = static_cast<double>(sorted.holds[k]) / longer.samples * trust[c];
  }
  screening = std::move(sorted);
  return confirmed;
}

// `candidates` (best first) reordered so that the preshapes take turns: the best of each preshape
// (preshapes in the order their best grasps come), then the second best of each, and so on. The
// order within a preshape is kept.
std::vector<std::size_t> preshapesInTurn(const std::vector<grasping::Grasp>& grasps,
                                         const std::vector<std::size_t>& candidates) {
  std::vector<std::string> preshapes;
  std::vector<std::vector<std::size_t>> queues;
  for (std::size_t i : candidates) {
    const auto it = std::find(preshapes.begin(), preshapes.end(), grasps[i].preshape);
    if (it == preshapes.end()) {
      preshapes.push_back(grasps[i].preshape);
      queues.push_back({i});
    } else {
      queues[static_cast<std::size_t>(it - preshapes.begin())].push_back(i);
    }
  }
  std::vector<std::size_t> in_turn;
  in_turn.reserve(candidates.size());
  for (std::size_t round = 0; in_turn.size() < candidates.size(); ++round)
    for (const auto& queue : queues)
      if (round < queue.size()) in_turn.push_back(queue[round]);
  return in_turn;
}

// `candidates` with the larger least finger travel first (stable: pre-score order on ties).
void sortByLeastFingerTravel(const grasping::HandModel& hand,
                             const std::vector<grasping::Grasp>& grasps,
                             std::vector<std::size_t>& candidates) {
  std::vector<std::pair<double, std::size_t>> keyed;
  keyed.reserve(candidates.size());
  for (std::size_t i : candidates) keyed.emplace_back(leastFingerTravel(hand, grasps[i]), i);
  std::stable_sort(keyed.begin(), keyed.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t k = 0; k < keyed.size(); ++k) candidates[k] = keyed[k].second;
}

// `candidates` reordered so that those whose planned closing carries the load check's weight
// (grasping::loadCapacity at the grasp's own pose, capacity >= 1) come first, each part in its
// given order; returns how many do. Which grasps are worth perturbed samples: a grasp that cannot
// carry the object at its nominal pose seldom does under pose errors, and scoring it takes the
// place of one that might.
std::size_t carryableFirst(const grasping::HandModel& hand, const grasping::GraspObject& object,
                           const std::vector<grasping::Grasp>& grasps,
                           const grasping::QualityParams& quality,
                           const grasping::LoadCapacityParams& load,
                           std::vector<std::size_t>& candidates) {
  std::vector<char> carries(candidates.size(), 0);
  tbb::parallel_for(std::size_t{0}, candidates.size(), [&](std::size_t k) {
    const grasping::Grasp& grasp = grasps[candidates[k]];
    const auto capacity = grasping::loadCapacity(
        hand, grasp.hand_pose, grasp.joints, grasp.contacts, object.centerOfMass(), quality, load);
    carries[k] = capacity.carries();
  });
  std::vector<std::size_t> reordered;
  reordered.reserve(candidates.size());
  for (std::size_t k = 0; k < candidates.size(); ++k)
    if (carries[k]) reordered.push_back(candidates[k]);
  const std::size_t carryable = reordered.size();
  for (std::size_t k = 0; k < candidates.size(); ++k)
    if (!carries[k]) reordered.push_back(candidates[k]);
  candidates = std::move(reordered);
  return carryable;
}

}  // namespace

double leastFingerTravel(const grasping::HandModel& hand, const grasping::Grasp& grasp) {
  const Eigen::VectorXd& open = hand.preshape(grasp.preshape).joints;
  if (grasp.joints.size() != open.size())
    throw InvalidArgument("least finger travel: the grasp's joints are not the hand's");
  double least = std::numeric_limits<double>::infinity();
  for (const auto& finger : hand.fingers()) {
    double travel = 0;
    for (const auto& drive : finger.drives)
      travel += std::abs(grasp.joints[drive.joint] - open[drive.joint]);
    least = std::min(least, travel);
  }
  return hand.fingers().empty() ? 0.0 : least;
}

grasping::GraspRobustness graspRobustness(const RobustnessResult& result,
                                          const RobustnessParams& params) {
  grasping::GraspRobustness r;
  r.r = result.score;
  r.ci95_low = result.wilson_low;
  r.ci95_high = result.wilson_high;
  r.samples = result.samples;
  r.mu = params.quality.friction;
  r.torsional_friction_m = params.quality.torsional_friction_m.value_or(0.0);
  r.contact_patch = grasping::toString(params.closing.contact_patch);
  r.sigma_m = positionSigmaM(params);
  r.sigma_rad = orientationSigmaRad(params);
  r.variant = toString(params.variant);
  r.start_collisions = result.collisions - result.guarded_holds;
  r.closing_failures = result.closing_failures;
  r.no_force_closure = result.no_force_closure;
  r.too_weak = result.too_weak;
  if (params.load) {
    r.load_mass_kg = params.load->mass_kg;
    r.load_torque_share = params.load->torque_share;
  }
  r.settled_holds = result.settled_holds;
  return r;
}

RankingBudgetUsed rankingBudgetFor(const RobustRankingParams& params,
                                   const grasping::RankingBudget& hand_budget) {
  RankingBudgetUsed used;
  used.screen_k = params.screen_k.value_or(hand_budget.screen_grasps.value_or(kDefaultScreenK));
  used.screen_samples =
      params.screen_samples.value_or(hand_budget.screen_samples.value_or(kDefaultScreenSamples));
  used.search_below_r = params.refinement.search_below_r.value_or(
      hand_budget.refine_below_r.value_or(kDefaultSearchBelowR));
  used.screen_candidates = params.screen_candidates.value_or(
      hand_budget.screen_candidates.value_or(kDefaultScreenCandidates));
  used.confirm_samples =
      params.confirm_samples.value_or(hand_budget.confirm_samples.value_or(kDefaultConfirmSamples));
  return used;
}

void checkRobustRankingParams(const RobustRankingParams& params) {
  if (params.enabled && params.robustness.samples < 1)
    throw InvalidArgument("robust ranking: need at least one robustness sample");
  if (params.enabled && params.screen_samples && *params.screen_samples < 1)
    throw InvalidArgument("robust ranking: need at least one screening sample");
  if (params.enabled && params.confirm_samples && *params.confirm_samples < 0)
    throw InvalidArgument("robust ranking: confirm_samples must be >= 0");
  if (params.friction && !(std::isfinite(*params.friction) && *params.friction >= 0))
    throw InvalidArgument("robust ranking: friction must be finite and >= 0");
  if (const auto& bar = params.refinement.search_below_r; bar && !(*bar >= 0 && *bar <= 1))
    throw InvalidArgument("robust ranking: refinement's search_below_r must be in [0, 1]");
}

RobustRankingResult rankByRobustness(const grasping::HandModel& hand,
                                     const grasping::GraspObject& object,
                                     std::vector<grasping::Grasp> grasps,
                                     const grasping::HypothesisParams& planner,
                                     const RobustRankingParams& params,
                                     const std::vector<double>& trust) {
  if (!trust.empty() && trust.size() != grasps.size())
    throw InvalidArgument("robust ranking: one trust factor per grasp needed");
  // Screening's bounds rely on scores growing with holds: a factor below zero would turn them.
  for (double t : trust) {
    if (!(std::isfinite(t) && t >= 0))
      throw InvalidArgument("robust ranking: trust factors must be finite and >= 0");
  }
  checkRobustRankingParams(params);
  Stopwatch watch;
  RobustRankingResult out;
  out.enabled = params.enabled;
  out.budget = rankingBudgetFor(params, hand.rankingBudget());
  const std::size_t n = grasps.size();
  auto trustOf = [&](std::size_t i) { return trust.empty() ? 1.0 : trust[i]; };
  std::vector<double> pre_score(n);
  for (std::size_t i = 0; i < n; ++i) pre_score[i] = grasps[i].epsilon * trustOf(i);
  // The candidates for scoring: the best by pre-score (stable: the planner's order on ties).
  std::vector<std::size_t> by_pre(n);
  std::iota(by_pre.begin(), by_pre.end(), 0);
  std::stable_sort(by_pre.begin(), by_pre.end(),
                   [&](std::size_t a, std::size_t b) { return pre_score[a] > pre_score[b]; });

  std::vector<double> rank_score = pre_score;
  // 2: scored for robustness, 1: screened only, 0: neither.
  std::vector<int> level(n, 0);
  if (params.enabled && n > 0) {
    // r is judged as the planner judged: its quality (friction unless overridden, force-closure
    // test, contact model) and its closing.
    RobustnessParams rp = params.robustness;
    rp.quality = grasping::withHandContactModel(planner.quality, hand);
    if (params.friction) rp.quality.friction = *params.friction;
    rp.closing = planner.closing;
    grasping::GraspSimulator simulator(hand, object);
    const std::size_t top_k = params.top_k == 0 ? n : std::min(params.top_k, n);
    const std::size_t screen_k = out.budget.screen_k == 0 ? n : std::min(out.budget.screen_k, n);
    // The candidates for scoring, best first: by pre-score, or by the screening score.
    std::vector<std::size_t> candidates;
    for (std::size_t i : by_pre)
      if (!grasps[i].contacts.empty()) candidates.push_back(i);
    if (screen_k > top_k) {
      if (out.budget.screen_candidates == ScreenCandidates::kPreshapesInTurnByTravel)
        sortByLeastFingerTravel(hand, grasps, candidates);
      if (out.budget.screen_candidates != ScreenCandidates::kByPreScore)
        candidates = preshapesInTurn(grasps, candidates);
      if (rp.load)
        out.carryable = carryableFirst(hand, object, grasps, rp.quality, *rp.load, candidates);
      if (candidates.size() > screen_k) candidates.resize(screen_k);
      const Stopwatch screen_watch;
      RobustnessParams screen = rp;
      screen.samples = out.budget.screen_samples;
      std::vector<double> trusts;
      for (std::size_t i : candidates) trusts.push_back(trustOf(i));
      // Best-first gives only the chosen a screening score: which others ran all their samples
      // depends on the thread count, and the order returned must not. The others rank by
      // pre-score.
      const int confirm_samples = out.budget.confirm_samples;
      const std::size_t picked = confirm_samples > 0 ? kConfirmCandidatesPerScored * top_k : top_k;
      Screening screening =
          params.screening_pruning == ScreeningPruning::kBestFirst
              ? screenBestFirst(simulator, grasps, candidates, trusts, screen, picked)
              : screenInOrder(simulator, grasps, candidates, trusts, screen, picked,
                              params.screening_pruning == ScreeningPruning::kInOrder);
      if (confirm_samples > 0)
        out.confirmed = confirmScreening(simulator, grasps, candidates, trusts, screen,
                                         confirm_samples, picked, screening);
      std::vector<std::size_t> contenders;
      for (std::size_t k = 0; k < screening.chosen.size(); ++k) {
        const std::size_t i = candidates[screening.chosen[k]];
        rank_score[i] = screening.scores[k];
        level[i] = 1;
        contenders.push_back(i);
      }
      out.screened = screening.finished;
      out.screen_pruned = candidates.size() - screening.finished;
      // Chosen best first, or in pre-score order: a stable sort breaks ties of screening score
      // by pre-score either way. After a confirmation the top_k come from the confirmed (first,
      // in the screening's order), so they and the others are sorted apart.
      candidates = std::move(contenders);
      const auto by_score = [&](std::size_t a, std::size_t b) {
        return rank_score[a] > rank_score[b];
      };
      const auto confirmed_end = candidates.begin() + static_cast<std::ptrdiff_t>(out.confirmed);
      std::stable_sort(candidates.begin(), confirmed_end, by_score);
      std::stable_sort(confirmed_end, candidates.end(), by_score);
      out.screening_s = screen_watch.seconds();
    } else if (rp.load) {
      out.carryable = carryableFirst(hand, object, grasps, rp.quality, *rp.load, candidates);
    }
    if (candidates.size() > top_k) candidates.resize(top_k);
    const Stopwatch score_watch;
    for (std::size_t i : candidates) {
      const RobustnessResult r = evaluateRobustness(simulator, grasps[i], rp, kScoreStream);
      grasps[i].robustness = graspRobustness(r, rp);
      rank_score[i] = r.score * trustOf(i);
      level[i] = 2;
      ++out.scored;
    }
    out.scoring_s = score_watch.seconds();
    const Stopwatch refine_watch;
    if (params.refinement.enabled) {
      // The most robust scored grasps are searched for still more robust poses: the grasps a user
      // executes first are the ones worth the closings.
      std::stable_sort(candidates.begin(), candidates.end(),
                       [&](std::size_t a, std::size_t b) { return rank_score[a] > rank_score[b]; });
      const std::size_t refine_k = params.refinement.max_grasps == 0
                                       ? candidates.size()
                                       : std::min(params.refinement.max_grasps, candidates.size());
      for (std::size_t c = 0; c < refine_k; ++c) {
        const std::size_t i = candidates[c];
        if (refineScoredGrasp(simulator, grasps[i], planner, rp, params.refinement,
                              out.budget.search_below_r))
          ++out.refined;
        rank_score[i] = grasps[i].robustness->r * trustOf(i);
      }
    }
    out.refinement_s = refine_watch.seconds();
  }
  // Ties break by the pre-score of the grasp returned: a refined grasp's pose, and so its
  // epsilon, may have moved.
  for (std::size_t i = 0; i < n; ++i) pre_score[i] = grasps[i].epsilon * trustOf(i);
  out.order = by_pre;
  std::stable_sort(out.order.begin(), out.order.end(), [&](std::size_t a, std::size_t b) {
    if (level[a] != level[b]) return level[a] > level[b];
    if (rank_score[a] != rank_score[b]) return rank_score[a] > rank_score[b];
    return pre_score[a] > pre_score[b];
  });
  for (std::size_t i : out.order) {
    out.scores.push_back(rank_score[i]);
    out.grasps.push_back(std::move(grasps[i]));
    out.grasps.back().id = static_cast<int>(out.grasps.size() - 1);
  }
  out.time_s = watch.seconds();
  log().debug(
      "robust ranking: {} of {} grasps carry the load, {} screened ({} pruned, {} confirmed), {} "
      "scored, {} refined "
      "in {:.2f} s (screening {:.2f} s, scoring {:.2f} s, refinement {:.2f} s)",
      out.carryable, n, out.screened, out.screen_pruned, out.confirmed, out.scored, out.refined,
      out.time_s, out.screening_s, out.scoring_s, out.refinement_s);
  return out;
}

}  // namespace skelgrasp::ranking
