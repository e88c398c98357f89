#include "skelgrasp/evaluation/score.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "skelgrasp/common/json.h"
#include "skelgrasp/common/logging.h"

namespace skelgrasp::evaluation {
namespace {

constexpr double kMillisecondsPerSecond = 1000.0;

void checkParams(const ScoreParams& params) {
  if (params.frictions.empty()) throw InvalidArgument("score: give at least one friction (mu)");
  if (params.frictions.size() > kMaxScoreFrictions) {
    throw InvalidArgument(fmt::format("score: {} friction coefficients, at most {}",
                                      params.frictions.size(), kMaxScoreFrictions));
  }
  for (double mu : params.frictions) {
    if (!(mu >= 0) || !std::isfinite(mu))
      throw InvalidArgument(fmt::format("score: friction {} is not a finite number >= 0", mu));
  }
  if (params.compute_robustness && params.robustness.samples < 1)
    throw InvalidArgument("score: robustness needs at least one sample");
}

// A count as a whole number, saturated (the products below may pass 2^64 for hostile inputs).
std::uint64_t saturated(double count) {
  constexpr double kLargest = 18446744073709549568.0;  // the largest double below 2^64
  return count >= kLargest ? UINT64_MAX : static_cast<std::uint64_t>(count);
}

// The quality measure at `mu` with the hand's contact model unless the caller chose one.
grasping::QualityParams qualityAt(const ScoreParams& params, const grasping::HandModel& hand,
                                  double mu) {
  grasping::QualityParams quality = params.quality;
  quality.friction = mu;
  return grasping::withHandContactModel(quality, hand);
}

GraspScore scoreOne(grasping::GraspSimulator& simulator, const grasping::GraspPlacement& placement,
                    const ScoreParams& params, double& robustness_s) {
  Stopwatch watch;
  const grasping::HandModel& hand = simulator.hand();
  GraspScore score;
  score.id = placement.id;
  score.preshape = placement.preshape;
  const grasping::Preshape& preshape = hand.preshape(placement.preshape);
  const grasping::ClosingResult closing =
      simulator.close(placement.hand_pose, preshape, params.closing);
  score.joints = closing.joints;
  score.contacts = closing.contacts;
  if (!closing.status.ok()) {
    score.closing_failure = closing.reason;
    score.colliding_link = closing.colliding_link;
  }
  // The grasp as the planners record it: what ranking::evaluateRobustness perturbs.
  grasping::Grasp grasp;
  grasp.preshape = placement.preshape;
  grasp.hand_pose = placement.hand_pose;
  grasp.joints = closing.joints;
  grasp.contacts = closing.contacts;
  for (double mu : params.frictions) {
    FrictionScore at;
    at.mu = mu;
    if (closing.status.ok()) {
      const grasping::QualityParams quality = qualityAt(params, hand, mu);
      const grasping::WrenchSpaceResult judged =
          grasping::evaluateGrasp(closing.contacts, simulator.object(), quality);
      at.force_closure = judged.force_closure;
      at.closure_margin = judged.closure_margin;
      at.epsilon = judged.epsilon;
      if (params.compute_robustness) {
        ranking::RobustnessParams robustness = params.robustness;
        robustness.quality = quality;
        robustness.closing = params.closing;
        // grasp_index 0 for every grasp: the convention plan and run share (score.h).
        at.robustness = ranking::evaluateRobustness(simulator, grasp, robustness, 0);
        robustness_s += at.robustness->time_s;
      }
    }
    score.by_friction.push_back(std::move(at));
  }
  score.time_s = watch.seconds();
  return score;
}

nlohmann::json contactsJson(const std::vector<grasping::Contact>& contacts) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& c : contacts) {
    list.push_back({{"point", toJson(c.point)},
                    {"normal", toJson(c.normal)},
                    {"link", c.link},
                    {"palm", c.palm}});
  }
  return list;
}

nlohmann::json robustnessJson(const std::optional<ranking::RobustnessResult>& r) {
  if (!r) return nullptr;
  return {{"r", r->score},
          {"ci95", {r->wilson_low, r->wilson_high}},
          {"samples", r->samples},
          {"force_closure", r->force_closure},
          {"collisions", r->collisions},
          {"guarded_holds", r->guarded_holds},
          {"settled_holds", r->settled_holds},
          {"closing_failures", r->closing_failures},
          {"no_force_closure", r->no_force_closure},
          {"too_weak", r->too_weak},
          {"time_s", r->time_s}};
}

// Force-closure count and mean r over the closed grasps, at friction number `k`.
struct FrictionTotals {
  std::size_t force_closure = 0;
  std::size_t scored = 0;  // grasps with a robustness score
  double r_sum = 0;
};

FrictionTotals totalsAt(const ScoreResult& result, std::size_t k) {
  FrictionTotals totals;
  for (const auto& g : result.grasps) {
    const FrictionScore& at = g.by_friction[k];
    totals.force_closure += at.force_closure;
    if (at.robustness) {
      ++totals.scored;
      totals.r_sum += at.robustness->score;
    }
  }
  return totals;
}

}  // namespace

std::uint64_t scoreClosings(std::size_t grasps, const ScoreParams& params) {
  const double per_grasp =
      1.0 + (params.compute_robustness ? static_cast<double>(params.frictions.size()) *
                                             std::max(params.robustness.samples, 0)
                                       : 0.0);
  return saturated(static_cast<double>(grasps) * per_grasp);
}

void checkScoreWork(std::size_t grasps, const ScoreParams& params) {
  const std::uint64_t closings = scoreClosings(grasps, params);
  if (closings <= ranking::kMaxScoreClosings) return;
  const std::string samples = params.compute_robustness
                                  ? fmt::format(" at {} friction(s) x {} robustness samples",
                                                params.frictions.size(), params.robustness.samples)
                                  : std::string();
  throw InvalidArgument(fmt::format(
      "scoring {} grasps{} is {} hand closings, more than the limit of {} per command; score "
      "fewer grasps at a time or take fewer samples",
      grasps, samples, closings, ranking::kMaxScoreClosings));
}

ScoreResult scoreGrasps(const grasping::HandModel& hand, const grasping::GraspObject& object,
                        const std::vector<grasping::GraspPlacement>& grasps,
                        const ScoreParams& params) {
  checkParams(params);
  checkScoreWork(grasps.size(), params);
  Stopwatch watch;
  ScoreResult result;
  result.grasps.reserve(grasps.size());
  grasping::GraspSimulator simulator(hand, object);
  ProgressReporter progress("score: grasps", grasps.size(), kGraspsProgressIntervalS);
  for (const auto& placement : grasps) {
    result.grasps.push_back(scoreOne(simulator, placement, params, result.robustness_s));
    result.closed += result.grasps.back().closing_failure.empty();
    // Quick scorings print no progress: the first line comes after one interval.
    if (watch.seconds() >= kGraspsProgressIntervalS) progress.step(result.grasps.size());
  }
  result.time_s = watch.seconds();
  if (grasps.empty()) {
    result.status = Status::Make(StatusCode::kNoResult, "no grasps to score");
  } else if (result.closed == 0) {
    result.status =
        Status::Make(StatusCode::kNoResult, "no grasp closed (see each grasp's closing failure)");
  }
  log().info("scored {} grasp(s) with {}: {} closed, {:.2f} s", grasps.size(), hand.name(),
             result.closed, result.time_s);
  return result;
}

nlohmann::json scoreToJson(const ScoreResult& result, const ScoreParams& params,
                           const grasping::HandModel& hand, const std::string& object,
                           const std::string& grasps_file) {
  const grasping::QualityParams quality = qualityAt(params, hand, params.frictions.front());
  const auto& rp = params.robustness;
  nlohmann::json robustness = nullptr;
  if (params.compute_robustness) {
    robustness = {{"samples", rp.samples},
                  {"variant", toString(rp.variant)},
                  {"seed", rp.seed},
                  {"grasp_index", 0},
                  // The sigmas used: set ones, else the variant's defaults.
                  {"sigma_m", ranking::positionSigmaM(rp)},
                  {"sigma_rad", ranking::orientationSigmaRad(rp)},
                  {"load_check", rp.load ? nlohmann::json{{"mass_kg", rp.load->mass_kg},
                                                          {"torque_share", rp.load->torque_share}}
                                         : nlohmann::json(nullptr)}};
  }
  nlohmann::json per_mu = nlohmann::json::array();
  for (std::size_t k = 0; k < params.frictions.size(); ++k) {
    const FrictionTotals totals = totalsAt(result, k);
    per_mu.push_back({{"mu", params.frictions[k]},
                      {"force_closure", totals.force_closure},
                      {"mean_r", totals.scored ? nlohmann::json(totals.r_sum / totals.scored)
                                               : nlohmann::json(nullptr)}});
  }
  nlohmann::json grasps = nlohmann::json::array();
  for (const auto& g : result.grasps) {
    nlohmann::json closure = nlohmann::json::array();
    for (const auto& at : g.by_friction) {
      closure.push_back({{"mu", at.mu},
                         {"force_closure", at.force_closure},
                         {"margin", numberOrNull(at.closure_margin)},
                         {"epsilon", at.epsilon},
                         {"robustness", robustnessJson(at.robustness)}});
    }
    nlohmann::json joints = nlohmann::json::object();
    for (std::size_t j = 0; j < hand.joints().size(); ++j) {
      const auto index = static_cast<Eigen::Index>(j);
      if (hand.joints()[j].movable() && index < g.joints.size())
        joints[hand.joints()[j].name] = g.joints[index];
    }
    grasps.push_back(
        {{"id", g.id},
         {"preshape", g.preshape},
         {"closed", g.closing_failure.empty()},
         {"closing_failure",
          g.closing_failure.empty() ? nlohmann::json(nullptr) : nlohmann::json(g.closing_failure)},
         {"colliding_link",
          g.colliding_link.empty() ? nlohmann::json(nullptr) : nlohmann::json(g.colliding_link)},
         {"contacts", g.contacts.size()},
         {"contact_list", contactsJson(g.contacts)},
         {"joints", joints},
         {"closure", closure},
         {"time_s", g.time_s}});
  }
  const std::size_t n = result.grasps.size();
  return {{"schema", "skelgrasp.score/1"},
          {"grasps_file", grasps_file},
          {"object", object},
          {"hand", hand.name()},
          {"units", "m"},
          {"parameters",
           {{"mu", params.frictions},
            {"closing", grasping::toString(params.closing.method)},
            {"contact_patch", grasping::toString(params.closing.contact_patch)},
            {"fc_test", grasping::toString(quality.fc_test)},
            {"reference_compat", quality.reference_compat},
            {"cone_edges", quality.cone_edges},
            {"torsional_friction_m", quality.torsional_friction_m.value_or(0.0)},
            {"robustness", robustness}}},
          {"status", toJson(result.status)},
          {"summary",
           {{"grasps", n},
            {"closed", result.closed},
            {"per_mu", per_mu},
            {"time_s", result.time_s},
            {"robustness_s", result.robustness_s},
            {"ms_per_grasp",
             n ? nlohmann::json(kMillisecondsPerSecond * result.time_s / static_cast<double>(n))
               : nlohmann::json(nullptr)}}},
          {"grasps", grasps}};
}

std::string scoreSummaryLine(const ScoreResult& result, const ScoreParams& params) {
  std::string line =
      fmt::format("scored {} grasp(s), {} closed", result.grasps.size(), result.closed);
  for (std::size_t k = 0; k < params.frictions.size(); ++k) {
    const FrictionTotals totals = totalsAt(result, k);
    line += fmt::format("; mu {}: {} force closure", params.frictions[k], totals.force_closure);
    if (totals.scored)
      line += fmt::format(", mean r {:.2f}", totals.r_sum / static_cast<double>(totals.scored));
  }
  const double ms_per_grasp = result.grasps.empty() ? 0.0
                                                    : kMillisecondsPerSecond * result.time_s /
                                                          static_cast<double>(result.grasps.size());
  return line + fmt::format("; {:.2f} s ({:.0f} ms per grasp)", result.time_s, ms_per_grasp);
}

}  // namespace skelgrasp::evaluation
