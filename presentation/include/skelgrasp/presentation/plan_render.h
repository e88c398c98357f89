#pragma once
// A picture of a plan (`skelgrasp plan --render`, Python's render_plan).
#include <string>

#include "skelgrasp/common/mesh.h"
#include "skelgrasp/grasping/grasp.h"
#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/skeleton/skeleton.h"

namespace skelgrasp::presentation {

// The object (grey), its skeleton if given, and one short line per grasp along its approach
// direction ending at the grasp centre point (like the paper's Fig. 9), from two sides; plus the
// best grasp with the closed hand.
void renderPlanPng(const std::string& path, const TriangleMesh& object,
                   const skeleton::Skeleton* skeleton, const grasping::PlanResult& result,
                   const grasping::HandModel& hand, int panel_size = 480);

}  // namespace skelgrasp::presentation
