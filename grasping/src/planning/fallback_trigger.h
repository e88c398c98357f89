#pragma once
// The skeleton planner's hook into the fallback strategies (fallback_planner.cpp).
#include "skelgrasp/grasping/planning/planners.h"

namespace skelgrasp::grasping::internal {

// The grasp limit of the skeleton strategies: params.max_grasps, or its larger half when the
// centre candidates will run after them (they get the rest), so a limit does not shut them out.
std::size_t skeletonGraspLimit(const SkeletonPlannerParams& params);

// After the skeleton strategies, when `params.fallback` is set and the time limit has not stopped
// the plan:
//  * the skeleton gave no hand pose at all (reason fallback_no_segment) or fewer than
//    params.fallback_min_grasps grasps (fallback_few_grasps), and its grasp limit was not reached:
//    records that reason as one rejected hypothesis and appends the fallback strategies' grasps
//    and counts to `result`;
//  * otherwise, with params.centre_candidates: appends the centre candidates (sphere and axis
//    poses with every preshape the hand plans with).
// Both within the time left and up to params.max_grasps grasps in all. `elapsed_s`: planning time
// used so far.
void addFallbackGrasps(const HandModel& hand, const GraspObject& object,
                       const SkeletonPlannerParams& params, double elapsed_s, PlanResult& result);

// Then params.surface_candidates surface-normal hypotheses (planSurfaceGrasps, seeded by
// params.seed), within the time and grasp count left; their grasps and counts are appended.
void addSurfaceCandidates(const HandModel& hand, const GraspObject& object,
                          const SkeletonPlannerParams& params, double elapsed_s,
                          PlanResult& result);

}  // namespace skelgrasp::grasping::internal
