#pragma once
// grasps.json (schema skelgrasp.grasps/3, docs/planning.md) and the one-line summary of a plan
// (its picture: presentation/plan_render.h).
#include <nlohmann/json.hpp>

#include <string>

#include "skelgrasp/grasping/grasp.h"
#include "skelgrasp/grasping/hand/hand_model.h"

namespace skelgrasp::grasping {

// One grasp; "robustness" only when the grasp has one.
nlohmann::json graspToJson(const Grasp& grasp, const HandModel& hand);
// The "summary" of a plan without "kept" (which counts the plan's grasps, not the summary's).
nlohmann::json planSummaryJson(const PlanSummary& summary);
nlohmann::json planToJson(const PlanResult& result, const HandModel& hand,
                          const std::string& object);

// One-line summary: "<object> <hand> <planner>: N hypotheses, G generated, F force closure ...".
std::string planSummaryLine(const PlanResult& result, const std::string& hand,
                            const std::string& object);

}  // namespace skelgrasp::grasping
