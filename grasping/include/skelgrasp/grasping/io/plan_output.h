#pragma once
// grasps.json (schema skelgrasp.grasps/3, docs/planning.md) and pictures of planned grasps.
#include <nlohmann/json.hpp>

#include <string>

#include "skelgrasp/grasping/grasp.h"
#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/skeleton/skeleton.h"

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

// The object (grey), its skeleton if given, and one short line per grasp along its approach
// direction ending at the grasp centre point (like the paper's Fig. 9), from two sides; plus the
// best grasp with the closed hand.
void renderPlanPng(const std::string& path, const TriangleMesh& object,
                   const skeleton::Skeleton* skeleton, const PlanResult& result,
                   const HandModel& hand, int panel_size = 480);

}  // namespace skelgrasp::grasping
