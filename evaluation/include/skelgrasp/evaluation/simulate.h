#pragma once
// Given grasps executed by the physics judge (`skelgrasp simulate`, docs/physics.md): each grasp,
// known by its hand pose and preshape, is executed in the rigid-body simulation at one or several
// friction coefficients; with samples, also under the pose error of the robustness score r (the
// same seeded errors about the same centre), which gives the physical robustness sim_r: the share
// of perturbed executions that hold.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/common/error.h"
#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/grasping/io/grasps_file.h"
#include "skelgrasp/grasping/simulation/grasp_object.h"
#include "skelgrasp/physics/execution.h"
#include "skelgrasp/physics/physical_object.h"
#include "skelgrasp/ranking/robustness.h"

namespace skelgrasp::evaluation {

// Most perturbed executions per grasp and friction: a Wilson interval is already ±0.03 at 1000.
inline constexpr int kMaxSimulationSamples = 10'000;
// Most physics executions one simulation of a grasps file may run (`simulate`, Python simulate):
// grasps x frictions x (1 + samples). About ten hours of CPU at the 240-420 ms an execution costs
// (docs/physics.md); beyond it a request is refused before any work.
inline constexpr std::uint64_t kMaxSimulatedExecutions = 100'000;

struct SimulateParams {
  // Friction coefficients, each judged in turn (as ScoreParams::frictions).
  std::vector<double> frictions = {physics::kDefaultFriction};
  // The protocol; its friction is replaced by each of `frictions`.
  physics::JudgeParams judge;
  // Perturbed executions per grasp and friction for sim_r (0: the nominal execution only).
  int samples = 0;
  // The pose errors of r: seed, variant (its sigmas: 10 mm and 5 degrees for the default) and
  // explicit sigmas. Only samplePoseError's inputs are used.
  ranking::RobustnessParams robustness;
  // The kinematic closing that finds the grasp's contacts, whose mean point the pose errors act
  // about (as for r).
  grasping::ClosingParams closing;
};

struct PhysicalRobustness {
  int samples = 0;
  int holds = 0;
  double sim_r = 0;
  double ci95_low = 0, ci95_high = 1;
  // Why the other executions failed.
  int start_failures = 0, closing_failures = 0, disturbance_failures = 0;
  std::vector<bool> held;  // per sample, in sample order
};

struct FrictionSimulation {
  double mu = 0;
  physics::ExecutionResult nominal;
  std::optional<PhysicalRobustness> robustness;  // with samples > 0
};

struct GraspSimulation {
  nlohmann::json id;
  std::string preshape;
  std::vector<FrictionSimulation> by_friction;
  double cpu_s = 0;  // summed thread CPU time of its executions
};

struct SimulateResult {
  Status status;  // kNoResult when there was no grasp
  std::vector<GraspSimulation> grasps;
  std::size_t executions = 0;
  double execution_cpu_s = 0;  // summed over every execution
  double time_s = 0;           // wall time, the object's preparation excluded
};

// The physics executions simulateGrasps runs for `grasps` grasps: grasps x frictions x
// (1 + samples).
std::uint64_t simulatedExecutions(std::size_t grasps, const SimulateParams& params);
// Throws InvalidArgument when simulatedExecutions exceeds kMaxSimulatedExecutions, saying how the
// count arises.
void checkSimulationWork(std::size_t grasps, const SimulateParams& params);

// Throws InvalidArgument for bad parameters (no friction, more than kMaxScoreFrictions, a
// negative one, samples outside [0, kMaxSimulationSamples], bad judge parameters, more work than
// kMaxSimulatedExecutions). `object` and
// `physical` must be the same mesh in the grasps' frame.
SimulateResult simulateGrasps(const grasping::HandModel& hand, const grasping::GraspObject& object,
                              const physics::PhysicalObject& physical,
                              const std::vector<grasping::GraspPlacement>& grasps,
                              const SimulateParams& params = {});

// The skelgrasp.simulation/1 document (docs/physics.md).
nlohmann::json simulationToJson(const SimulateResult& result, const SimulateParams& params,
                                const grasping::HandModel& hand,
                                const physics::PhysicalObject& physical, const std::string& object,
                                const std::string& grasps_file);

// One line for the terminal: grasps, nominal holds and mean sim_r per mu, CPU per execution.
std::string simulationSummaryLine(const SimulateResult& result, const SimulateParams& params);

}  // namespace skelgrasp::evaluation
