#include "skelgrasp/grasping/planning/hypothesis.h"

#include <algorithm>
#include <cmath>

namespace skelgrasp::grasping {

const char* toString(GraspType type) {
  return type == GraspType::kPower ? "power" : "precision";
}

std::optional<GraspType> graspTypeNamed(const std::string& name) {
  for (GraspType type : {GraspType::kPrecision, GraspType::kPower}) {
    if (name == toString(type)) return type;
  }
  return std::nullopt;
}

HypothesisOutcome evaluateHypothesis(GraspSimulator& simulator, const Pose& gcp,
                                     const Preshape& preshape, const HypothesisParams& params) {
  return judgeHypothesis(closeHypothesis(simulator, gcp, preshape, params), simulator.object(),
                         params);
}

namespace {
// Approaches within this angle of straight down onto the support plane may be lifted
// (HypothesisParams::scene_lift_max_m): cos 45 degrees.
constexpr double kLiftMinDownCosine = 0.70710678118654752;

// How many whole steps fit in a length (a length that is a multiple of the step in decimal, as
// 0.150 / 0.001, must not lose its last step to rounding).
int wholeSteps(double length_m, double step_m) {
  constexpr double kRounding = 1e-9;
  return static_cast<int>(std::floor(length_m / step_m + kRounding));
}

bool comesDownOntoPlane(const SceneChecker& scene, const Eigen::Vector3d& approach) {
  return scene.plane() &&
         -approach.dot(scene.plane()->coefficients.head<3>()) >= kLiftMinDownCosine;
}
}  // namespace

HypothesisOutcome closeHypothesis(GraspSimulator& simulator, const Pose& gcp,
                                  const Preshape& preshape, const HypothesisParams& params) {
  if (!(params.scene_lift_max_m >= 0) ||
      (params.scene_lift_max_m > 0 && !(params.scene_lift_step_m > 0))) {
    throw InvalidArgument("hypothesis: the scene lift must be >= 0, its step > 0");
  }
  HypothesisOutcome out;
  const Eigen::Vector3d approach = gcp.rotation().col(2);
  auto poseAt = [&](double retreat) {
    Pose moved = gcp;
    moved.translation() -= retreat * approach;
    return moved;
  };
  // Back off until the open hand is free of the object: coarse steps of 8 retreat steps, then the
  // first free fine step after the last colliding coarse one (a free gap narrower than a coarse
  // step before it is not looked for).
  auto freeAt = [&](int step) {
    return !simulator.inCollision(
        simulator.handPoseForGcp(poseAt(step * params.retreat_step_m), preshape), preshape.joints);
  };
  const int steps = wholeSteps(params.max_retreat_m, params.retreat_step_m);
  constexpr int kCoarse = 8;
  int first_free = -1;
  int last_colliding = -1;
  for (int i = 0;; i = std::min(i + kCoarse, steps)) {
    if (freeAt(i)) {
      first_free = i;
      break;
    }
    last_colliding = i;
    if (i == steps) break;
  }
  if (first_free < 0) {
    out.reason = reason::kRetreatExhausted;
    return out;
  }
  for (int i = last_colliding + 1; i < first_free; ++i) {
    if (freeAt(i)) {
      first_free = i;
      break;
    }
  }
  double retreat = first_free * params.retreat_step_m;
  double extra = params.extra_retreat_m;
  if (params.clearance) {
    const double clearance = params.clearance(gcp.translation());
    if (!(clearance >= 0) || !std::isfinite(clearance)) {
      throw InvalidArgument("hypothesis: the clearance must be finite and >= 0");
    }
    extra = std::max(extra, clearance);
  }
  if (extra > 0 &&
      !simulator.inCollision(simulator.handPoseForGcp(poseAt(retreat + extra), preshape),
                             preshape.joints)) {
    retreat += extra;
  }
  Grasp grasp;
  grasp.preshape = preshape.name;
  grasp.gcp_pose = poseAt(retreat);
  grasp.hand_pose = simulator.handPoseForGcp(grasp.gcp_pose, preshape);
  grasp.retreat_m = retreat;
  if (params.scene) {
    SceneCheckResult scene = params.scene->check(grasp.hand_pose, preshape.joints, approach);
    if (scene.collision && comesDownOntoPlane(*params.scene, approach)) {
      const int lift_steps = params.scene_lift_max_m > 0
                                 ? wholeSteps(params.scene_lift_max_m, params.scene_lift_step_m)
                                 : 0;
      for (int k = 1; k <= lift_steps && scene.collision; ++k) {
        const double lifted = retreat + k * params.scene_lift_step_m;
        const Pose lifted_hand = simulator.handPoseForGcp(poseAt(lifted), preshape);
        scene = params.scene->check(lifted_hand, preshape.joints, approach);
        if (!scene.collision) {
          grasp.gcp_pose = poseAt(lifted);
          grasp.hand_pose = lifted_hand;
          grasp.retreat_m = lifted;
        }
      }
    }
    if (scene.collision) {
      out.reason = reason::kSceneCollision;
      out.scene_hit = std::move(scene);
      return out;
    }
  }
  const ClosingResult closing = simulator.close(grasp.hand_pose, preshape, params.closing);
  grasp.joints = closing.joints;
  if (!closing.status.ok()) {
    out.reason =
        closing.reason == "start_collision" ? reason::kStartCollision : reason::kTooFewContacts;
    return out;
  }
  // The open hand and its approach were clear; the fingers closing around a small object can still
  // sweep into the table or a neighbour (found with the fallback's side grasps of the demo ball).
  if (params.scene) {
    const SceneCheckResult closed = params.scene->checkPose(grasp.hand_pose, closing.joints);
    if (closed.collision) {
      out.reason = reason::kSceneCollision;
      out.scene_hit = closed;
      return out;
    }
  }
  out.generated = true;
  grasp.contacts = closing.contacts;
  out.grasp = std::move(grasp);
  return out;
}

HypothesisOutcome judgeHypothesis(HypothesisOutcome&& closed, const GraspObject& object,
                                  const HypothesisParams& params) {
  if (!closed.generated || !closed.grasp) return std::move(closed);
  HypothesisOutcome out;
  out.generated = true;
  Grasp grasp = std::move(*closed.grasp);
  const WrenchSpaceResult quality = evaluateGrasp(grasp.contacts, object, params.quality);
  grasp.force_closure = quality.force_closure;
  grasp.epsilon = quality.epsilon;
  grasp.volume = quality.volume;
  if (!quality.force_closure) {
    out.reason = reason::kNotForceClosure;
    return out;
  }
  if (quality.epsilon < params.min_epsilon) {
    out.reason = reason::kEpsilonBelowMinimum;
    return out;
  }
  out.grasp = std::move(grasp);
  return out;
}

std::optional<Grasp> countOutcome(HypothesisOutcome&& outcome, PlanSummary& summary) {
  summary.generated += outcome.generated;
  if (outcome.generated && (outcome.grasp || outcome.reason != reason::kNotForceClosure)) {
    ++summary.force_closure;
  }
  if (!outcome.grasp) {
    ++summary.rejections[outcome.reason];
    const SceneCheckResult& hit = outcome.scene_hit;
    if (hit.collision) {
      ++summary.scene_collision_links[hit.link];
      ++summary.scene_collision_obstacles[hit.obstacle];
      if (hit.obstacle == "octree") ++summary.scene_collision_labels[hit.obstacle_label];
    }
  }
  return std::move(outcome.grasp);
}

void PlanSummary::add(const PlanSummary& other) {
  hypotheses += other.hypotheses;
  poses += other.poses;
  generated += other.generated;
  force_closure += other.force_closure;
  planning_s += other.planning_s;
  for (const auto& [why, count] : other.rejections) rejections[why] += count;
  for (const auto& [link, count] : other.scene_collision_links)
    scene_collision_links[link] += count;
  for (const auto& [obstacle, count] : other.scene_collision_obstacles)
    scene_collision_obstacles[obstacle] += count;
  for (const auto& [label, count] : other.scene_collision_labels)
    scene_collision_labels[label] += count;
  precision += other.precision;
  power += other.power;
  timed_out = timed_out || other.timed_out;
  max_grasps_reached = max_grasps_reached || other.max_grasps_reached;
}

void finishPlan(PlanResult& result, double planning_s) {
  std::stable_sort(result.grasps.begin(), result.grasps.end(),
                   [](const Grasp& a, const Grasp& b) { return a.epsilon > b.epsilon; });
  for (std::size_t i = 0; i < result.grasps.size(); ++i) result.grasps[i].id = static_cast<int>(i);
  result.summary.planning_s = planning_s;
  if (result.grasps.empty()) {
    result.status = Status::Make(StatusCode::kNoResult, "no grasp found; see the rejection counts");
  }
}

}  // namespace skelgrasp::grasping
