#pragma once
// The options of Python's plan(): one object holding the library's Params structs
// (ranking::PlanOptions' groups), with the settings both planners share held once (planner, seed,
// time and grasp limits, minimum epsilon, quality, closing). bind_options.cpp binds it;
// docs/python.md.
#include <cstdint>
#include <string>

#include "skelgrasp/grasping/planning/planners.h"
#include "skelgrasp/ranking/plan_grasps.h"
#include "skelgrasp/ranking/robust_ranking.h"
#include "skelgrasp/skeleton/extraction.h"

namespace skelgrasp::python {

// Every default is the library's, as `skelgrasp plan` has them but for the time limit (the
// library's 0, no limit; the command line sets 30 s).
struct PlanOptions {
  ranking::Planner planner = ranking::Planner::kSkeleton;
  // Seeds the planner (vertex order, surface samples) and the robustness samples, as --seed does.
  std::uint64_t seed = grasping::SkeletonPlannerParams{}.seed;
  double timeout_s = grasping::SkeletonPlannerParams{}.timeout_s;         // 0: no limit
  std::size_t max_grasps = grasping::SkeletonPlannerParams{}.max_grasps;  // 0: no limit
  // The hypothesis parameters of whichever planner runs (each Params' own `hypothesis`, its
  // `timeout_s`, `max_grasps` and `seed` are set from the ones here).
  double min_epsilon = grasping::HypothesisParams{}.min_epsilon;
  grasping::QualityParams quality;
  grasping::ClosingParams closing;
  skeleton::SkeletonParams skeleton;
  grasping::SkeletonPlannerParams skeleton_planner;
  grasping::SurfacePlannerParams surface_planner;
  // Its robustness.seed is `seed`; robustness.load set means the load check is wanted (applied
  // where the variant has one: ranking::setLoadCheck).
  ranking::RobustRankingParams ranking;

  // The library's options these stand for (planGrasps' argument). reference_compat implies the
  // reference's contact patch (centre), as --reference-compat does.
  ranking::PlanOptions library() const;
  // Throws InvalidArgument "<field>: <problem>" (the field's path below PlanOptions, e.g.
  // "ranking.robustness.samples") for a value the command line's option checks or the library
  // would refuse, then runs the library's own ranking::PlanOptions::validate().
  void validate() const;
};

// The checks PlanOptions::validate runs on each group, the fields named after `prefix` (""
// for a group validated on its own, "ranking." within PlanOptions).
void validateQuality(const grasping::QualityParams& quality, const std::string& prefix);
void validateSkeleton(const skeleton::SkeletonParams& skeleton, const std::string& prefix);
void validateSkeletonPlanner(const grasping::SkeletonPlannerParams& planner,
                             const std::string& prefix);
void validateRobustness(const ranking::RobustnessParams& robustness, const std::string& prefix);
void validateRobustRefinement(const ranking::RobustRefinementParams& refinement,
                              const std::string& prefix);
void validateRobustRanking(const ranking::RobustRankingParams& ranking, const std::string& prefix);

}  // namespace skelgrasp::python
