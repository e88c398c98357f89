#include "batch_records.h"

#include <limits>

#include "skelgrasp/common/json.h"

namespace skelgrasp::evaluation::internal {
namespace {

// A value as it appears in the file, cut short for error messages.
std::string shownValue(const nlohmann::json& value) {
  constexpr std::size_t kMaxShownChars = 40;
  std::string text = value.dump();
  if (text.size() > kMaxShownChars) text = text.substr(0, kMaxShownChars) + "...";
  return text;
}

// Typed access to the keys of one record; every failure names the key.
class Fields {
 public:
  explicit Fields(const nlohmann::json& j) : j_(j) {
    if (!j_.is_object()) throw RecordError("not a JSON object");
  }

  const nlohmann::json& at(const char* key) const {
    const auto it = j_.find(key);
    if (it == j_.end()) throw RecordError(std::string("key '") + key + "' is missing");
    return *it;
  }
  bool isNull(const char* key) const { return at(key).is_null(); }
  bool has(const char* key) const { return j_.contains(key); }

  std::string text(const char* key) const {
    const auto& v = at(key);
    if (!v.is_string()) wrongType(key, "a string", v);
    return v.get<std::string>();
  }
  bool flag(const char* key) const {
    const auto& v = at(key);
    if (!v.is_boolean()) wrongType(key, "true or false", v);
    return v.get<bool>();
  }
  double real(const char* key) const {
    const auto& v = at(key);
    if (!v.is_number()) wrongType(key, "a number", v);
    return v.get<double>();
  }
  std::optional<double> realOrNull(const char* key) const {
    return isNull(key) ? std::nullopt : std::optional<double>(real(key));
  }
  std::uint64_t count(const char* key) const { return count(key, at(key)); }
  int integer(const char* key) const {
    const auto& v = at(key);
    if (!v.is_number_integer() || v.get<std::int64_t>() < std::numeric_limits<int>::min() ||
        v.get<std::int64_t>() > std::numeric_limits<int>::max()) {
      wrongType(key, "a whole number", v);
    }
    return v.get<int>();
  }
  std::map<std::string, std::size_t> counts(const char* key) const {
    const auto& v = at(key);
    if (!v.is_object()) wrongType(key, "an object of counts", v);
    std::map<std::string, std::size_t> out;
    for (const auto& [name, value] : v.items()) {
      out[name] = count(std::string(key) + "." + name, value);
    }
    return out;
  }

 private:
  [[noreturn]] static void wrongType(const std::string& key, const char* expected,
                                     const nlohmann::json& v) {
    throw RecordError("key '" + key + "' must be " + expected + ", not " + shownValue(v));
  }
  static std::uint64_t count(const std::string& key, const nlohmann::json& v) {
    if (v.is_number_unsigned()) return v.get<std::uint64_t>();
    if (v.is_number_integer() && v.get<std::int64_t>() >= 0) return v.get<std::uint64_t>();
    wrongType(key, "a whole number >= 0", v);
  }

  const nlohmann::json& j_;
};

RunStatus parseRunStatus(const std::string& text) {
  for (const RunStatus s : {RunStatus::kOk, RunStatus::kNoGrasp, RunStatus::kError}) {
    if (text == toString(s)) return s;
  }
  throw RecordError("key 'status' must be ok, no_grasp or error, not '" + text + "'");
}

ranking::Planner plannerOf(const Fields& f) {
  const std::string name = f.text("planner");
  try {
    return ranking::parsePlanner(name);
  } catch (const std::exception& e) {
    throw RecordError(std::string("key 'planner': ") + e.what());
  }
}

nlohmann::json orNull(const std::optional<double>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

}  // namespace

const char* toString(RunStatus status) {
  switch (status) {
    case RunStatus::kOk:
      return "ok";
    case RunStatus::kNoGrasp:
      return "no_grasp";
    case RunStatus::kError:
      break;
  }
  return "error";
}

std::string runKey(const std::string& object, const std::string& hand, ranking::Planner planner) {
  return object + "|" + hand + "|" + toString(planner);
}
std::string runKey(const RunRecord& run) {
  return runKey(run.object, run.hand, run.planner);
}
std::string runKey(const GraspRecord& grasp) {
  return runKey(grasp.object, grasp.hand, grasp.planner);
}

void to_json(nlohmann::json& j, const RunRecord& run) {
  j = {{"object", run.object},
       {"hand", run.hand},
       {"planner", toString(run.planner)},
       {"status", toString(run.status)},
       {"error", run.error}};
  if (run.object_hash) j["object_hash"] = *run.object_hash;
  if (!run.measures) return;
  const RunMeasures& m = *run.measures;
  j["seed"] = m.seed;
  j["hypotheses"] = m.hypotheses;
  j["poses"] = m.poses;
  j["generated"] = m.generated;
  j["force_closure"] = m.force_closure;
  j["force_closure_rate"] = m.force_closure_rate;
  j["kept"] = m.kept;
  j["power"] = m.power;
  j["precision"] = m.precision;
  j["rejections"] = m.rejections;
  j["timed_out"] = m.timed_out;
  j["planning_s"] = m.planning_s;
  j["ms_per_valid_grasp"] = orNull(m.ms_per_valid_grasp);
  j["regularise_s"] = m.regularise_s;
  j["skeleton_s"] = m.skeleton_s;
  j["robustness_grasps"] = m.robustness_grasps;
  j["robustness_samples"] = m.robustness_samples;
  j["robustness_s"] = m.robustness_s;
  j["robustness_mean"] = orNull(m.robustness_mean);
  j["ranked"] = m.ranked;
  j["ranked_grasps"] = m.ranked_grasps;
  j["ranked_r_mean"] = orNull(m.ranked_r_mean);
  j["ranking_s"] = m.ranking_s;
  j["ranked_r_best"] = orNull(m.ranked_r_best);
  j["ranked_refined"] = m.ranked_refined;
  j["ranked_samples"] = m.ranked_samples;
  j["ranked_failures"] = {{"start_collision", m.ranked_start_collisions},
                          {"closing", m.ranked_closing_failures},
                          {"no_force_closure", m.ranked_no_force_closure},
                          {"too_weak", m.ranked_too_weak}};
  // A record read from a line without them (merged or rewritten) stays without them.
  if (m.physics) {
    const PhysicsMeasures& ph = *m.physics;
    j["physics"] = {{"judged", ph.judged},
                    {"holds", ph.holds},
                    {"failed",
                     {{"start", ph.start_failures},
                      {"closing", ph.closing_failures},
                      {"disturbance", ph.disturbance_failures}}},
                    {"cpu_s", ph.cpu_s}};
  }
  if (m.ranked_refinement_s) {
    j["ranked_r_mean_unrefined"] = orNull(m.ranked_r_mean_unrefined);
    j["ranked_refinement_s"] = *m.ranked_refinement_s;
  }
}

void from_json(const nlohmann::json& j, RunRecord& run) {
  const Fields f(j);
  run.object = f.text("object");
  run.hand = f.text("hand");
  run.planner = plannerOf(f);
  run.object_hash =
      f.has("object_hash") ? std::optional<std::string>(f.text("object_hash")) : std::nullopt;
  run.status = parseRunStatus(f.text("status"));
  run.error = f.text("error");
  run.measures.reset();
  if (run.status == RunStatus::kError) return;
  RunMeasures m;
  m.seed = f.count("seed");
  m.hypotheses = f.count("hypotheses");
  m.poses = f.count("poses");
  m.generated = f.count("generated");
  m.force_closure = f.count("force_closure");
  m.force_closure_rate = f.real("force_closure_rate");
  m.kept = f.count("kept");
  m.power = f.count("power");
  m.precision = f.count("precision");
  m.rejections = f.counts("rejections");
  m.timed_out = f.flag("timed_out");
  m.planning_s = f.real("planning_s");
  m.ms_per_valid_grasp = f.realOrNull("ms_per_valid_grasp");
  m.regularise_s = f.real("regularise_s");
  m.skeleton_s = f.real("skeleton_s");
  m.robustness_grasps = f.count("robustness_grasps");
  m.robustness_samples = f.integer("robustness_samples");
  m.robustness_s = f.real("robustness_s");
  m.robustness_mean = f.realOrNull("robustness_mean");
  if (f.has("ranked")) {
    m.ranked = f.flag("ranked");
    m.ranked_grasps = f.count("ranked_grasps");
    m.ranked_r_mean = f.realOrNull("ranked_r_mean");
    m.ranking_s = f.real("ranking_s");
  }
  if (f.has("ranked_refined")) {
    m.ranked_r_best = f.realOrNull("ranked_r_best");
    m.ranked_refined = f.count("ranked_refined");
  }
  if (f.has("ranked_samples")) {
    m.ranked_samples = f.count("ranked_samples");
    const std::map<std::string, std::size_t> failures = f.counts("ranked_failures");
    const auto cause = [&](const char* name) {
      const auto it = failures.find(name);
      if (it == failures.end())
        throw RecordError(std::string("key 'ranked_failures.") + name + "' is missing");
      return it->second;
    };
    m.ranked_start_collisions = cause("start_collision");
    m.ranked_closing_failures = cause("closing");
    m.ranked_no_force_closure = cause("no_force_closure");
    // Records written before the load check have no too_weak: none of their samples was checked.
    const auto weak = failures.find("too_weak");
    m.ranked_too_weak = weak == failures.end() ? 0 : weak->second;
  }
  if (f.has("ranked_refinement_s")) {
    m.ranked_r_mean_unrefined = f.realOrNull("ranked_r_mean_unrefined");
    m.ranked_refinement_s = f.real("ranked_refinement_s");
  }
  if (f.has("physics")) {
    const Fields ph(f.at("physics"));
    PhysicsMeasures& physics = m.physics.emplace();
    physics.judged = ph.count("judged");
    physics.holds = ph.count("holds");
    const std::map<std::string, std::size_t> failed = ph.counts("failed");
    const auto phase = [&](const char* name) {
      const auto it = failed.find(name);
      if (it == failed.end())
        throw RecordError(std::string("key 'physics.failed.") + name + "' is missing");
      return it->second;
    };
    physics.start_failures = phase("start");
    physics.closing_failures = phase("closing");
    physics.disturbance_failures = phase("disturbance");
    physics.cpu_s = ph.real("cpu_s");
    if (physics.holds + physics.start_failures + physics.closing_failures +
            physics.disturbance_failures !=
        physics.judged) {
      throw RecordError("key 'physics': holds and failures do not add up to judged");
    }
  }
  run.measures = std::move(m);
}

void to_json(nlohmann::json& j, const GraspRecord& g) {
  j = {{"object", g.object},
       {"hand", g.hand},
       {"planner", toString(g.planner)},
       {"grasp", g.grasp},
       {"type", g.type},
       {"strategy", g.strategy},
       {"epsilon", g.epsilon},
       {"volume", numberOrNull(g.volume)},
       {"time_ms", g.time_ms}};
  const auto& r = g.robustness;
  j["robustness"] = r ? nlohmann::json(r->score) : nlohmann::json(nullptr);
  j["robustness_low"] = r ? nlohmann::json(r->low) : nlohmann::json(nullptr);
  j["robustness_high"] = r ? nlohmann::json(r->high) : nlohmann::json(nullptr);
  j["robustness_collisions"] = r ? nlohmann::json(r->collisions) : nlohmann::json(nullptr);
  if (g.physics_holds) j["physics_holds"] = *g.physics_holds;
}

void from_json(const nlohmann::json& j, GraspRecord& g) {
  const Fields f(j);
  g.object = f.text("object");
  g.hand = f.text("hand");
  g.planner = plannerOf(f);
  g.grasp = f.integer("grasp");
  g.type = f.text("type");
  g.strategy = f.text("strategy");
  g.epsilon = f.real("epsilon");
  g.volume = f.realOrNull("volume");
  g.time_ms = f.real("time_ms");
  g.robustness.reset();
  g.physics_holds.reset();
  if (f.has("physics_holds")) g.physics_holds = f.flag("physics_holds");
  // The four robustness keys are null together (a grasp not scored) or numbers together.
  if (f.isNull("robustness")) {
    for (const char* key : {"robustness_low", "robustness_high", "robustness_collisions"}) {
      if (!f.isNull(key))
        throw RecordError(std::string("key '") + key + "' must be null, as 'robustness' is");
    }
    return;
  }
  g.robustness = GraspRobustness{f.real("robustness"), f.real("robustness_low"),
                                 f.real("robustness_high"), f.integer("robustness_collisions")};
}

}  // namespace skelgrasp::evaluation::internal
