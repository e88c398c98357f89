// Grasp description (JSON, schema "skelgrasp.grasp_description/1", docs/hands.md) applied to a
// URDF model.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <sstream>
#include <string>

#include "hand_loading.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/pose.h"

namespace skelgrasp::grasping::internal {
namespace {

using nlohmann::json;

// Most screening samples and candidates a description may ask for, the commands' own limits: a
// million perturbed executions per candidate would be hours, and no plan has a billion grasps.
constexpr std::uint64_t kMaxBudgetSamples = 1'000'000;
constexpr std::uint64_t kMaxBudgetCount = 1'000'000'000;
// Closing steps: below these a closing takes millions of steps, above them a finger jumps through
// a thin object in one step (defaults 0.02 rad and 0.5 mm).
constexpr double kMinClosingStepRad = 1e-4;
constexpr double kMaxClosingStepRad = 0.5;
constexpr double kMinClosingStepM = 1e-5;
constexpr double kMaxClosingStepM = 0.05;
// Torsional friction length, in metres: the range of --torsional-friction.
constexpr double kMaxTorsionalFrictionM = 1e3;

class DescriptionReader {
 public:
  DescriptionReader(const HandModel& hand, std::string origin)
      : hand_(hand), origin_(std::move(origin)) {}

  [[noreturn]] void fail(const std::string& problem) const { throw IoError(origin_, problem); }

  int link(const std::string& name, const std::string& where) const {
    const int i = hand_.linkIndex(name);
    if (i < 0) fail(where + ": unknown link '" + name + "'");
    return i;
  }
  int movableJoint(const std::string& name, const std::string& where) const {
    const int i = hand_.jointIndex(name);
    if (i < 0) fail(where + ": unknown joint '" + name + "'");
    if (!hand_.joints()[i].movable()) fail(where + ": joint '" + name + "' is fixed");
    return i;
  }
  // j[key] (fallback when absent): a number in [min, max].
  double numberIn(const json& j, const char* key, double fallback, double min, double max) const {
    if (!j.contains(key)) return fallback;
    if (!j.at(key).is_number()) fail(std::string("'") + key + "' must be a number");
    const double v = j.at(key).get<double>();
    if (!(v >= min && v <= max)) {
      fail(std::string("'") + key + "' is " + fmtNumber(v) + ", outside [" + fmtNumber(min) + ", " +
           fmtNumber(max) + "]");
    }
    return v;
  }
  static std::string fmtNumber(double v) {
    std::ostringstream text;
    text << v;
    return text.str();
  }
  double positive(const json& j, const char* key, double fallback) const {
    if (!j.contains(key)) return fallback;
    const double v = j.at(key).get<double>();
    if (!(v > 0)) fail(std::string("'") + key + "' must be positive");
    return v;
  }

  // The optional "ranking" section (absent or null: none): a misspelt key would silently leave the
  // ranking's default, so unknown keys are refused. Counts are compared as unsigned 64-bit numbers
  // before they are narrowed.
  RankingBudget rankingBudget(const json& j) const {
    RankingBudget budget;
    if (j.is_null()) return budget;
    if (!j.is_object()) fail("'ranking' must be an object");
    const auto count = [&](const json& value, std::uint64_t low, std::uint64_t high,
                           const char* key) {
      if (!value.is_number_unsigned() || value.get<std::uint64_t>() < low ||
          value.get<std::uint64_t>() > high)
        fail(std::string("ranking: '") + key + "' must be a whole number in [" +
             std::to_string(low) + ", " + std::to_string(high) + "]");
      return value.get<std::uint64_t>();
    };
    for (const auto& [key, value] : j.items()) {
      if (key == "screen_grasps") {
        budget.screen_grasps = count(value, 0, kMaxBudgetCount, "screen_grasps");
      } else if (key == "screen_samples") {
        budget.screen_samples =
            static_cast<int>(count(value, 1, kMaxBudgetSamples, "screen_samples"));
      } else if (key == "confirm_samples") {
        budget.confirm_samples =
            static_cast<int>(count(value, 0, kMaxBudgetSamples, "confirm_samples"));
      } else if (key == "refine_below_r") {
        // Its range is HandModel::setRankingBudget's to check.
        if (!value.is_number()) fail("ranking: 'refine_below_r' must be a number");
        budget.refine_below_r = value.get<double>() + 0.0;  // -0 read as 0
      } else if (key == "screen_by") {
        const std::string problem = "ranking: 'screen_by' must be " + screenCandidateChoices();
        if (!value.is_string()) fail(problem);
        try {
          budget.screen_candidates = parseScreenCandidates(value.get<std::string>());
        } catch (const InvalidArgument&) {
          fail(problem);
        }
      } else {
        fail("ranking: unknown key '" + key +
             "' (known: screen_grasps, screen_samples, confirm_samples, refine_below_r, "
             "screen_by)");
      }
    }
    return budget;
  }

  // The optional "strength" section (docs/hands.md): unknown keys are refused.
  HandStrength strength(const json& j) const {
    HandStrength strength;
    if (j.is_null()) return strength;
    if (!j.is_object()) fail("'strength' must be an object");
    for (const auto& [key, value] : j.items()) {
      if (key == "fingertip_force_n") {
        if (!value.is_number()) fail("strength: 'fingertip_force_n' must be a number");
        strength.fingertip_force_n = value.get<double>();
      } else if (key == "source") {
        if (!value.is_string()) fail("strength: 'source' must be a string");
        strength.source = value.get<std::string>();
      } else {
        fail("strength: unknown key '" + key + "' (known: fingertip_force_n, source)");
      }
    }
    return strength;
  }

  ShapeThresholds thresholds(const json& j, const std::string& where) const {
    ShapeThresholds t;
    t.lambda1_min_m = j.value("lambda1_min_m", 0.0);
    t.lambda1_max_m = j.value("lambda1_max_m", 1e9);
    t.lambda2_min_m = j.value("lambda2_min_m", 0.0);
    t.lambda2_max_m = j.value("lambda2_max_m", 1e9);
    if (t.lambda1_min_m > t.lambda1_max_m || t.lambda2_min_m > t.lambda2_max_m) {
      fail(where + ": a minimum exceeds its maximum");
    }
    return t;
  }

  // A grasp centre point's pose: within kMaxHandLengthM of its link, a rotation of unit length
  // within --pose's tolerance (a zero quaternion was normalised to NaN, [2, 0, 0, 0] silently).
  void checkGcp(const json& gcp, const std::string& where) const {
    const auto vector = [&](const char* key, std::size_t size) {
      const json& v = gcp.at(key);
      if (!v.is_array() || v.size() != size) fail(where + " gcp: '" + key + "' has a wrong size");
      Eigen::VectorXd out(static_cast<Eigen::Index>(size));
      for (std::size_t i = 0; i < size; ++i) {
        if (!v[i].is_number() || !std::isfinite(v[i].get<double>()))
          fail(where + " gcp: '" + key + "' is not finite");
        out[static_cast<Eigen::Index>(i)] = v[i].get<double>();
      }
      return out;
    };
    const double offset = vector("position", 3).stableNorm();
    if (!(offset <= kMaxHandLengthM)) {
      fail(where + " gcp: position is " + fmtNumber(offset) + " m from its link, more than " +
           fmtNumber(kMaxHandLengthM) + " m");
    }
    const double length = vector("quaternion_wxyz", 4).stableNorm();
    if (!(std::abs(length - 1) <= kPoseUnitTolerance)) {
      fail(where + " gcp: quaternion has length " + fmtNumber(length) + ", not 1 within " +
           fmtNumber(kPoseUnitTolerance));
    }
  }

  Preshape preshape(const std::string& name, const json& j) const {
    Preshape p;
    p.name = name;
    p.joints = hand_.zeroConfiguration();
    const std::string where = "preshape '" + name + "'";
    for (const auto& [joint, value] : j.at("joints").items()) {
      const int index = movableJoint(joint, where);
      if (hand_.joints()[index].mimic_of >= 0)
        fail(where + ": joint '" + joint + "' is a mimic joint");
      const double v = value.get<double>();
      const auto& limits = hand_.joints()[index];
      if (v < limits.lower - 1e-6 || v > limits.upper + 1e-6) {
        fail(where + ": joint '" + joint + "' value " + std::to_string(v) + " outside its limits");
      }
      p.joints[index] = v;
    }
    hand_.normalise(p.joints);
    const json& gcp = j.at("gcp");
    p.gcp_link = link(gcp.at("link").get<std::string>(), where + " gcp");
    checkGcp(gcp, where);
    p.gcp_in_link = poseFromJson(gcp);
    // "power" and "precision" are of their own type; another preshape is an alternative of the
    // type it names, or none.
    p.grasp_type = graspTypeNamed(name);
    if (j.contains("grasp_type")) {
      const std::optional<GraspType> named = graspTypeNamed(j.at("grasp_type").get<std::string>());
      if (!named) fail(where + ": grasp_type must be \"power\" or \"precision\"");
      if (p.grasp_type && *p.grasp_type != *named)
        fail(where + ": grasp_type must be its own name's type");
      p.grasp_type = named;
    }
    if (j.contains("max_object_length_m")) {
      // The main preshapes are closed where no size is asked: by the surface candidates and the
      // robust refinement's switch between the two types.
      if (graspTypeNamed(name))
        fail(where + ": only an alternative preshape can have a size limit");
      const json& length = j.at("max_object_length_m");
      if (!length.is_number() || !(std::isfinite(length.get<double>()) && length.get<double>() > 0))
        fail(where + ": max_object_length_m must be a positive number of metres");
      p.max_object_length_m = length.get<double>();
    }
    return p;
  }

 private:
  const HandModel& hand_;
  std::string origin_;
};

}  // namespace

void applyGraspDescription(HandModel& hand, const std::string& description_json,
                           const std::string& origin) {
  DescriptionReader reader(hand, origin);
  json d;
  try {
    d = json::parse(description_json);
  } catch (const json::exception& e) {
    reader.fail(describeJsonError(e, description_json));
  }
  try {
    const std::string schema = d.value("schema", "");
    if (schema != "skelgrasp.grasp_description/1") {
      reader.fail("schema must be \"skelgrasp.grasp_description/1\" (got \"" + schema + "\")");
    }
    std::vector<Finger> fingers;
    // Each joint is driven by one finger, as a drive or as a follower: two fingers driving one
    // joint fight over it, and a joint following its own follower is a coupling cycle.
    std::map<int, std::string> driven_by;
    const auto drive_once = [&](int joint, const std::string& where) {
      const auto [it, inserted] = driven_by.emplace(joint, where);
      if (!inserted) {
        reader.fail(where + ": joint '" + hand.joints()[joint].name + "' is already driven by " +
                    it->second);
      }
    };
    for (const auto& f : d.at("fingers")) {
      Finger finger;
      finger.name = f.at("name").get<std::string>();
      const std::string where = "finger '" + finger.name + "'";
      for (const auto& drive_json : f.at("joints")) {
        FingerDrive drive;
        drive.joint = reader.movableJoint(drive_json.at("joint").get<std::string>(), where);
        drive_once(drive.joint, where);
        drive.direction = drive_json.value("direction", 1.0);
        if (drive.direction != 1.0 && drive.direction != -1.0)
          reader.fail(where + ": direction must be 1 or -1");
        for (const auto& follower : drive_json.value("followers", json::array())) {
          const int joint = reader.movableJoint(follower.at("joint").get<std::string>(), where);
          drive_once(joint, where);
          const double ratio =
              reader.numberIn(follower, "ratio", 1.0, -kMaxJointLimit, kMaxJointLimit);
          drive.followers.emplace_back(joint, ratio);
        }
        finger.drives.push_back(std::move(drive));
      }
      for (const auto& [name, mode] : f.at("links").items()) {
        const std::string m = mode.get<std::string>();
        const CollisionMode cm =
            m == "all"      ? CollisionMode::kAll
            : m == "actors" ? CollisionMode::kActors
            : m == "none"   ? CollisionMode::kNone
                            : (reader.fail(where + ": collision mode must be all, actors or none"),
                             CollisionMode::kNone);
        finger.links.emplace_back(reader.link(name, where), cm);
      }
      if (finger.drives.empty()) reader.fail(where + " has no joints");
      fingers.push_back(std::move(finger));
    }
    if (fingers.empty()) reader.fail("no fingers");
    std::vector<int> palm;
    for (const auto& name : d.value("palm_links", json::array()))
      palm.push_back(reader.link(name, "palm_links"));

    std::map<std::string, Preshape> preshapes;
    for (const auto& [name, p] : d.at("preshapes").items())
      preshapes[name] = reader.preshape(name, p);
    for (const char* required : {"power", "precision"}) {
      if (!preshapes.count(required))
        reader.fail(std::string("missing preshape '") + required + "'");
    }

    PlannerThresholds thresholds;
    const json& t = d.at("thresholds");
    thresholds.round_ratio = reader.positive(t, "round_ratio", thresholds.round_ratio);
    if (!t.at("precision").is_null())
      thresholds.precision = reader.thresholds(t.at("precision"), "precision thresholds");
    if (!t.at("power").is_null())
      thresholds.power = reader.thresholds(t.at("power"), "power thresholds");
    thresholds.power_retreat_m = t.value("power_retreat_m", thresholds.power_retreat_m);

    const json& intervals = d.at("intervals");
    const double precision_m = reader.positive(intervals, "precision_m", 0.047);
    const double power_m = reader.positive(intervals, "power_m", 0.094);

    ClosingDefaults closing;
    const json c = d.value("closing", json::object());
    closing.step_rad =
        reader.numberIn(c, "step_rad", closing.step_rad, kMinClosingStepRad, kMaxClosingStepRad);
    closing.step_m =
        reader.numberIn(c, "step_m", closing.step_m, kMinClosingStepM, kMaxClosingStepM);
    closing.palm_contact_distance_m =
        reader.positive(c, "palm_contact_distance_m", closing.palm_contact_distance_m);
    closing.torsional_friction_m = reader.numberIn(
        c, "torsional_friction_m", closing.torsional_friction_m, 0, kMaxTorsionalFrictionM);

    hand.setDescription(std::move(fingers), std::move(palm), std::move(preshapes), thresholds,
                        precision_m, power_m, closing);
    hand.setRankingBudget(reader.rankingBudget(d.value("ranking", json::object())));
    hand.setStrength(reader.strength(d.value("strength", json::object())));
  } catch (const json::exception& e) {
    reader.fail(std::string("grasp description: ") + e.what());
  } catch (const InvalidArgument& e) {
    reader.fail(e.what());
  }
}

}  // namespace skelgrasp::grasping::internal
