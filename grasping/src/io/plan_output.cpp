#include "skelgrasp/grasping/io/plan_output.h"

#include <fmt/format.h>

#include "skelgrasp/common/json.h"
#include "skelgrasp/grasping/io/refinement_json.h"

namespace skelgrasp::grasping {

nlohmann::json graspToJson(const Grasp& g, const HandModel& hand) {
  nlohmann::json joints = nlohmann::json::object();
  for (std::size_t j = 0; j < hand.joints().size(); ++j) {
    if (hand.joints()[j].movable() && static_cast<Eigen::Index>(j) < g.joints.size()) {
      joints[hand.joints()[j].name] = g.joints[static_cast<Eigen::Index>(j)];
    }
  }
  nlohmann::json contacts = nlohmann::json::array();
  for (const auto& c : g.contacts) {
    contacts.push_back({{"point", toJson(c.point)},
                        {"normal", toJson(c.normal)},
                        {"link", c.link},
                        {"palm", c.palm}});
  }
  nlohmann::json out = {
      {"id", g.id},
      {"type", toString(g.type)},
      {"strategy", g.strategy},
      {"segment", g.segment >= 0 ? nlohmann::json(g.segment) : nlohmann::json(nullptr)},
      {"skeleton_vertex",
       g.skeleton_vertex >= 0 ? nlohmann::json(g.skeleton_vertex) : nlohmann::json(nullptr)},
      {"preshape", g.preshape},
      {"gcp_pose", poseToJson(g.gcp_pose)},
      {"hand_pose", poseToJson(g.hand_pose)},
      {"retreat_m", g.retreat_m},
      {"joints", joints},
      {"contacts", contacts},
      {"force_closure", g.force_closure},
      {"epsilon", g.epsilon},
      {"volume", numberOrNull(g.volume)}};
  if (g.robustness) {
    const GraspRobustness& r = *g.robustness;
    out["robustness"] = {
        {"r", r.r},
        {"ci95", {r.ci95_low, r.ci95_high}},
        {"samples", r.samples},
        {"mu", r.mu},
        {"torsional_friction_m", r.torsional_friction_m},
        {"contact_patch", r.contact_patch},
        {"sigma_m", r.sigma_m},
        {"sigma_rad", r.sigma_rad},
        {"variant", r.variant},
        {"failures",
         {{"start_collision", r.start_collisions},
          {"closing", r.closing_failures},
          {"no_force_closure", r.no_force_closure},
          {"too_weak", r.too_weak}}},
        {"settled_holds", r.settled_holds},
        {"load_check", r.load_mass_kg > 0 ? nlohmann::json{{"mass_kg", r.load_mass_kg},
                                                           {"torque_share", r.load_torque_share}}
                                          : nlohmann::json(nullptr)}};
    if (r.refinement) {
      const GraspRobustRefinement& f = *r.refinement;
      out["robustness"]["refinement"] = {{"refined", f.refined},
                                         {"evaluations", f.evaluations},
                                         {"search_samples", f.search_samples},
                                         {"r_before", f.r_before},
                                         {"preshape_before", f.preshape_before},
                                         {"moves",
                                          {{"shift_x_m", f.shift_x_m},
                                           {"shift_y_m", f.shift_y_m},
                                           {"standoff_m", f.standoff_m},
                                           {"roll_rad", f.roll_rad}}},
                                         {"mean_shift",
                                          {{"steps", f.mean_shift_steps},
                                           {"distance_m", f.mean_shift_m},
                                           {"angle_rad", f.mean_shift_rad}}}};
      if (f.check_samples > 0) {
        out["robustness"]["refinement"]["check"] = {
            {"samples", f.check_samples},
            {"holds_before", f.check_holds_before},
            {"holds_after",
             f.check_holds_after ? nlohmann::json(*f.check_holds_after) : nlohmann::json(nullptr)}};
      }
    }
  }
  return withRefinementJson(g, std::move(out));
}

nlohmann::json planSummaryJson(const PlanSummary& s) {
  nlohmann::json labels = nlohmann::json::object();  // JSON keys are strings
  for (const auto& [label, count] : s.scene_collision_labels) labels[std::to_string(label)] = count;
  return {{"hypotheses", s.hypotheses},
          {"poses", s.poses},
          {"generated", s.generated},
          {"force_closure", s.force_closure},
          {"force_closure_rate", s.forceClosureRate()},
          {"planning_s", s.planning_s},
          {"ms_per_valid_grasp",
           s.force_closure ? nlohmann::json(s.msPerValidGrasp()) : nlohmann::json(nullptr)},
          {"rejections", s.rejections},
          {"scene_collision_links", s.scene_collision_links},
          {"scene_collision_obstacles", s.scene_collision_obstacles},
          {"scene_collision_labels", labels},
          {"by_type", {{"power", s.power}, {"precision", s.precision}}},
          {"timed_out", s.timed_out},
          {"max_grasps_reached", s.max_grasps_reached}};
}

nlohmann::json planToJson(const PlanResult& r, const HandModel& hand, const std::string& object) {
  nlohmann::json grasps = nlohmann::json::array();
  for (const auto& g : r.grasps) grasps.push_back(graspToJson(g, hand));
  nlohmann::json summary = planSummaryJson(r.summary);
  summary["kept"] = r.grasps.size();
  return {{"schema", "skelgrasp.grasps/3"},
          {"object", object},
          {"hand", hand.name()},
          {"planner", r.planner},
          {"units", "m"},
          {"status", {{"code", toString(r.status.code)}, {"message", r.status.message}}},
          {"summary", std::move(summary)},
          {"grasps", grasps}};
}

std::string planSummaryLine(const PlanResult& r, const std::string& hand,
                            const std::string& object) {
  const auto& s = r.summary;
  std::string line = fmt::format(
      "{} {} {}: {} hypotheses, {} generated, {} force closure ({:.1f}%), {} kept ({} power, {} "
      "precision), {:.2f} s, {} ms per valid grasp",
      object, hand, r.planner, s.hypotheses, s.generated, s.force_closure,
      100 * s.forceClosureRate(), r.grasps.size(), s.power, s.precision, s.planning_s,
      s.force_closure ? fmt::format("{:.1f}", s.msPerValidGrasp()) : std::string("n/a"));
  if (r.grasps.empty()) {
    std::string reasons;
    for (const auto& [why, count] : s.rejections)
      reasons += fmt::format("{}{} {}", reasons.empty() ? "" : ", ", count, why);
    line += "; rejected: " + reasons;
  }
  return line;
}

}  // namespace skelgrasp::grasping
