#include "skelgrasp/evaluation/true_object.h"

#include <algorithm>
#include <map>

#include "skelgrasp/grasping/grasp.h"
#include "skelgrasp/ranking/robust_ranking.h"

namespace skelgrasp::evaluation {

ScoreParams TrueObjectParams::defaultScore() {
  ScoreParams score;
  // The ranking's own criterion (settled, the load check), so that the claimed and the true r
  // measure the same thing; score's sample count (100).
  score.robustness.variant = ranking::RobustnessVariant::kSettled;
  score.robustness.load = ranking::defaultLoadCheck();
  return score;
}

std::vector<TrueGraspJudgement> judgeOnTrueObject(const grasping::HandModel& hand,
                                                  const grasping::GraspObject& object,
                                                  const physics::PhysicalObject* physical,
                                                  const std::vector<ClaimedGrasp>& grasps,
                                                  const TrueObjectParams& params) {
  std::vector<grasping::GraspPlacement> placements;
  placements.reserve(grasps.size());
  for (const auto& g : grasps) placements.push_back(g.placement);
  std::vector<TrueGraspJudgement> out(grasps.size());
  if (grasps.empty()) return out;
  const ScoreResult scored = scoreGrasps(hand, object, placements, params.score);
  for (std::size_t i = 0; i < grasps.size(); ++i) {
    TrueGraspJudgement& j = out[i];
    j.claimed_r = grasps[i].claimed_r;
    j.observed_contact_ratio = grasps[i].observed_contact_ratio;
    const GraspScore& s = scored.grasps[i];
    j.closing_failure = s.closing_failure;
    j.starts_inside = s.closing_failure == grasping::reason::kStartCollision;
    const FrictionScore& at = s.by_friction.front();
    j.true_force_closure = at.force_closure;
    j.true_r = at.robustness ? at.robustness->score : 0.0;
  }
  if (physical != nullptr) {
    SimulateParams simulate = params.simulate;
    simulate.frictions = {params.score.frictions.front()};
    const SimulateResult executed = simulateGrasps(hand, object, *physical, placements, simulate);
    for (std::size_t i = 0; i < grasps.size(); ++i) {
      const FrictionSimulation& at = executed.grasps[i].by_friction.front();
      out[i].nominal_holds = at.nominal.holds;
      if (!at.nominal.holds) out[i].failed_phase = physics::toString(at.nominal.failed_phase);
      if (at.robustness) out[i].sim_r = at.robustness->sim_r;
    }
  }
  return out;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  const double upper = values[mid];
  if (values.size() % 2 == 1) return upper;
  const double lower =
      *std::max_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid));
  return 0.5 * (lower + upper);
}

ScanToGraspFigures scanToGraspFigures(const std::vector<ScanToGraspCase>& cases) {
  struct PerObject {
    double claimed = 0, truth = 0;
    std::size_t views = 0;
    bool grasps = false;
  };
  std::map<std::string, PerObject> objects;
  ScanToGraspFigures f;
  f.cases = cases.size();
  std::vector<double> times;
  double claimed_sum = 0, true_sum_of_claimed = 0;
  std::size_t judged = 0, held = 0;
  for (const auto& c : cases) {
    times.push_back(c.run_s);
    PerObject& o = objects[c.object];
    ++o.views;
    if (c.returned > 0) {
      ++f.cases_with_grasps;
      o.grasps = true;
    }
    double case_claimed = 0, case_true = 0;
    std::size_t with_claim = 0;
    for (const auto& g : c.top) {
      ++f.top_grasps;
      f.starts_inside += g.starts_inside;
      case_true += g.true_r;
      if (g.claimed_r) {
        case_claimed += *g.claimed_r;
        ++with_claim;
        claimed_sum += *g.claimed_r;
        true_sum_of_claimed += g.true_r;
        ++f.claimed_pairs;
      }
      if (g.nominal_holds) {
        ++judged;
        held += *g.nominal_holds;
      }
    }
    o.claimed += with_claim ? case_claimed / static_cast<double>(with_claim) : 0.0;
    o.truth += c.top.empty() ? 0.0 : case_true / static_cast<double>(c.top.size());
  }
  std::vector<double> claimed, truth;
  for (const auto& [name, o] : objects) {
    claimed.push_back(o.claimed / static_cast<double>(o.views));
    truth.push_back(o.truth / static_cast<double>(o.views));
    f.objects_with_grasps += o.grasps;
  }
  f.objects = objects.size();
  f.median_claimed_r = median(claimed);
  f.median_true_r = median(truth);
  f.median_run_s = median(times);
  if (judged > 0) f.hold_rate = static_cast<double>(held) / static_cast<double>(judged);
  if (f.claimed_pairs > 0) {
    f.claimed_minus_true =
        (claimed_sum - true_sum_of_claimed) / static_cast<double>(f.claimed_pairs);
  }
  return f;
}

}  // namespace skelgrasp::evaluation
