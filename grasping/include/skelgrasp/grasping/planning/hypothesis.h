#pragma once
// Turning one hand pose hypothesis into a grasp: back off until collision-free, optionally retreat
// further, close the fingers, judge the contacts. Shared by the planners.
#include <functional>
#include <optional>

#include "skelgrasp/grasping/grasp.h"
#include "skelgrasp/grasping/planning/scene.h"
#include "skelgrasp/grasping/quality/quality.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"

namespace skelgrasp::grasping {

struct HypothesisParams {
  double retreat_step_m = 0.001;  // back-off step along the approach direction
  double max_retreat_m = 0.150;   // give up beyond this
  double extra_retreat_m = 0;     // then this much further when still collision-free (power)
  // Clearance from surface whose true position is uncertain (a reconstruction's noisy or
  // filled-in surface): when set, it gives for a hypothesis' grasp centre point (object frame) how
  // far the true surface may lie outside the mesh around it (metres, >= 0), and the open hand is
  // backed off beyond its first collision-free pose by at least that much (the larger of it and
  // extra_retreat_m, taken where the pose there is free too), so that it does not start inside the
  // real object (docs/pipeline.md, "Clearance from uncertain surface"). Unset: the mesh is exact.
  std::function<double(const Eigen::Vector3d& gcp)> clearance;
  // Force-closure grasps with a lower epsilon are rejected (low_epsilon); 0 keeps all of them.
  double min_epsilon = 0;
  QualityParams quality;
  ClosingParams closing;
  // When set, poses whose open hand or straight approach hits the scene are rejected
  // (scene_collision) before closing. Object and scene share one frame (the scan's).
  const SceneChecker* scene = nullptr;
  // A hand coming down onto the support plane (approach within 45 degrees of straight down) whose
  // placed open hand or approach hits the scene is lifted back along its approach in
  // scene_lift_step_m steps, up to scene_lift_max_m, until the scene check passes: fingers that
  // close around a flat object beside the table grasp it higher up instead of being rejected
  // (docs/planning.md, "The candidate pool beyond the skeleton strategies"). 0: no lift, the pose
  // is rejected (scene_collision).
  double scene_lift_max_m = 0.02;
  double scene_lift_step_m = 0.002;
};

struct HypothesisOutcome {
  std::optional<Grasp> grasp;    // set when kept (force closure and epsilon >= minimum)
  const char* reason = nullptr;  // set when not kept
  bool generated = false;        // placed collision-free and closed
  SceneCheckResult scene_hit;    // scene_collision: the first colliding link and what it hit
};

// `gcp` is the hypothesis' grasp centre point pose (object frame; z = approach direction).
// The same as judgeHypothesis(closeHypothesis(...)).
HypothesisOutcome evaluateHypothesis(GraspSimulator& simulator, const Pose& gcp,
                                     const Preshape& preshape, const HypothesisParams& params);

// The first half of evaluateHypothesis: back off, retreat, scene check, close. `generated` with
// `grasp` set (pose, joints, contacts; quality not judged yet) when it closed with enough contacts,
// else `reason` (and `scene_hit`). Local refinement (refinement.h) closes many poses this way.
HypothesisOutcome closeHypothesis(GraspSimulator& simulator, const Pose& gcp,
                                  const Preshape& preshape, const HypothesisParams& params);
// The second half: quality of a closed hypothesis' grasp, kept or rejected (not_force_closure,
// epsilon_below_minimum). Outcomes that did not close are returned unchanged.
HypothesisOutcome judgeHypothesis(HypothesisOutcome&& closed, const GraspObject& object,
                                  const HypothesisParams& params);

// Counts an outcome in the summary (generated, force closure, rejection reason and scene link);
// returns the grasp when the hypothesis was kept.
std::optional<Grasp> countOutcome(HypothesisOutcome&& outcome, PlanSummary& summary);

// Ends a planner run: grasps sorted by epsilon (best first) and numbered, the planning time set,
// status kNoResult when nothing was kept.
void finishPlan(PlanResult& result, double planning_s);

}  // namespace skelgrasp::grasping
