#pragma once
// planGrasps: the whole job of `skelgrasp plan` in one call. Skeleton (skeleton planner only) ->
// planner -> robust ranking, so that a C++ user gets the grasps the command line and Python return:
// ranked by their robustness r, the best scored ones carrying it (Grasp::robustness).
// docs/planning.md.
//
//   const auto hand = skelgrasp::grasping::loadBuiltinHand("sdh");
//   const auto plan = skelgrasp::ranking::planGrasps(mesh, hand, {});
//   if (plan.status.ok()) use(plan.grasps.front());  // the best grasp, with its r
#include <functional>
#include <optional>
#include <string>

#include "skelgrasp/common/error.h"
#include "skelgrasp/grasping/grasp.h"
#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/grasping/planning/planners.h"
#include "skelgrasp/grasping/simulation/grasp_object.h"
#include "skelgrasp/ranking/robust_ranking.h"
#include "skelgrasp/skeleton/extraction.h"

namespace skelgrasp::ranking {

// The planners. Declared in the order of their names: summaries sort by it.
enum class Planner {
  kSkeleton,  // "skeleton": the paper's skeleton-based planner (Alg. 1); needs the skeleton
  kSurface,   // "surface": the baseline sampling the object's surface
};
// Throws InvalidArgument "unknown planner 'NAME' (use skeleton, surface)".
Planner parsePlanner(const std::string& name);
const char* toString(Planner planner);

// The options of planGrasps in three groups: the skeleton stage, the planner, the robust ranking.
// Every default is the stage's own Params default (no time limit: the command line sets 30 s).
// Units: metres, seconds, radians.
struct PlanOptions {
  Planner planner = Planner::kSkeleton;
  // The skeleton stage (skeleton planner only): regularisation to a closed manifold, contraction
  // (simplified to skeleton::kDefaultContractionVertices vertices), cleanup.
  skeleton::SkeletonParams skeleton;
  // The skeleton planner (planner == kSkeleton): time and grasp limits (0: none), seed, vertex
  // distance, fallback strategies, centre and surface candidates; its `hypothesis` holds the
  // closing, the quality (friction 0.35, force-closure test, contact model), the minimum epsilon
  // and the scene check.
  grasping::SkeletonPlannerParams skeleton_planner;
  // The surface planner (planner == kSurface): 500 hypotheses without a time limit.
  grasping::SurfacePlannerParams surface_planner;
  // Robust ranking (robust_ranking.h): the best 10 of up to 60 screened grasps scored with 50
  // perturbed executions each and ranked first by r; `enabled = false` keeps the planner's epsilon
  // order. r is judged as the chosen planner judged its grasps (its `hypothesis`), with the
  // friction replaced by ranking.friction when that is set; the samples are seeded by
  // ranking.robustness.seed.
  RobustRankingParams ranking;

  // The chosen planner's hypothesis parameters: those the ranking judges r with.
  const grasping::HypothesisParams& hypothesis() const;
  // Throws InvalidArgument for a caller's mistake found before any work: a planner that is not
  // one of Planner's, or ranking parameters checkRobustRankingParams refuses. The stages check
  // their own parameters as they run (and throw InvalidArgument too).
  void validate() const;
};

// Seconds of the stages of planning one object with one hand. The skeleton's parts are unset for
// the surface planner, which needs no skeleton. Loading the mesh and writing outputs are not
// counted: they depend on the disk, not on the method.
struct PlanTiming {
  std::optional<double> regularise_s;  // the closed manifold the contraction needs
  std::optional<double> skeleton_s;    // contraction, mapping and analysis
  double planning_s = 0;               // hypotheses generated, closed and judged
  double ranking_s = 0;                // robust ranking, refinement for robustness included
  double total_s() const;
};

// The timing of a plan from the skeleton stage's times (null: the surface planner, no skeleton),
// the planner's and the ranking's. The skeleton's time is its total less the regularisation.
PlanTiming planTimingOf(const skeleton::SkeletonTimings* skeleton, double planning_s,
                        double ranking_s);

// What planGrasps returns. The PlanResult part (status, planner, grasps, summary) is what
// grasping's planToJson, planSummaryLine and renderPlanPng read.
//  * status: kOk with grasps; kNoResult when the planner kept none (summary.rejections say why);
//    the skeleton stage's own status when it could not process the mesh, or kInvalidInput for a
//    mesh without a face of positive area with either planner (skeleton_failed: then no planner
//    ran and there are no grasps; callers report the mesh as bad input).
//  * grasps: ranked, best first, ids 0..n-1 (id = rank); the scored ones carry their robustness.
struct GraspPlan : grasping::PlanResult {
  bool skeleton_failed = false;
  // The skeleton planGrasps extracted (skeleton planner, none given in PlanInputs), else unset.
  std::optional<skeleton::SkeletonResult> skeleton;
  // What the ranking did (screened, scored, refined, budget, times). Its grasps are `grasps`
  // (moved out: ranking.grasps is empty); ranking.scores and ranking.order match `grasps`.
  RobustRankingResult ranking;
  PlanTiming timing;
};

// What a caller may hand planGrasps beside the object.
struct PlanInputs {
  // The object's skeleton, already extracted (several hands or planners on one object, or a
  // skeleton stage of the caller's own): planned on instead of extracting one with
  // PlanOptions::skeleton. Must be of the object's mesh, and outlive the call.
  const skeleton::SkeletonResult* skeleton = nullptr;
  // How far each grasp is trusted (robust_ranking.h: pre-score epsilon x trust, rank score r x
  // trust), e.g. the share of its contacts on surface a sensor saw; unset: 1. Called on each
  // planned grasp, and again on each grasp refinement for robustness moved (it touches elsewhere
  // now): its rank score becomes r x its own trust and the scored grasps are re-sorted by it.
  // Must return a finite number >= 0.
  std::function<double(const grasping::Grasp&)> trust;
};

// Plans grasps on `mesh` with `hand` and ranks them by robustness: skeleton (skeleton planner),
// planner, robust ranking. Deterministic for the options' seeds unless a time limit cuts the
// planner short. Throws InvalidArgument for a caller's mistake (PlanOptions::validate, a stage's
// parameters, an empty mesh); data failures are in the status.
GraspPlan planGrasps(const TriangleMesh& mesh, const grasping::HandModel& hand,
                     const PlanOptions& options);

// The same on an object the caller holds (its collision geometry and distance field are built
// once for every hand and planner run on it), with the inputs above.
GraspPlan planGrasps(const grasping::GraspObject& object, const grasping::HandModel& hand,
                     const PlanOptions& options, const PlanInputs& inputs = {});

}  // namespace skelgrasp::ranking
