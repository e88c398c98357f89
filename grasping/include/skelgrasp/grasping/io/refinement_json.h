#pragma once
// The "refinement" member of a grasp in grasps.json (docs/planning.md, "Local refinement").
#include <nlohmann/json.hpp>

#include "skelgrasp/grasping/grasp.h"

namespace skelgrasp::grasping {

// `grasp_json` with "refinement": {"refined", "evaluations", "margin_before", "margin_after",
// "moves": {"tangent_m", "lateral_m", "roll_rad", "standoff_m"}} added when the grasp was refined;
// unchanged otherwise (grasps planned without refinement are written as before).
nlohmann::json withRefinementJson(const Grasp& grasp, nlohmann::json grasp_json);

}  // namespace skelgrasp::grasping
