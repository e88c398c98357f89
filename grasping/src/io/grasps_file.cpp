#include "skelgrasp/grasping/io/grasps_file.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"

namespace skelgrasp::grasping {
namespace {

constexpr const char* kPlanSchemaPrefix = "skelgrasp.grasps/";
constexpr const char* kRunSchemaPrefix = "skelgrasp.run/";

bool startsWith(const std::string& text, const std::string& prefix) {
  return text.compare(0, prefix.size(), prefix) == 0;
}

std::string joinIds(const std::vector<long long>& ids) {
  std::string text;
  for (long long id : ids) text += (text.empty() ? "" : ", ") + std::to_string(id);
  return text;
}

// The ids of a run file's "objects" (empty when it has no such list).
std::vector<long long> runObjectIds(const nlohmann::json& file) {
  std::vector<long long> ids;
  if (!file.contains("objects")) return ids;
  const auto& objects = file["objects"];
  if (!objects.is_array()) throw InvalidArgument("grasps file: \"objects\" is not a list");
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const auto& id = requiredField(objects[i], "id", fmt::format("object {}", i));
    if (!id.is_number_integer())
      throw InvalidArgument(fmt::format("object {}: \"id\" is not a whole number", i));
    ids.push_back(id.get<long long>());
  }
  return ids;
}

}  // namespace

const nlohmann::json& requiredField(const nlohmann::json& j, const char* key,
                                    const std::string& where) {
  if (!j.is_object() || !j.contains(key)) {
    throw InvalidArgument(fmt::format("{} has no \"{}\"", where, key));
  }
  return j.at(key);
}

double finiteNumberField(const nlohmann::json& j, const char* key, const std::string& where) {
  const auto& v = requiredField(j, key, where);
  if (!v.is_number() || !std::isfinite(v.get<double>())) {
    throw InvalidArgument(fmt::format("{}: \"{}\" is not a finite number", where, key));
  }
  return v.get<double>();
}

Pose handPoseField(const nlohmann::json& grasp, const std::string& where) {
  const auto& pose = requiredField(grasp, "hand_pose", where);
  const auto bad = [&] {
    return InvalidArgument(where +
                           ": \"hand_pose\" is not a pose {\"position\": [x, y, z], "
                           "\"quaternion_wxyz\": [w, x, y, z]}");
  };
  if (!pose.is_object() || !pose.contains("position") || !pose.contains("quaternion_wxyz"))
    throw bad();
  const auto& p = pose["position"];
  const auto& q = pose["quaternion_wxyz"];
  if (!p.is_array() || p.size() != 3 || !q.is_array() || q.size() != 4) throw bad();
  for (const auto* array : {&p, &q}) {
    for (const auto& v : *array) {
      if (!v.is_number() || !std::isfinite(v.get<double>())) throw bad();
    }
  }
  const Eigen::Vector3d position(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
  if (!(position.stableNorm() <= kMaxGraspPositionM)) {
    throw InvalidArgument(
        fmt::format("{}: \"hand_pose\" position is {:.3g} m from the origin, "
                    "more than the limit of {:g} m",
                    where, position.stableNorm(), kMaxGraspPositionM));
  }
  const Eigen::Quaterniond rotation(q[0].get<double>(), q[1].get<double>(), q[2].get<double>(),
                                    q[3].get<double>());
  // stableNorm: [1e308, 1e308, 0, 0] must not overflow to a length that looks like anything.
  const double length = rotation.coeffs().stableNorm();
  if (!(std::abs(length - 1) <= kPoseUnitTolerance)) {
    throw InvalidArgument(
        fmt::format("{}: \"hand_pose\" quaternion has length {:.6g}, not 1 "
                    "within {:g}",
                    where, length, kPoseUnitTolerance));
  }
  return poseFromJson(pose);
}

double retreatField(const nlohmann::json& grasp, const std::string& where) {
  const double retreat = finiteNumberField(grasp, "retreat_m", where);
  if (!(retreat >= 0 && retreat <= kMaxRetreatM)) {
    throw InvalidArgument(fmt::format("{}: \"retreat_m\" is {:g}, outside [0, {:g}] m", where,
                                      retreat, kMaxRetreatM));
  }
  return retreat;
}

std::vector<double> closedJointsField(const nlohmann::json& grasp, const HandModel& hand,
                                      const std::string& where) {
  const auto& joints = requiredField(grasp, "joints", where);
  if (!joints.is_object()) throw InvalidArgument(where + ": \"joints\" is not an object");
  for (const auto& [name, value] : joints.items()) {
    const int j = hand.jointIndex(name);
    if (j < 0 || !hand.joints()[j].movable()) {
      throw InvalidArgument(fmt::format("{}: joint \"{}\" is not a movable joint of hand {}", where,
                                        name, hand.name()));
    }
  }
  std::vector<double> values(hand.joints().size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t j = 0; j < hand.joints().size(); ++j) {
    const Joint& joint = hand.joints()[j];
    if (!joint.movable()) continue;
    if (!joints.contains(joint.name)) {
      throw InvalidArgument(fmt::format("{}: \"joints\" lacks joint \"{}\" of hand {}", where,
                                        joint.name, hand.name()));
    }
    const auto& value = joints.at(joint.name);
    if (!value.is_number() || !std::isfinite(value.get<double>()))
      throw InvalidArgument(
          fmt::format("{}: joint \"{}\" is not a finite number", where, joint.name));
    const double q = value.get<double>();
    if (!(q >= joint.lower - kJointLimitTolerance && q <= joint.upper + kJointLimitTolerance)) {
      throw InvalidArgument(fmt::format("{}: joint \"{}\" is {:g}, outside its limits [{:g}, {:g}]",
                                        where, joint.name, q, joint.lower, joint.upper));
    }
    values[j] = q;
  }
  return values;
}

std::string defaultPreshapeName(const HandModel& hand) {
  const auto& preshapes = hand.preshapes();
  if (preshapes.count("power")) return "power";
  if (preshapes.size() == 1) return preshapes.begin()->first;
  throw InvalidArgument(
      fmt::format("hand {} has no \"power\" preshape and more than one other: "
                  "the grasp must name its \"preshape\"",
                  hand.name()));
}

std::string preshapeField(const nlohmann::json& grasp, const HandModel& hand,
                          const std::string& where, bool required) {
  if (!required && grasp.is_object() && !grasp.contains("preshape"))
    return defaultPreshapeName(hand);
  const auto& preshape = requiredField(grasp, "preshape", where);
  if (!preshape.is_string()) throw InvalidArgument(where + ": \"preshape\" is not a string");
  const std::string name = preshape.get<std::string>();
  try {
    hand.preshape(name);  // throws naming the hand's preshapes
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(where + ": " + e.what());
  }
  return name;
}

GraspsFileKind graspsFileKind(const nlohmann::json& file) {
  const auto& schema = requiredField(file, "schema", "grasps file");
  const std::string text = schema.is_string() ? schema.get<std::string>() : schema.dump();
  if (schema.is_string() && startsWith(text, kPlanSchemaPrefix)) return GraspsFileKind::kPlan;
  if (schema.is_string() && startsWith(text, kRunSchemaPrefix)) return GraspsFileKind::kRun;
  throw InvalidArgument(fmt::format(
      "grasps file has schema {}, expected skelgrasp.grasps/N (plan) or skelgrasp.run/N (run)",
      schema.dump()));
}

std::vector<GraspPlacement> readGraspPlacements(const nlohmann::json& file, const HandModel& hand,
                                                const std::optional<long long>& object) {
  const GraspsFileKind kind = graspsFileKind(file);
  if (file.contains("hand")) {
    const auto& file_hand = file["hand"];
    if (!file_hand.is_string() || file_hand.get<std::string>() != hand.name()) {
      throw InvalidArgument(fmt::format("grasps file was planned with hand {}, not {}",
                                        file_hand.dump(), hand.name()));
    }
  }
  const auto& list = requiredField(file, "grasps", "grasps file");
  if (!list.is_array()) throw InvalidArgument("grasps file: \"grasps\" is not a list");
  if (list.size() > kMaxGraspsPerFile) {
    throw InvalidArgument(fmt::format("grasps file holds {} grasps, more than the {} one file may",
                                      list.size(), kMaxGraspsPerFile));
  }
  if (kind == GraspsFileKind::kPlan && object) {
    throw InvalidArgument(
        "a plan's grasps file holds one object's grasps: an object id applies to run files only");
  }
  if (kind == GraspsFileKind::kRun) {
    const auto ids = runObjectIds(file);
    if (object && !ids.empty() && std::find(ids.begin(), ids.end(), *object) == ids.end()) {
      throw InvalidArgument(
          fmt::format("grasps file has no object {} (its objects: {})", *object, joinIds(ids)));
    }
    if (!object && ids.size() > 1) {
      throw InvalidArgument(
          fmt::format("grasps file holds the grasps of {} objects (ids {}): choose one by its id",
                      ids.size(), joinIds(ids)));
    }
  }
  std::vector<GraspPlacement> placements;
  placements.reserve(list.size());
  for (std::size_t i = 0; i < list.size(); ++i) {
    const auto& g = list[i];
    const std::string where = fmt::format("grasp {}", i);
    if (!g.is_object()) throw InvalidArgument(where + " is not an object");
    if (object) {
      const auto& owner = requiredField(g, "object", where);
      if (!owner.is_number_integer())
        throw InvalidArgument(where + ": \"object\" is not a whole number");
      if (owner.get<long long>() != *object) continue;
    }
    GraspPlacement p;
    p.id = g.contains("id") ? g["id"] : nlohmann::json(nullptr);
    p.hand_pose = handPoseField(g, where);
    p.preshape = preshapeField(g, hand, where, false);
    placements.push_back(std::move(p));
  }
  return placements;
}

}  // namespace skelgrasp::grasping
