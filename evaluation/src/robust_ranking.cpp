#include "skelgrasp/evaluation/robust_ranking.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "skelgrasp/common/logging.h"

namespace skelgrasp::evaluation {

grasping::GraspRobustness graspRobustness(const RobustnessResult& result,
                                          const RobustnessParams& params) {
  grasping::GraspRobustness r;
  r.r = result.score;
  r.ci95_low = result.wilson_low;
  r.ci95_high = result.wilson_high;
  r.samples = result.samples;
  r.mu = params.quality.friction;
  r.sigma_m = positionSigmaM(params);
  r.sigma_rad = orientationSigmaRad(params);
  r.variant = toString(params.variant);
  return r;
}

RobustRankingResult rankByRobustness(const grasping::HandModel& hand,
                                     const grasping::GraspObject& object,
                                     std::vector<grasping::Grasp> grasps,
                                     const grasping::HypothesisParams& planner,
                                     const RobustRankingParams& params,
                                     const std::vector<double>& trust) {
  if (!trust.empty() && trust.size() != grasps.size())
    throw InvalidArgument("robust ranking: one trust factor per grasp needed");
  if (params.enabled && params.robustness.samples < 1)
    throw InvalidArgument("robust ranking: need at least one robustness sample");
  if (params.friction && !(std::isfinite(*params.friction) && *params.friction >= 0))
    throw InvalidArgument("robust ranking: friction must be finite and >= 0");
  Stopwatch watch;
  RobustRankingResult out;
  const std::size_t n = grasps.size();
  std::vector<double> pre_score(n);
  for (std::size_t i = 0; i < n; ++i)
    pre_score[i] = grasps[i].epsilon * (trust.empty() ? 1.0 : trust[i]);
  // The candidates for scoring: the best by pre-score (stable: the planner's order on ties).
  std::vector<std::size_t> by_pre(n);
  std::iota(by_pre.begin(), by_pre.end(), 0);
  std::stable_sort(by_pre.begin(), by_pre.end(),
                   [&](std::size_t a, std::size_t b) { return pre_score[a] > pre_score[b]; });

  std::vector<double> rank_score = pre_score;
  std::vector<char> scored(n, 0);
  if (params.enabled && n > 0) {
    // r is judged as the planner judged: its quality (friction unless overridden, force-closure
    // test, contact model) and its closing.
    RobustnessParams rp = params.robustness;
    rp.quality = planner.quality;
    if (params.friction) rp.quality.friction = *params.friction;
    if (!rp.quality.torsional_friction_m)
      rp.quality.torsional_friction_m = hand.closingDefaults().torsional_friction_m;
    rp.closing = planner.closing;
    grasping::GraspSimulator simulator(hand, object);
    const std::size_t k = params.top_k == 0 ? n : std::min(params.top_k, n);
    for (std::size_t j = 0; j < k; ++j) {
      const std::size_t i = by_pre[j];
      if (grasps[i].contacts.empty()) continue;
      // grasp_index 0 for every grasp: common random numbers (see the header).
      const RobustnessResult r = evaluateRobustness(simulator, grasps[i], rp, 0);
      grasps[i].robustness = graspRobustness(r, rp);
      rank_score[i] = r.score * (trust.empty() ? 1.0 : trust[i]);
      scored[i] = 1;
      ++out.scored;
    }
  }
  out.order = by_pre;
  std::stable_sort(out.order.begin(), out.order.end(), [&](std::size_t a, std::size_t b) {
    if (scored[a] != scored[b]) return scored[a] > scored[b];
    if (rank_score[a] != rank_score[b]) return rank_score[a] > rank_score[b];
    return pre_score[a] > pre_score[b];
  });
  for (std::size_t i : out.order) {
    out.scores.push_back(rank_score[i]);
    out.grasps.push_back(std::move(grasps[i]));
    out.grasps.back().id = static_cast<int>(out.grasps.size() - 1);
  }
  out.time_s = watch.seconds();
  log().debug("robust ranking: {} of {} grasps scored in {:.2f} s", out.scored, n, out.time_s);
  return out;
}

}  // namespace skelgrasp::evaluation
