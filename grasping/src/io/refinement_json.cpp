#include "skelgrasp/grasping/io/refinement_json.h"

namespace skelgrasp::grasping {

nlohmann::json withRefinementJson(const Grasp& grasp, nlohmann::json grasp_json) {
  if (!grasp.refinement) return grasp_json;
  const GraspRefinement& r = *grasp.refinement;
  grasp_json["refinement"] = {{"refined", r.refined},
                              {"evaluations", r.evaluations},
                              {"margin_before", r.margin_before},
                              {"margin_after", r.margin_after},
                              {"moves",
                               {{"tangent_m", r.tangent_m},
                                {"lateral_m", r.lateral_m},
                                {"roll_rad", r.roll_rad},
                                {"standoff_m", r.standoff_m}}}};
  return grasp_json;
}

}  // namespace skelgrasp::grasping
