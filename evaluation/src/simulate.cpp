#include "skelgrasp/evaluation/simulate.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "skelgrasp/common/json.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/evaluation/score.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"

namespace skelgrasp::evaluation {
namespace {

void checkParams(const SimulateParams& params) {
  if (params.frictions.empty()) throw InvalidArgument("simulate: give at least one friction (mu)");
  if (params.frictions.size() > kMaxScoreFrictions) {
    throw InvalidArgument(fmt::format("simulate: {} friction coefficients, at most {}",
                                      params.frictions.size(), kMaxScoreFrictions));
  }
  for (double mu : params.frictions) {
    if (!(mu >= 0) || !std::isfinite(mu))
      throw InvalidArgument(fmt::format("simulate: friction {} is not a finite number >= 0", mu));
  }
  if (params.samples < 0 || params.samples > kMaxSimulationSamples) {
    throw InvalidArgument(fmt::format("simulate: samples {}: must be in [0, {}]", params.samples,
                                      kMaxSimulationSamples));
  }
  const double sigma_m = ranking::positionSigmaM(params.robustness);
  const double sigma_rad = ranking::orientationSigmaRad(params.robustness);
  if (!(sigma_m >= 0) || !std::isfinite(sigma_m) || !(sigma_rad >= 0) ||
      !std::isfinite(sigma_rad)) {
    throw InvalidArgument("simulate: pose error sigmas must be finite and >= 0");
  }
}

// The point the pose errors act about, as for r: the mean of the contacts the kinematic closing
// reaches; the grasp centre point when it reaches none.
Eigen::Vector3d perturbationCentreOf(grasping::GraspSimulator& simulator,
                                     const grasping::GraspPlacement& placement,
                                     const grasping::ClosingParams& closing) {
  const auto& preshape = simulator.hand().preshape(placement.preshape);
  const auto closed = simulator.close(placement.hand_pose, preshape, closing);
  if (closed.contacts.empty())
    return (placement.hand_pose * simulator.hand().gcpInRoot(preshape)).translation();
  grasping::Grasp grasp;
  grasp.contacts = closed.contacts;
  return ranking::perturbationCentre(grasp);
}

PhysicalRobustness physicalRobustness(const grasping::HandModel& hand,
                                      const physics::PhysicalObject& physical,
                                      const grasping::GraspPlacement& placement,
                                      const Eigen::Vector3d& centre,
                                      const physics::JudgeParams& judge,
                                      const SimulateParams& params, double& cpu_s) {
  const auto& preshape = hand.preshape(placement.preshape);
  std::vector<physics::ExecutionResult> runs(static_cast<std::size_t>(params.samples));
  tbb::parallel_for(0, params.samples, [&](int i) {
    // grasp_index 0, as score and plan: the same errors as the grasp's r.
    const Pose pose = ranking::perturbedPose(placement.hand_pose,
                                             ranking::samplePoseError(params.robustness, 0, i),
                                             centre, params.robustness.variant);
    runs[static_cast<std::size_t>(i)] =
        physics::executeGrasp(hand, physical, pose, preshape, judge);
  });
  PhysicalRobustness robustness;
  robustness.samples = params.samples;
  for (const auto& run : runs) {
    robustness.held.push_back(run.holds);
    robustness.holds += run.holds;
    robustness.start_failures += run.failed_phase == physics::ExecutionPhase::kStart;
    robustness.closing_failures += run.failed_phase == physics::ExecutionPhase::kClosing;
    robustness.disturbance_failures += run.failed_phase == physics::ExecutionPhase::kDisturbance;
    cpu_s += run.cpu_s;
  }
  robustness.sim_r = static_cast<double>(robustness.holds) / params.samples;
  std::tie(robustness.ci95_low, robustness.ci95_high) =
      ranking::wilsonInterval(robustness.holds, robustness.samples);
  return robustness;
}

nlohmann::json phaseJson(const physics::ExecutionResult::PhaseCost& cost) {
  return {{"cpu_s", cost.cpu_s}, {"steps", cost.steps}};
}

nlohmann::json executionJson(const physics::ExecutionResult& run) {
  nlohmann::json disturbances = nlohmann::json::array();
  for (const auto& d : run.disturbances) {
    disturbances.push_back({{"direction", toJson(d.direction)},
                            {"held", d.held},
                            {"displacement_m", d.displacement_m},
                            {"rotation_rad", d.rotation_rad},
                            {"simulated_s", d.simulated_s}});
  }
  return {{"holds", run.holds},
          {"failed_phase", run.holds ? nlohmann::json(nullptr)
                                     : nlohmann::json(physics::toString(run.failed_phase))},
          {"reason", run.reason.empty() ? nlohmann::json(nullptr) : nlohmann::json(run.reason)},
          {"start_penetration_m", run.start_penetration_m},
          {"penetrating_link", run.penetrating_link.empty() ? nlohmann::json(nullptr)
                                                            : nlohmann::json(run.penetrating_link)},
          {"closing_displacement_m", run.closing_displacement_m},
          {"closing_rotation_rad", run.closing_rotation_rad},
          {"touching_links", run.touching_links},
          {"disturbances", disturbances},
          {"steps", run.steps},
          {"cpu_s", run.cpu_s},
          {"cost",
           {{"start", phaseJson(run.start_cost)},
            {"closing", phaseJson(run.closing_cost)},
            {"release", phaseJson(run.release_cost)},
            {"disturbances", phaseJson(run.disturbance_cost)}}}};
}

nlohmann::json robustnessJson(const std::optional<PhysicalRobustness>& r) {
  if (!r) return nullptr;
  return {{"sim_r", r->sim_r},
          {"ci95", {r->ci95_low, r->ci95_high}},
          {"samples", r->samples},
          {"holds", r->holds},
          {"start_failures", r->start_failures},
          {"closing_failures", r->closing_failures},
          {"disturbance_failures", r->disturbance_failures}};
}

struct Totals {
  std::size_t holds = 0;
  std::size_t scored = 0;
  double sim_r_sum = 0;
};

Totals totalsAt(const SimulateResult& result, std::size_t k) {
  Totals totals;
  for (const auto& g : result.grasps) {
    const auto& at = g.by_friction[k];
    totals.holds += at.nominal.holds;
    if (at.robustness) {
      ++totals.scored;
      totals.sim_r_sum += at.robustness->sim_r;
    }
  }
  return totals;
}

}  // namespace

std::uint64_t simulatedExecutions(std::size_t grasps, const SimulateParams& params) {
  const double count = static_cast<double>(grasps) * static_cast<double>(params.frictions.size()) *
                       (1.0 + std::max(params.samples, 0));
  constexpr double kLargest = 18446744073709549568.0;  // the largest double below 2^64
  return count >= kLargest ? UINT64_MAX : static_cast<std::uint64_t>(count);
}

void checkSimulationWork(std::size_t grasps, const SimulateParams& params) {
  const std::uint64_t executions = simulatedExecutions(grasps, params);
  if (executions <= kMaxSimulatedExecutions) return;
  throw InvalidArgument(fmt::format(
      "simulating {} grasps at {} friction(s) x (1 + {} samples) is {} executions, more than the "
      "limit of {} per command; simulate fewer grasps at a time (--max-grasps) or take fewer "
      "samples",
      grasps, params.frictions.size(), params.samples, executions, kMaxSimulatedExecutions));
}

SimulateResult simulateGrasps(const grasping::HandModel& hand, const grasping::GraspObject& object,
                              const physics::PhysicalObject& physical,
                              const std::vector<grasping::GraspPlacement>& grasps,
                              const SimulateParams& params) {
  checkParams(params);
  checkSimulationWork(grasps.size(), params);
  Stopwatch watch;
  SimulateResult result;
  grasping::GraspSimulator simulator(hand, object);
  ProgressReporter progress("simulate: grasps", grasps.size(), kGraspsProgressIntervalS);
  for (const auto& placement : grasps) {
    GraspSimulation simulated;
    simulated.id = placement.id;
    simulated.preshape = placement.preshape;
    const auto& preshape = hand.preshape(placement.preshape);
    std::optional<Eigen::Vector3d> centre;
    for (double mu : params.frictions) {
      FrictionSimulation at;
      at.mu = mu;
      physics::JudgeParams judge = params.judge;
      judge.friction = mu;
      at.nominal = physics::executeGrasp(hand, physical, placement.hand_pose, preshape, judge);
      simulated.cpu_s += at.nominal.cpu_s;
      ++result.executions;
      if (params.samples > 0) {
        if (!centre) centre = perturbationCentreOf(simulator, placement, params.closing);
        at.robustness =
            physicalRobustness(hand, physical, placement, *centre, judge, params, simulated.cpu_s);
        result.executions += static_cast<std::size_t>(params.samples);
      }
      simulated.by_friction.push_back(std::move(at));
    }
    result.execution_cpu_s += simulated.cpu_s;
    result.grasps.push_back(std::move(simulated));
    // Quick simulations print no progress: the first line comes after one interval.
    if (watch.seconds() >= kGraspsProgressIntervalS) progress.step(result.grasps.size());
  }
  result.time_s = watch.seconds();
  if (grasps.empty()) result.status = Status::Make(StatusCode::kNoResult, "no grasps to simulate");
  log().info("simulated {} grasp(s) with {}: {} executions, {:.2f} s", grasps.size(), hand.name(),
             result.executions, result.time_s);
  return result;
}

nlohmann::json simulationToJson(const SimulateResult& result, const SimulateParams& params,
                                const grasping::HandModel& hand,
                                const physics::PhysicalObject& physical, const std::string& object,
                                const std::string& grasps_file) {
  const auto& judge = params.judge;
  nlohmann::json robustness = nullptr;
  if (params.samples > 0) {
    robustness = {{"samples", params.samples},
                  {"seed", params.robustness.seed},
                  {"grasp_index", 0},
                  {"sigma_m", ranking::positionSigmaM(params.robustness)},
                  {"sigma_rad", ranking::orientationSigmaRad(params.robustness)}};
  }
  const auto torques = physics::jointTorqueLimits(hand, judge);
  nlohmann::json torque_limits = nlohmann::json::object();
  for (std::size_t j = 0; j < hand.joints().size(); ++j) {
    if (hand.joints()[j].movable()) torque_limits[hand.joints()[j].name] = torques[j];
  }
  nlohmann::json per_mu = nlohmann::json::array();
  for (std::size_t k = 0; k < params.frictions.size(); ++k) {
    const Totals totals = totalsAt(result, k);
    per_mu.push_back(
        {{"mu", params.frictions[k]},
         {"nominal_holds", totals.holds},
         {"mean_sim_r", totals.scored ? nlohmann::json(totals.sim_r_sum / totals.scored)
                                      : nlohmann::json(nullptr)}});
  }
  nlohmann::json grasps = nlohmann::json::array();
  for (const auto& g : result.grasps) {
    nlohmann::json by_mu = nlohmann::json::array();
    for (const auto& at : g.by_friction) {
      by_mu.push_back({{"mu", at.mu},
                       {"nominal", executionJson(at.nominal)},
                       {"robustness", robustnessJson(at.robustness)}});
    }
    grasps.push_back(
        {{"id", g.id}, {"preshape", g.preshape}, {"physics", by_mu}, {"cpu_s", g.cpu_s}});
  }
  const std::size_t executions = result.executions;
  return {{"schema", "skelgrasp.simulation/1"},
          {"grasps_file", grasps_file},
          {"object", object},
          {"hand", hand.name()},
          {"units", "m"},
          {"engine", "bullet"},
          {"parameters",
           {{"mu", params.frictions},
            {"mass_kg", physical.massKg()},
            {"disturbance_force_n",
             judge.disturbance_force_n.value_or(physical.massKg() * physics::kStandardGravity)},
            {"closing_time_s", judge.closing_time_s},
            {"disturbance_time_s", judge.disturbance_time_s},
            {"max_displacement_m", judge.max_displacement_m},
            {"max_rotation_rad", judge.max_rotation_rad},
            {"max_start_penetration_m", judge.max_start_penetration_m},
            {"time_step_s", judge.time_step_s},
            {"solver_iterations", judge.solver_iterations},
            {"joint_torque_limits", torque_limits},
            {"robustness", robustness}}},
          {"object_model",
           {{"volume_m3", physical.volumeM3()},
            {"center_of_mass", toJson(physical.centerOfMass())},
            {"collision_triangles", physical.closedSurface().faces.size()},
            {"shape_error_m", physical.shapeErrorM()},
            {"shape_error_p95_m", physical.shapeErrorP95M()},
            {"build_s", physical.buildSeconds()}}},
          {"status", toJson(result.status)},
          {"summary",
           {{"grasps", result.grasps.size()},
            {"per_mu", per_mu},
            {"executions", executions},
            {"ms_cpu_per_execution",
             executions ? nlohmann::json(1000.0 * result.execution_cpu_s / executions)
                        : nlohmann::json(nullptr)},
            {"time_s", result.time_s}}},
          {"grasps", grasps}};
}

std::string simulationSummaryLine(const SimulateResult& result, const SimulateParams& params) {
  std::string line = fmt::format("simulated {} grasp(s)", result.grasps.size());
  for (std::size_t k = 0; k < params.frictions.size(); ++k) {
    const Totals totals = totalsAt(result, k);
    line += fmt::format("; mu {}: {} hold", params.frictions[k], totals.holds);
    if (totals.scored)
      line +=
          fmt::format(", mean sim_r {:.2f}", totals.sim_r_sum / static_cast<double>(totals.scored));
  }
  const double ms = result.executions ? 1000.0 * result.execution_cpu_s / result.executions : 0.0;
  return line + fmt::format("; {:.2f} s ({:.1f} ms CPU per execution)", result.time_s, ms);
}

}  // namespace skelgrasp::evaluation
