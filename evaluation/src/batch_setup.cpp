#include "batch_setup.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/logging.h"

namespace skelgrasp::evaluation::internal {
namespace fs = std::filesystem;
namespace {

const char* const kBatchFile = "/batch.json";

const char* unitName(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::kMeters:
      return "m";
    case LengthUnit::kMillimeters:
      return "mm";
    case LengthUnit::kAuto:
      break;
  }
  return "auto";
}

nlohmann::json skeletonOptions(const skeleton::SkeletonParams& s) {
  const auto& r = s.regularisation;
  const auto& c = s.contraction;
  return {{"regularisation",
           {{"method", geometry::toString(r.method)},
            {"alpha_divisor", r.alpha_divisor},
            {"offset_divisor", r.offset_divisor},
            {"remesh_target_edge_m", r.remesh_target_edge_m},
            {"remesh_iterations", r.remesh_iterations},
            {"join_area_fraction", r.join_area_fraction},
            {"join_attempts", r.join_attempts},
            {"keep_largest_component", r.keep_largest_component},
            {"auto_max_hole_edges", r.auto_max_hole_edges},
            {"auto_min_vertices",
             r.auto_min_vertices ? nlohmann::json(*r.auto_min_vertices) : nlohmann::json()},
            {"max_vertices", r.max_vertices ? nlohmann::json(*r.max_vertices) : nlohmann::json()}}},
          {"contraction",
           {{"max_triangle_angle_rad", c.max_triangle_angle_rad},
            {"quality_speed_tradeoff", c.quality_speed_tradeoff},
            {"medially_centered_speed_tradeoff", c.medially_centered_speed_tradeoff},
            {"area_variation_factor", c.area_variation_factor},
            {"max_iterations", c.max_iterations},
            {"is_medially_centered", c.is_medially_centered},
            {"min_edge_length_fraction", c.min_edge_length_fraction}}},
          {"spur_radius_factor", s.spur_radius_factor},
          {"curvature_stencil_m", s.graph.curvature_stencil_m}};
}

// Flattens nested objects to "a.b" keys, so a difference names the exact option.
void flatten(const nlohmann::json& j, const std::string& prefix,
             std::map<std::string, nlohmann::json>& out) {
  if (!j.is_object()) {
    out[prefix] = j;
    return;
  }
  for (const auto& [key, value] : j.items()) {
    flatten(value, prefix.empty() ? key : prefix + "." + key, out);
  }
}

std::string shown(const nlohmann::json& value) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_array()) {
    std::string text;
    for (const auto& v : value) text += (text.empty() ? "" : ",") + shown(v);
    return text;
  }
  return value.dump();
}

}  // namespace

// Robust ranking as recorded in batch.json (only when on, so batches from before the option
// resume). Budgets left to the hands are recorded as the defaults, as before they became optional,
// and each hand whose own budget differs from that gets its budget in "hand_budgets": a batch
// from before the hands had budgets resumes only where nothing changed.
nlohmann::json rankingOptions(const ranking::RobustRankingParams& r,
                              const std::vector<grasping::HandModel>& hands) {
  const ranking::RankingBudgetUsed recorded =
      ranking::rankingBudgetFor(r);  // as for a hand without a budget
  nlohmann::json options = {
      {"top_k", r.top_k},
      {"screen_k", recorded.screen_k},
      {"screen_samples", recorded.screen_samples},
      {"samples", r.robustness.samples},
      {"variant", toString(r.robustness.variant)},
      {"load_check", r.robustness.load
                         ? nlohmann::json{{"mass_kg", r.robustness.load->mass_kg},
                                          {"torque_share", r.robustness.load->torque_share}}
                         : nlohmann::json(nullptr)},
      // The search moves the returned grasps, so a batch resumed with another
      // search would mix two kinds of grasps.
      {"refinement",
       {{"enabled", r.refinement.enabled},
        {"max_grasps", r.refinement.max_grasps},
        {"search_below_r", recorded.search_below_r},
        {"max_evaluations", r.refinement.max_evaluations},
        {"samples", r.refinement.samples},
        {"max_standoff_m", r.refinement.max_standoff_m},
        {"mean_shift_steps", r.refinement.mean_shift_steps}}}};
  // A found pose is checked on samples of its own, not on r's; a batch from a skelgrasp that did
  // not reported the moved grasps' r from the samples that chose them, so it does not resume
  // into this one.
  if (r.refinement.enabled) options["refinement"]["check"] = "own_samples";
  // Screening may take every preshape's best grasps in turn; a batch from a skelgrasp that did
  // not screened the best by epsilon, so it resumes only into that.
  if (recorded.screen_candidates != grasping::ScreenCandidates::kByPreScore)
    options["screen_by"] = toString(recorded.screen_candidates);
  // The screening's contenders may run more samples before the choice; a batch from a skelgrasp
  // without the confirmation ran none, so it resumes only into that.
  if (recorded.confirm_samples != 0) options["confirm_samples"] = recorded.confirm_samples;
  for (const auto& hand : hands) {
    const ranking::RankingBudgetUsed own = ranking::rankingBudgetFor(r, hand.rankingBudget());
    if (own.screen_k != recorded.screen_k || own.screen_samples != recorded.screen_samples ||
        own.search_below_r != recorded.search_below_r ||
        own.screen_candidates != recorded.screen_candidates ||
        own.confirm_samples != recorded.confirm_samples) {
      options["hand_budgets"][hand.name()] = {{"screen_k", own.screen_k},
                                              {"screen_samples", own.screen_samples},
                                              {"search_below_r", own.search_below_r}};
      // Only where it differs, so the record of a hand whose screening is the options' own
      // stays as it was.
      if (own.screen_candidates != recorded.screen_candidates)
        options["hand_budgets"][hand.name()]["screen_by"] = toString(own.screen_candidates);
      if (own.confirm_samples != recorded.confirm_samples)
        options["hand_budgets"][hand.name()]["confirm_samples"] = own.confirm_samples;
    }
  }
  return options;
}

nlohmann::json resultOptions(const BatchParams& p, const std::vector<grasping::HandModel>& hands) {
  std::vector<std::string> planners;
  for (const ranking::Planner planner : p.planners) planners.push_back(toString(planner));
  const auto& q = p.quality;
  const auto& r = p.robustness;
  const auto& c = r.closing;
  nlohmann::json options = {
      {"hands", p.hands},
      {"planners", planners},
      {"seed", p.seed},
      {"timeout_s", p.timeout_s},
      {"vertex_distance_m", p.vertex_distance_m},
      {"centre_candidates", p.centre_candidates},
      {"surface_hypotheses", p.surface_hypotheses},
      {"mu", q.friction},
      {"reference_compat", q.reference_compat},
      {"quality",
       {{"cone_edges", q.cone_edges},
        // The hand's model (nullopt) is recorded as 0, as before the option became optional.
        {"torsional_friction_m", q.torsional_friction_m.value_or(0.0)},
        {"compute_volume", q.compute_volume}}},
      {"robustness_grasps", p.robustness_grasps},
      {"robustness",
       {{"samples", r.samples},
        {"variant", toString(r.variant)},
        // Unset sigmas and closing steps are recorded as before they became optional (-1, 0).
        {"position_sigma_m", r.position_sigma_m.value_or(-1.0)},
        {"orientation_sigma_rad", r.orientation_sigma_rad.value_or(-1.0)},
        {"closing",
         {{"step_rad", c.step_rad.value_or(0.0)},
          {"step_m", c.step_m.value_or(0.0)},
          {"palm_contact_distance_m", c.palm_contact_distance_m.value_or(-1.0)},
          {"palm_contacts", c.palm_contacts},
          {"contact_distance_m", c.contact_distance_m},
          {"min_contacts", c.min_contacts},
          {"max_passes", c.max_passes},
          {"max_iterations_per_pass", c.max_iterations_per_pass}}}}},
      {"skeleton", skeletonOptions(p.skeleton)},
      {"load",
       {{"units", unitName(p.load.units)},
        {"auto_millimetre_diagonal", p.load.auto_millimetre_diagonal}}},
  };
  // The centre candidates close the precision preshapes too (and the SDH has a fingertip
  // tripod); a batch from a skelgrasp that did not planned power ones only, so it does not resume
  // into this one.
  if (p.centre_candidates) options["centre_candidate_types"] = "power_and_precision";
  if (p.ranking.enabled) options["ranking"] = rankingOptions(p.ranking, hands);
  // Only when on, so batches without the physics judge resume as they were.
  if (p.physics)
    options["physics"] = {{"grasps", p.physics->grasps}, {"mass_kg", p.physics->mass_kg}};
  // Batches from before the option judged by patch centres and recorded nothing: only corners are
  // recorded, so those resume with --contact-patch centre and not with the default.
  if (c.contact_patch != grasping::ContactPatch::kCentre)
    options["contact_patch"] = grasping::toString(c.contact_patch);
  // Only when on, so batches from before the option resume.
  if (p.surface_candidates > 0) options["surface_candidates"] = p.surface_candidates;
  // The hands whose planners close alternative preshapes, with their names (the SDH's tripods, claw
  // and narrow tripod were added one by one): only those, so batches of the other hands resume,
  // and older ones with --no-alternative-preshapes.
  nlohmann::json with_alternatives = nlohmann::json::object();
  const bool skeleton_planner = std::find(p.planners.begin(), p.planners.end(),
                                          ranking::Planner::kSkeleton) != p.planners.end();
  if (p.alternative_preshapes && !q.reference_compat && skeleton_planner) {
    for (const auto& hand : hands) {
      // A preshape with a grasp type that is not named after it is an alternative; one for small
      // objects names its limit, so a batch planned with another limit is not resumed.
      std::vector<std::string> names;
      for (const auto& [name, preshape] : hand.preshapes()) {
        if (!preshape.grasp_type || name == grasping::toString(*preshape.grasp_type)) continue;
        names.push_back(name);
        if (preshape.max_object_length_m)
          names.back() += fmt::format(" (objects up to {} m)", *preshape.max_object_length_m);
      }
      if (!names.empty()) with_alternatives[hand.name()] = names;
    }
  }
  if (!with_alternatives.empty()) options["alternative_preshapes"] = with_alternatives;
  return options;
}

std::string describeDifferences(const nlohmann::json& recorded, const nlohmann::json& current) {
  std::map<std::string, nlohmann::json> was, now;
  flatten(recorded, "", was);
  flatten(current, "", now);
  std::set<std::string> keys;
  for (const auto& [key, value] : was) keys.insert(key);
  for (const auto& [key, value] : now) keys.insert(key);
  std::string text;
  for (const auto& key : keys) {
    const auto a = was.find(key), b = now.find(key);
    if (a != was.end() && b != now.end() && a->second == b->second) continue;
    text += fmt::format("{}{} {} -> {}", text.empty() ? "" : ", ", key,
                        a == was.end() ? "(none)" : shown(a->second),
                        b == now.end() ? "(none)" : shown(b->second));
  }
  return text;
}

std::optional<nlohmann::json> readBatchOptions(const std::string& dir) {
  const std::string path = dir + kBatchFile;
  if (!fs::exists(path)) return std::nullopt;
  const auto batch = readJsonFile(path);
  if (!batch.is_object() || !batch.contains("schema_version") || !batch.contains("options") ||
      !batch.at("schema_version").is_number_integer()) {
    throw IoError(path, "not a batch description (schema_version and options expected)");
  }
  if (batch.at("schema_version").get<int>() > kBatchSchemaVersion) {
    throw IoError(path, fmt::format("schema version {} is newer than this skelgrasp's ({})",
                                    batch.at("schema_version").get<int>(), kBatchSchemaVersion));
  }
  return batch.at("options");
}

void writeBatchOptions(const std::string& dir, const nlohmann::json& options) {
  writeJsonFile(dir + kBatchFile, {{"schema_version", kBatchSchemaVersion}, {"options", options}},
                2);
}

std::uint64_t fnv1a(const std::string& bytes, std::uint64_t seed) {
  std::uint64_t h = 1469598103934665603ULL ^ seed;
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ULL;
  return h;
}

std::string contentHash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  std::uint64_t h = fnv1a("");
  std::vector<char> buffer(1 << 16);
  while (in.read(buffer.data(), static_cast<std::streamsize>(buffer.size())) || in.gcount() > 0) {
    for (std::streamsize i = 0; i < in.gcount(); ++i) {
      h = (h ^ static_cast<unsigned char>(buffer[i])) * 1099511628211ULL;
    }
  }
  if (in.bad()) return {};
  return fmt::format("{:016x}", h);
}

std::vector<ObjectIdentity> identifyObjects(const std::vector<std::string>& paths) {
  std::vector<ObjectIdentity> objects;
  std::vector<fs::path> normal;
  std::set<std::string> seen;
  for (const auto& path : paths) {
    fs::path p = fs::absolute(path).lexically_normal();
    if (!seen.insert(p.string()).second) {
      log().warn("evaluate: {} is listed more than once; evaluated once", path);
      continue;
    }
    objects.push_back({path, {}, {}});
    normal.push_back(std::move(p));
  }
  if (normal.empty()) return objects;
  // The deepest directory holding every object: the common prefix of their parent directories.
  const fs::path first_parent = normal[0].parent_path();
  std::vector<fs::path> root(first_parent.begin(), first_parent.end());
  for (const auto& p : normal) {
    const fs::path parent = p.parent_path();
    std::size_t common = 0;
    for (auto it = parent.begin();
         it != parent.end() && common < root.size() && *it == root[common]; ++it) {
      ++common;
    }
    root.resize(common);
  }
  fs::path root_dir;
  for (const auto& part : root) root_dir /= part;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    objects[i].id = normal[i].lexically_relative(root_dir).generic_string();
  }
  return objects;
}

}  // namespace skelgrasp::evaluation::internal
