#pragma once
// Local refinement of a grasp hypothesis: before it is kept or dropped, a small neighbourhood of
// its pose is searched for the pose with the largest closure margin (docs/planning.md, "Local
// refinement"). The moves: shift along the skeleton tangent, shift across the approach towards the
// local surface centroid, roll about the approach, standoff along the approach. The search is a
// deterministic compass (pattern) search: try +-step on each move, take the first improvement,
// halve the steps when none improves, stop at the evaluation budget or the smallest steps.
// Margin maximisation follows the min-weight force-closure metric (quality.h); the code is ours.
#include <optional>
#include <vector>

#include "skelgrasp/grasping/planning/hypothesis.h"

namespace skelgrasp::grasping {

struct RefinementParams {
  // Off by default: refining every closed hypothesis made planning 8-12x slower (4 of 12 YCB
  // object/hand runs hit the 30 s limit; docs/planning.md, "Local refinement"). `--refine` on the
  // planning commands switches it on.
  bool enabled = false;
  // Poses closed and judged per hypothesis besides the seed (each costs one retreat search and one
  // closing); 0: no search, but kept grasps still record their margin (refined = false).
  int max_evaluations = 12;
  // First step of each move; every step is halved together when no move improves.
  double tangent_step_m = 0.004;
  double lateral_step_m = 0.004;
  double roll_step_rad = 0.17453292519943295;  // 10 degrees
  double standoff_step_m = 0.004;
  // The search ends when the steps have been halved this many times without an improvement.
  int max_halvings = 2;
  // Bounds of the moves (absolute, from the seed pose).
  double max_tangent_m = 0.02;
  double max_lateral_m = 0.03;
  double max_roll_rad = 0.5235987755982988;  // 30 degrees
  double max_standoff_m = 0.02;
  // A local centroid farther than this from the approach line (across it) is jumped to first.
  double min_centroid_jump_m = 0.001;
};

// Where the hypothesis came from, in the object frame.
struct RefinementFrame {
  Eigen::Vector3d tangent = Eigen::Vector3d::UnitZ();  // skeleton tangent at the vertex
  // Centroid of the surface points of the local interval; the lateral move points at it.
  Eigen::Vector3d local_centroid = Eigen::Vector3d::Zero();
};

// Signed normalised closure margin n l* of the min-weight LP (quality.h) for contacts on the
// object, with evaluateGrasp's centre and torque scale and `params`' friction and contact model:
// in (0, 1] with force closure by the LP rule, <= 0 without (how far the origin is outside the
// wrench hull); kNoClosureMargin with fewer than 7 wrenches or no LP solution. Wrenches spanning
// less than 6D give at most 0.
constexpr double kNoClosureMargin = -1e3;
double signedClosureMargin(const std::vector<Contact>& contacts, const GraspObject& object,
                           const QualityParams& params);

// evaluateHypothesis with local refinement: the seed `gcp` is closed; when it closes with enough
// contacts (kept or a near-miss) its neighbourhood is searched and the best pose judged. The kept
// grasp's `refinement` records the moves. Never worse than the seed: a pose replaces the seed only
// when it is force closure where the seed was not, or has a larger margin with the same verdict,
// and still passes min_epsilon. With refinement disabled: exactly evaluateHypothesis. Throws
// InvalidArgument for a negative budget, bound or halving count or a step <= 0.
HypothesisOutcome evaluateRefinedHypothesis(GraspSimulator& simulator, const Pose& gcp,
                                            const Preshape& preshape,
                                            const HypothesisParams& params,
                                            const RefinementFrame& frame,
                                            const RefinementParams& refinement);

}  // namespace skelgrasp::grasping
