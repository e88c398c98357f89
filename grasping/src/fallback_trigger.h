#pragma once
// The skeleton planner's hook into the fallback strategies (fallback_planner.cpp).
#include "skelgrasp/grasping/planners.h"

namespace skelgrasp::grasping::internal {

// After the skeleton strategies: when `params.fallback` is set, nothing stopped the plan (time,
// grasp count) and the skeleton gave no hand pose at all (reason fallback_no_segment) or fewer
// than params.fallback_min_grasps grasps (fallback_few_grasps), records that reason as one rejected
// hypothesis and appends the fallback strategies' grasps and counts to `result`, within the time
// and grasp count left. `elapsed_s`: planning time used so far.
void addFallbackGrasps(const HandModel& hand, const GraspObject& object,
                       const SkeletonPlannerParams& params, double elapsed_s, PlanResult& result);

}  // namespace skelgrasp::grasping::internal
