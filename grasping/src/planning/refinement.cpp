#include "skelgrasp/grasping/planning/refinement.h"

#include "skelgrasp/grasping/planning/compass_search.h"

#include <Eigen/SVD>

#include <array>
#include <cmath>

namespace skelgrasp::grasping {
namespace {

// A candidate must beat the best so far by more than this margin (n l*, dimensionless) to
// replace it: ties and LP rounding never move the pose.
constexpr double kMarginImprovement = 1e-9;
// Singular values below this fraction of the largest do not count towards the wrench rank (as
// the quality module's rank test).
constexpr double kRelativeRankTolerance = 1e-9;
// The tangent move is used only when the approach is at least this far (sine of the angle) from
// the skeleton tangent; at endpoints the hand comes in along the tangent, where a shift along it
// is undone by the retreat.
constexpr double kMinTangentSine = 0.5;
// The smallest wrench set that can enclose the origin of 6D wrench space.
constexpr std::size_t kMinWrenches = 7;

enum Move { kTangent, kLateral, kRoll, kStandoff, kMoveCount };
using Moves = CompassSearch<kMoveCount>::Moves;

struct Score {
  bool closed = false;  // closed with enough contacts
  bool force_closure = false;
  double margin = kNoClosureMargin;
};

// Closed beats not closed, force closure beats none, then the larger margin.
bool better(const Score& a, const Score& b) {
  if (!a.closed) return false;
  if (!b.closed) return true;
  if (a.force_closure != b.force_closure) return a.force_closure;
  return a.margin > b.margin + kMarginImprovement;
}

Score scoreClosed(const HypothesisOutcome& closed, const GraspObject& object,
                  const QualityParams& quality) {
  Score score;
  if (!closed.generated || !closed.grasp) return score;
  score.closed = true;
  QualityParams verdict_params = quality;
  verdict_params.compute_epsilon = false;
  verdict_params.compute_volume = false;
  score.force_closure = evaluateGrasp(closed.grasp->contacts, object, verdict_params).force_closure;
  score.margin = signedClosureMargin(closed.grasp->contacts, object, quality);
  if (!score.force_closure) score.margin = std::min(score.margin, 0.0);
  return score;
}

}  // namespace

double signedClosureMargin(const std::vector<Contact>& contacts, const GraspObject& object,
                           const QualityParams& params) {
  const bool compat = params.reference_compat;
  const Eigen::Vector3d centre = compat ? object.vertexMean() : object.centerOfMass();
  const double torque_scale =
      compat ? torqueScaleLongestSide(object.bounds()) : torqueScaleMaxRadius(object);
  const std::vector<Wrench> wrenches = contactWrenches(contacts, centre, torque_scale, params);
  if (wrenches.size() < kMinWrenches) return kNoClosureMargin;
  const ClosureLpResult lp = solveClosureLp(wrenches);
  if (!lp.error.empty() || !lp.feasible) return kNoClosureMargin;
  const double margin = lp.margin * static_cast<double>(wrenches.size());
  Eigen::MatrixXd matrix(6, wrenches.size());
  for (std::size_t i = 0; i < wrenches.size(); ++i)
    matrix.col(static_cast<Eigen::Index>(i)) = wrenches[i];
  const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(matrix).singularValues();
  const long rank = (sv.array() > kRelativeRankTolerance * std::max(1.0, sv[0])).count();
  return rank < 6 ? std::min(margin, 0.0) : margin;
}

HypothesisOutcome evaluateRefinedHypothesis(GraspSimulator& simulator, const Pose& gcp,
                                            const Preshape& preshape,
                                            const HypothesisParams& params,
                                            const RefinementFrame& frame,
                                            const RefinementParams& refinement) {
  if (!refinement.enabled) return evaluateHypothesis(simulator, gcp, preshape, params);
  if (!(refinement.max_evaluations >= 0 && refinement.tangent_step_m > 0 &&
        refinement.lateral_step_m > 0 && refinement.roll_step_rad > 0 &&
        refinement.standoff_step_m > 0 && refinement.max_tangent_m >= 0 &&
        refinement.max_lateral_m >= 0 && refinement.max_roll_rad >= 0 &&
        refinement.max_standoff_m >= 0 && refinement.max_halvings >= 0)) {
    throw InvalidArgument("refinement: steps must be > 0, evaluations, bounds and halvings >= 0");
  }
  const GraspObject& object = simulator.object();
  HypothesisOutcome seed = closeHypothesis(simulator, gcp, preshape, params);
  // Only hypotheses that closed with enough contacts are refined (kept ones and near-misses).
  if (!seed.generated) return seed;
  const Score seed_score = scoreClosed(seed, object, params.quality);

  // Move directions, fixed by the seed pose.
  const Eigen::Vector3d approach = gcp.rotation().col(2);
  Eigen::Vector3d tangent = frame.tangent - frame.tangent.dot(approach) * approach;
  const bool use_tangent = tangent.norm() > kMinTangentSine * frame.tangent.norm();
  if (use_tangent) tangent.normalize();
  Eigen::Vector3d to_centroid = frame.local_centroid - gcp.translation();
  to_centroid -= to_centroid.dot(approach) * approach;
  if (use_tangent) to_centroid -= to_centroid.dot(tangent) * tangent;
  const double centroid_distance = to_centroid.norm();
  Eigen::Vector3d lateral;
  if (centroid_distance > refinement.min_centroid_jump_m) {
    lateral = to_centroid / centroid_distance;
  } else {
    lateral = use_tangent ? Eigen::Vector3d(approach.cross(tangent).normalized())
                          : anyPerpendicular(approach);
  }
  const double base_extra = params.extra_retreat_m;
  const Moves lower = {-refinement.max_tangent_m, -refinement.max_lateral_m,
                       -refinement.max_roll_rad, -base_extra};
  const Moves upper = {refinement.max_tangent_m, refinement.max_lateral_m, refinement.max_roll_rad,
                       refinement.max_standoff_m};

  Score best_score = seed_score;
  HypothesisOutcome best = std::move(seed);
  // The seed is kept apart so that it can be returned if the best pose fails min_epsilon.
  HypothesisOutcome seed_copy = best;
  int evaluations = 0;
  HypothesisParams moved_params = params;
  CompassSearch<kMoveCount> search(lower, upper);
  auto improves = [&](const Moves& moves) {
    ++evaluations;
    Pose pose = gcp;
    pose.translation() += moves[kTangent] * (use_tangent ? tangent : Eigen::Vector3d::Zero()) +
                          moves[kLateral] * lateral;
    pose.linear() = gcp.linear() * Eigen::AngleAxisd(moves[kRoll], Eigen::Vector3d::UnitZ());
    moved_params.extra_retreat_m = base_extra + moves[kStandoff];
    HypothesisOutcome closed = closeHypothesis(simulator, pose, preshape, moved_params);
    const Score score = scoreClosed(closed, object, params.quality);
    if (!better(score, best_score)) return false;
    best_score = score;
    best = std::move(closed);
    return true;
  };
  const auto has_budget = [&] { return evaluations < refinement.max_evaluations; };

  // Straight to the local centroid first: a hypothesis off the middle of the section is centred
  // in one evaluation instead of a ladder of steps.
  if (centroid_distance > refinement.min_centroid_jump_m && has_budget()) {
    Moves jump{};
    jump[kLateral] = std::min(centroid_distance, refinement.max_lateral_m);
    search.attempt(jump, improves);
  }
  search.run({refinement.tangent_step_m, refinement.lateral_step_m, refinement.roll_step_rad,
              refinement.standoff_step_m},
             {use_tangent, true, true, true}, refinement.max_halvings, has_budget, improves);
  const Moves& best_moves = search.best();

  const bool moved = best_moves != Moves{};
  HypothesisOutcome judged = judgeHypothesis(std::move(best), object, params);
  if (moved && !judged.grasp) {
    // The best pose failed min_epsilon: the seed, if it is kept, is never worse.
    HypothesisOutcome seed_judged = judgeHypothesis(std::move(seed_copy), object, params);
    if (seed_judged.grasp) {
      seed_judged.grasp->refinement =
          GraspRefinement{false, evaluations, seed_score.margin, seed_score.margin, 0, 0, 0, 0};
      return seed_judged;
    }
  }
  if (judged.grasp) {
    judged.grasp->refinement = GraspRefinement{moved,
                                               evaluations,
                                               seed_score.margin,
                                               best_score.margin,
                                               best_moves[kTangent],
                                               best_moves[kLateral],
                                               best_moves[kRoll],
                                               best_moves[kStandoff]};
  }
  return judged;
}

}  // namespace skelgrasp::grasping
