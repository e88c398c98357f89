#pragma once
// Refinement for robustness: the second half of issue 16's local refinement. Where the planner's
// refinement (grasping/planning/refinement.h) searches a hypothesis' neighbourhood for the largest
// closure margin, this searches a scored grasp's neighbourhood for the largest robustness r: the
// share of perturbed executions that still close to force closure (robustness.h). It runs in the
// robust ranking on the grasps it scores (robust_ranking.h), so it costs closings only where they
// pay: docs/ranking.md, "Refinement for robustness".
#include <cstddef>
#include <cstdint>
#include <optional>

#include "skelgrasp/grasping/planning/hypothesis.h"
#include "skelgrasp/ranking/robustness.h"

namespace skelgrasp::ranking {

// Scored grasps whose r is below this are searched, unless the parameters or the hand say
// otherwise (RobustRefinementParams::search_below_r).
inline constexpr double kDefaultSearchBelowR = 0.7;

struct RobustRefinementParams {
  // Off: the ranking returns the planner's poses.
  bool enabled = true;
  // The ranking searches near its most robust scored grasps, this many of them (0: all scored).
  // 10, all the grasps the ranking scores by default: over the 58 YCB meshes, searching 10 rather
  // than 5 lifted the median top-10 r by 0.5-3.5 points for 0.2-0.35 s more ranking per object.
  std::size_t max_grasps = 10;
  // Only grasps whose scored r is below this are searched (1: all but those that held in every
  // scoring sample; 0: none). A time-for-r trade: over the 58 YCB meshes at mu = 0.35, 0.7 rather
  // than 0.9 cut the median plan time by 15-18 % for 0.2-0.3 points of mean top-10 r. The SDH's
  // grasps below 0.7 gain 4 times as much r per perturbed execution as those at 0.7-0.9,
  // ARMAR-III's about as much; at r >= 0.9 (at most one failure expected in the search's 12
  // samples) a win is mostly luck (CHANGELOG.md has the measurement).
  // Unset: the hand's ranking budget (grasping::RankingBudget::refine_below_r), else
  // kDefaultSearchBelowR.
  std::optional<double> search_below_r;
  // Poses closed and judged per grasp besides its own (each costs one retreat search, one closing
  // and `samples` perturbed executions).
  int max_evaluations = 4;
  // Perturbed executions per pose in the search. Every pose of a grasp faces the same
  // perturbations (common random numbers), so a difference of a few samples is a difference of
  // the poses, not of their luck.
  int samples = 12;
  // A pose must hold in at least this many more of the search's samples than the best so far.
  int min_gain_samples = 1;
  // First steps of the moves, in the grasp centre point's frame (z = approach): standoff (backing
  // off along the approach; negative: closer, down to the first free pose), shift across the
  // approach (x and y), roll about the approach. The compass tries them in that order: most
  // failed samples of a good grasp start with the open hand in the object, which only standoff
  // cures. Its step is 10 mm because a 5 mm gain is about one sample in 12 and mostly went
  // unseen, so the budget went to shifts (docs/ranking.md, "Refinement for robustness").
  double standoff_step_m = 0.010;
  double shift_step_m = 0.005;
  double roll_step_rad = 0.2617993877991494;  // 15 degrees
  // Bounds of the moves from the planner's pose.
  double max_shift_m = 0.015;
  double max_standoff_m = 0.02;
  double max_roll_rad = 0.5235987755982988;  // 30 degrees
  // The steps are halved when no move improves, at most this many times.
  int max_halvings = 1;
  // Also try the hand's other preshape (precision <-> power) at the same grasp centre point.
  bool switch_preshape = true;
  // After the compass, at most this many mean-shift steps (0: none): the best pose is moved by the
  // mean pose error of its search samples that held (about the contacts' centre; all six degrees
  // of freedom, so it also tilts the approach, which the compass does not), and the moved pose is
  // judged like a compass move, one pose per step besides max_evaluations. The step costs no
  // samples of its own: it reads the best pose's search samples. Over the 58 YCB meshes (μ = 0.35)
  // one step lifted the median top-10 r by 0.4-2.2 points for 0.04-0.10 s of ranking per
  // object; a second step changed nothing, and a probe of 24 fresh samples per step gained more
  // only for the Shadow hand, for 0.15-0.36 s (docs/results.md).
  int mean_shift_steps = 1;
};

struct RobustRefinementOutcome {
  grasping::Grasp grasp;  // the best pose's grasp (the input grasp when nothing was better)
  bool refined = false;   // grasp differs from the input
  int evaluations = 0;    // poses closed besides the input's (mean-shift steps included)
  // Search-stream r (params.samples samples) of the input and of the returned pose.
  double search_r_before = 0, search_r_after = 0;
  // The returned pose's moves from the input's hypothesis (GraspRobustRefinement's frame and
  // signs); all 0 when not refined.
  double shift_x_m = 0, shift_y_m = 0, standoff_m = 0, roll_rad = 0;
  // Mean-shift steps taken after those moves, and how far they moved the grasp: the distance the
  // contacts' centre was carried (m) and the angle the hand turned (rad). 0 when none was taken.
  int mean_shift_steps = 0;
  double mean_shift_m = 0, mean_shift_rad = 0;
};

// Searches `grasp`'s neighbourhood for the pose with the largest r under `robustness` (samples
// replaced by params.samples, perturbations drawn from `stream`). Poses are closed as the planner
// closes them (`planner`: retreat, scene check, closing, quality, min_epsilon); a pose is a
// candidate only when its grasp is kept by those rules. The returned grasp keeps the input's
// type, strategy, segment, vertex and planner refinement record, with the new pose, preshape,
// joints, contacts and quality. Throws InvalidArgument for a negative budget, bound, halving or
// mean-shift step count, a step <= 0 or samples < 1. (search_below_r is the ranking's choice of
// grasps; this searches whatever grasp it is given.)
RobustRefinementOutcome refineForRobustness(grasping::GraspSimulator& simulator,
                                            const grasping::Grasp& grasp,
                                            const grasping::HypothesisParams& planner,
                                            const RobustnessParams& robustness,
                                            const RobustRefinementParams& params,
                                            std::uint64_t stream);

}  // namespace skelgrasp::ranking
