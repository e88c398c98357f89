#pragma once
// The physics judge's figures over many planned grasps (`skelgrasp bench physics`, `evaluate
// --judge physics`): how many hold, their physical robustness sim_r, the robustness r the plan
// reported for them, and how well r ranks them (docs/physics.md).
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/common/error.h"

namespace skelgrasp::evaluation {

// One planned grasp as the model scored it and as the physics judge executed it.
struct JudgedGrasp {
  std::string object;
  std::string hand;
  int rank = 0;             // in the plan, 0 = best
  std::optional<double> r;  // the plan's robustness (unset: the grasp was not scored)
  bool nominal_holds = false;
  std::string failed_phase;     // "start", "closing", "disturbance"; empty when it held
  std::optional<double> sim_r;  // with samples
  double cpu_s = 0;             // CPU time of its executions
  int executions = 0;
};

// Spearman's rank correlation of two equally long series (average ranks for ties); NaN when they
// hold fewer than two values or either is constant.
double spearman(const std::vector<double>& x, const std::vector<double>& y);

struct PhysicsFigures {
  std::size_t objects = 0;  // objects judged
  std::size_t objects_with_grasps = 0;
  std::size_t grasps = 0;            // grasps executed
  double nominal_hold_rate = 0;      // share of grasps whose nominal pose holds
  std::optional<double> mean_sim_r;  // over grasps with samples
  std::optional<double> mean_r;      // over grasps with r and sim_r (the pooled comparison)
  std::optional<double> mean_r_minus_sim_r;
  double spearman_r_sim_r = 0;    // NaN when undefined
  double spearman_r_nominal = 0;  // r against the nominal outcome (1 held, 0 not)
  double ms_cpu_per_execution = 0;
};

// The figures of `grasps` (one hand's, say); `objects` and `objects_with_grasps` are the caller's
// counts (objects without grasps contribute none).
PhysicsFigures physicsFigures(const std::vector<JudgedGrasp>& grasps, std::size_t objects,
                              std::size_t objects_with_grasps);

}  // namespace skelgrasp::evaluation
