#include "skelgrasp/ranking/robust_refinement.h"

#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "skelgrasp/common/logging.h"
#include "skelgrasp/grasping/planning/compass_search.h"

namespace skelgrasp::ranking {
namespace {

// In the compass's order (RobustRefinementParams: standoff first, as it cures starts in collision).
enum Move { kStandoff, kShiftX, kShiftY, kRoll, kMoveCount };
using CompassSearch = grasping::CompassSearch<kMoveCount>;
using Moves = CompassSearch::Moves;

// Two closed poses whose hand roots are closer than this (m) and turned less than this (rad) are
// one pose: the retreat search sends different moves towards the object back to the same first
// free pose, and judging it twice would only spend samples.
constexpr double kSamePoseDistanceM = 1e-4;
constexpr double kSamePoseAngleRad = 1e-3;

// The preshapes the search may switch a grasp with preshape `current` to: the hand's "power" and
// "precision" other than `current`, its own type's first (an alternative such as the SDH's
// "claw" may go back to "power"), each type only where the hand does it. Not the
// alternatives: the planners already closed them at every pose of their type, and over the 58
// YCB meshes switching to them cost the SDH 1.2 s of ranking per object for no gain in r
// (docs/results.md).
std::vector<const grasping::Preshape*> switchPreshapes(const grasping::HandModel& hand,
                                                       const std::string& current) {
  const auto it = hand.preshapes().find(current);
  if (it == hand.preshapes().end() || !it->second.grasp_type) return {};
  const grasping::GraspType own = *it->second.grasp_type;
  const grasping::GraspType other = own == grasping::GraspType::kPower
                                        ? grasping::GraspType::kPrecision
                                        : grasping::GraspType::kPower;
  std::vector<const grasping::Preshape*> out;
  for (grasping::GraspType type : {own, other}) {
    if (!hand.thresholds().of(type)) continue;
    for (const grasping::Preshape* p : hand.plannerPreshapes(type, /*alternatives=*/false)) {
      if (p->name != current) out.push_back(p);
    }
  }
  return out;
}

bool samePose(const Pose& a, const Pose& b) {
  if ((a.translation() - b.translation()).norm() > kSamePoseDistanceM) return false;
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() <= kSamePoseAngleRad;
}

// The mean-shift error of a pose whose perturbed executions under `params` on `stream` held as
// `held` says (sample order): the mean of the pose errors that held. For a pose error e ~ N(0, S)
// and r_S the r smoothed by it, E[e | held] = S grad log r_S: the step climbs r, and it is the
// cross-entropy method's update of the search distribution's mean. None when all or none held
// (no direction).
std::optional<PoseError> meanHeldError(const std::vector<bool>& held,
                                       const RobustnessParams& params, std::uint64_t stream) {
  Eigen::Vector3d translation = Eigen::Vector3d::Zero(), rotation = Eigen::Vector3d::Zero();
  int holds = 0;
  for (std::size_t i = 0; i < held.size(); ++i) {
    if (!held[i]) continue;
    const PoseError error = samplePoseError(params, stream, static_cast<int>(i));
    const Eigen::AngleAxisd turn(error.rotation);
    translation += error.translation;
    // Rotation vectors average well at the paper's few degrees.
    rotation += turn.angle() * turn.axis();
    ++holds;
  }
  if (holds == 0 || holds == static_cast<int>(held.size())) return std::nullopt;
  rotation /= holds;
  PoseError mean;
  mean.translation = translation / holds;
  if (rotation.norm() > 0)
    mean.rotation = Eigen::AngleAxisd(rotation.norm(), rotation.normalized()).toRotationMatrix();
  return mean;
}

}  // namespace

RobustRefinementOutcome refineForRobustness(grasping::GraspSimulator& simulator,
                                            const grasping::Grasp& grasp,
                                            const grasping::HypothesisParams& planner,
                                            const RobustnessParams& robustness,
                                            const RobustRefinementParams& params,
                                            std::uint64_t stream) {
  if (!(params.max_evaluations >= 0 && params.samples >= 1 && params.min_gain_samples >= 0 &&
        params.shift_step_m > 0 && params.standoff_step_m > 0 && params.roll_step_rad > 0 &&
        params.max_shift_m >= 0 && params.max_standoff_m >= 0 && params.max_roll_rad >= 0 &&
        params.max_halvings >= 0 && params.mean_shift_steps >= 0)) {
    throw InvalidArgument(
        "robust refinement: steps must be > 0, samples >= 1, evaluations, gains, bounds, "
        "halvings and mean-shift steps >= 0");
  }
  const grasping::HandModel& hand = simulator.hand();
  RobustnessParams search = robustness;
  search.samples = params.samples;
  RobustRefinementOutcome out;
  out.grasp = grasp;
  if (grasp.contacts.empty()) return out;
  const RobustnessResult seed_r = evaluateRobustness(simulator, grasp, search, stream);
  int best_holds = seed_r.force_closure;
  // Which of the search samples the best pose so far held in: where the mean shift moves it.
  std::vector<bool> best_held = seed_r.held;
  out.search_r_before = out.search_r_after = seed_r.score;
  // No pose can beat one that held in every sample by the required gain.
  if (best_holds + params.min_gain_samples > params.samples) return out;

  // The planner's hypothesis: the grasp centre point before it was backed off. Every move starts
  // there and is backed off again as the planner backs off, so a moved pose is one the planner
  // could have proposed.
  const Eigen::Vector3d approach = grasp.gcp_pose.linear().col(2);
  Pose hypothesis = grasp.gcp_pose;
  hypothesis.translation() += grasp.retreat_m * approach;
  auto baseExtraRetreat = [&](const grasping::Preshape& preshape) {
    return preshape.grasp_type == grasping::GraspType::kPower ? hand.thresholds().power_retreat_m
                                                              : 0.0;
  };

  // The search needs only the verdict; epsilon and volume (a hull each) are computed for the pose
  // it returns. Unless a minimum epsilon makes epsilon part of the verdict.
  const bool verdict_only = !(planner.min_epsilon > 0);
  std::vector<Pose> tried = {grasp.hand_pose};
  int evaluation_limit = params.max_evaluations;
  auto judge = [&](const Pose& gcp, const grasping::Preshape& preshape, double standoff) -> bool {
    if (out.evaluations >= evaluation_limit) return false;
    ++out.evaluations;
    grasping::HypothesisParams moved = planner;
    moved.extra_retreat_m = std::max(0.0, baseExtraRetreat(preshape) + standoff);
    if (verdict_only) moved.quality.compute_epsilon = moved.quality.compute_volume = false;
    grasping::HypothesisOutcome judged = grasping::judgeHypothesis(
        grasping::closeHypothesis(simulator, gcp, preshape, moved), simulator.object(), moved);
    if (!judged.grasp) return false;
    for (const Pose& pose : tried) {
      if (samePose(pose, judged.grasp->hand_pose)) return false;
    }
    tried.push_back(judged.grasp->hand_pose);
    // Only whether the pose beats the best matters: its samples stop once it cannot.
    const int needed = best_holds + params.min_gain_samples;
    const RobustnessResult r =
        evaluateRobustness(simulator, *judged.grasp, search, stream, params.samples - needed);
    if (r.gave_up || r.force_closure < needed) return false;
    best_holds = r.force_closure;
    best_held = r.held;
    out.search_r_after = r.score;
    grasping::Grasp& moved_grasp = *judged.grasp;
    moved_grasp.id = grasp.id;
    // The type follows the preshape only where the search switched it (a hand's own preshape
    // names need not say the type).
    moved_grasp.type =
        preshape.name == grasp.preshape || !preshape.grasp_type ? grasp.type : *preshape.grasp_type;
    moved_grasp.strategy = grasp.strategy;
    moved_grasp.segment = grasp.segment;
    moved_grasp.skeleton_vertex = grasp.skeleton_vertex;
    moved_grasp.refinement = grasp.refinement;
    out.grasp = std::move(moved_grasp);
    out.refined = true;
    return true;
  };

  const Moves lower = {-params.max_standoff_m, -params.max_shift_m, -params.max_shift_m,
                       -params.max_roll_rad};
  const Moves upper = {params.max_standoff_m, params.max_shift_m, params.max_shift_m,
                       params.max_roll_rad};
  CompassSearch compass(lower, upper);
  const grasping::Preshape* preshape = &hand.preshape(grasp.preshape);
  auto improves = [&](const Moves& moves) {
    Pose gcp = hypothesis;
    gcp.translation() += gcp.linear() * Eigen::Vector3d(moves[kShiftX], moves[kShiftY], 0);
    gcp.linear() = gcp.linear() * Eigen::AngleAxisd(moves[kRoll], Eigen::Vector3d::UnitZ());
    return judge(gcp, *preshape, moves[kStandoff]);
  };

  // The other preshape first: a fingertip pinch that a power grasp at the same place would beat
  // is the commonest fragile grasp, and the switch is one evaluation.
  if (params.switch_preshape) {
    for (const grasping::Preshape* switched : switchPreshapes(hand, grasp.preshape)) {
      // Each is judged against the best so far: the last accepted is the best.
      if (judge(hypothesis, *switched, 0.0)) {
        preshape = switched;
        log().debug("robust refinement: accepted preshape switch to {} r {:.2f}", switched->name,
                    out.search_r_after);
      }
    }
  }
  compass.run(
      {params.standoff_step_m, params.shift_step_m, params.shift_step_m, params.roll_step_rad},
      {true, true, true, true}, params.max_halvings,
      [&] { return out.evaluations < evaluation_limit; }, improves);
  // Then tilt and shift the best pose towards where its search samples held: all six degrees of
  // freedom, where the compass moves four. Each step is judged like a compass move (one more
  // pose, on the same samples), outside the compass's budget.
  const Pose compass_hand_pose = out.grasp.hand_pose;
  const Eigen::Vector3d compass_centre = perturbationCentre(out.grasp);
  for (int step = 0; step < params.mean_shift_steps && best_holds < params.samples; ++step) {
    const std::optional<PoseError> mean = meanHeldError(best_held, search, stream);
    if (!mean) break;
    const Pose gcp =
        perturbedPose(out.grasp.gcp_pose, *mean, perturbationCentre(out.grasp), search.variant);
    const grasping::Preshape& best_preshape = hand.preshape(out.grasp.preshape);
    // The grasp's own centre point, already backed off: no extra standoff on top of it.
    evaluation_limit = out.evaluations + 1;
    if (!judge(gcp, best_preshape, -baseExtraRetreat(best_preshape))) break;
    ++out.mean_shift_steps;
  }
  if (out.mean_shift_steps > 0) {
    // Both poses close the same hand: compare the hand roots'.
    const Pose shift = out.grasp.hand_pose * compass_hand_pose.inverse();
    out.mean_shift_m = (shift * compass_centre - compass_centre).norm();
    out.mean_shift_rad = Eigen::AngleAxisd(shift.linear()).angle();
  }
  const Moves& best_moves = compass.best();
  out.shift_x_m = best_moves[kShiftX];
  out.shift_y_m = best_moves[kShiftY];
  out.standoff_m = best_moves[kStandoff];
  out.roll_rad = best_moves[kRoll];
  if (out.refined && verdict_only) {
    const grasping::WrenchSpaceResult quality =
        grasping::evaluateGrasp(out.grasp.contacts, simulator.object(), planner.quality);
    out.grasp.epsilon = quality.epsilon;
    out.grasp.volume = quality.volume;
  }
  return out;
}

}  // namespace skelgrasp::ranking
