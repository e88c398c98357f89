#include "skelgrasp/grasping/io/grasp_export.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cmath>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/grasping/io/grasps_file.h"

namespace skelgrasp::grasping {
namespace {

constexpr double kNanosecondsPerSecond = 1e9;

void emitVector(YAML::Emitter& out, const char* key, const Eigen::Vector3d& v) {
  // + 0.0 turns a negated zero into 0, which YAML would otherwise print as "-0".
  out << YAML::Key << key << YAML::Value << YAML::BeginMap << YAML::Key << "x" << YAML::Value
      << v.x() + 0.0 << YAML::Key << "y" << YAML::Value << v.y() + 0.0 << YAML::Key << "z"
      << YAML::Value << v.z() + 0.0 << YAML::EndMap;
}

void emitHeader(YAML::Emitter& out, const std::string& frame_id) {
  out << YAML::Key << "header" << YAML::Value << YAML::BeginMap << YAML::Key << "frame_id"
      << YAML::Value << frame_id << YAML::EndMap;
}

// trajectory_msgs/JointTrajectory with one point (ROS 2 time fields sec/nanosec).
void emitPosture(YAML::Emitter& out, const char* key, const std::vector<std::string>& names,
                 const std::vector<double>& positions, double time_s, const std::string& frame) {
  const double whole_s = std::floor(time_s);
  out << YAML::Key << key << YAML::Value << YAML::BeginMap;
  emitHeader(out, frame);
  out << YAML::Key << "joint_names" << YAML::Value << YAML::Flow << names;
  out << YAML::Key << "points" << YAML::Value << YAML::BeginSeq << YAML::BeginMap;
  out << YAML::Key << "positions" << YAML::Value << YAML::Flow << positions;
  out << YAML::Key << "time_from_start" << YAML::Value << YAML::BeginMap << YAML::Key << "sec"
      << YAML::Value << static_cast<long>(whole_s) << YAML::Key << "nanosec" << YAML::Value
      << static_cast<long>(std::lround((time_s - whole_s) * kNanosecondsPerSecond)) << YAML::EndMap;
  out << YAML::EndMap << YAML::EndSeq << YAML::EndMap;
}

// moveit_msgs/GripperTranslation: a direction in the hand's root frame and distances (m).
void emitTranslation(YAML::Emitter& out, const char* key, const std::string& hand_frame,
                     const Eigen::Vector3d& direction, double desired_m, double min_m) {
  out << YAML::Key << key << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "direction" << YAML::Value << YAML::BeginMap;
  emitHeader(out, hand_frame);
  emitVector(out, "vector", direction);
  out << YAML::EndMap;
  out << YAML::Key << "desired_distance" << YAML::Value << desired_m;
  out << YAML::Key << "min_distance" << YAML::Value << min_m;
  out << YAML::EndMap;
}

struct GraspFields {
  std::string where;
  int id = 0;
  Pose hand_pose;
  std::string preshape;
  double retreat_m = 0;
  double quality = 0;
  std::vector<int> joints;
  std::vector<double> closed;
};

GraspFields readGrasp(const nlohmann::json& g, std::size_t index, const HandModel& hand) {
  GraspFields f;
  f.where = fmt::format("grasp {}", index);
  f.id = static_cast<int>(finiteNumberField(g, "id", f.where));
  f.hand_pose = handPoseField(g, f.where);
  f.preshape = preshapeField(g, hand, f.where, true);
  f.retreat_m = retreatField(g, f.where);
  // The ranking score where the run wrote one, else the grasp quality ε.
  f.quality = g.contains("rank_score") ? finiteNumberField(g, "rank_score", f.where)
                                       : finiteNumberField(g, "epsilon", f.where);
  // Every movable joint, in the hand's joint order (the order a URDF lists them, which is also
  // what MoveIt's JointTrajectory expects to be stable across grasps).
  const std::vector<double> closed = closedJointsField(g, hand, f.where);
  for (std::size_t j = 0; j < closed.size(); ++j) {
    if (!hand.joints()[j].movable()) continue;
    f.joints.push_back(static_cast<int>(j));
    f.closed.push_back(closed[j]);
  }
  return f;
}

// Longest object or frame name an export copies into every grasp: a path, never megabytes (a
// 60 MB "object" was written 15 times per grasp).
constexpr std::size_t kMaxNameBytes = 4096;

// The name `j[key]` when present (a string of at most kMaxNameBytes), else `fallback`.
std::string nameField(const nlohmann::json& j, const char* key, const std::string& fallback,
                      const std::string& where) {
  if (!j.is_object() || !j.contains(key)) return fallback;
  const auto& value = j.at(key);
  if (!value.is_string())
    throw InvalidArgument(fmt::format("{}: \"{}\" is not a string", where, key));
  if (value.get_ref<const std::string&>().size() > kMaxNameBytes) {
    throw InvalidArgument(
        fmt::format("{}: \"{}\" is longer than {} bytes", where, key, kMaxNameBytes));
  }
  return value.get<std::string>();
}

std::string objectOf(const nlohmann::json& file) {
  return nameField(file, "object", "object", "grasps file");
}

std::string frameOf(const nlohmann::json& file, const ExportParams& params) {
  if (params.frame_id) return *params.frame_id;
  if (file.contains("scene") && file["scene"].is_object() && file["scene"].contains("frame")) {
    return nameField(file["scene"], "frame", "", "grasps file: \"scene\"");
  }
  return objectOf(file);
}

std::vector<std::string> jointNames(const HandModel& hand, const std::vector<int>& joints) {
  std::vector<std::string> names;
  for (int j : joints) names.push_back(hand.joints()[j].name);
  return names;
}

std::string moveItYaml(const nlohmann::json& file, const std::vector<GraspFields>& grasps,
                       const HandModel& hand, const ExportParams& params) {
  const std::string frame = frameOf(file, params);
  const std::string hand_frame = hand.links()[hand.rootLink()].name;
  const std::string object = objectOf(file);
  YAML::Emitter out;
  out << YAML::BeginSeq;
  for (const auto& g : grasps) {
    const Preshape& preshape = hand.preshape(g.preshape);
    // The approach direction is the grasp centre point's z axis, in the hand's root frame.
    const Eigen::Vector3d approach = hand.gcpInRoot(preshape).rotation().col(2).normalized();
    const Eigen::Quaterniond q(g.hand_pose.rotation());
    // Mimic joints follow their leader in the hand's controller; MoveIt trajectories list only
    // the actuated ones.
    std::vector<int> actuated;
    std::vector<double> open, closed;
    for (std::size_t k = 0; k < g.joints.size(); ++k) {
      const int j = g.joints[k];
      if (hand.joints()[j].mimic_of >= 0) continue;
      actuated.push_back(j);
      open.push_back(preshape.joints[j]);
      closed.push_back(g.closed[k]);
    }
    const auto names = jointNames(hand, actuated);
    out << YAML::BeginMap;
    out << YAML::Key << "id" << YAML::Value << fmt::format("{}_{}_{}", object, hand.name(), g.id);
    emitPosture(out, "pre_grasp_posture", names, open, params.posture_time_s, hand_frame);
    emitPosture(out, "grasp_posture", names, closed, params.posture_time_s, hand_frame);
    out << YAML::Key << "grasp_pose" << YAML::Value << YAML::BeginMap;
    emitHeader(out, frame);
    out << YAML::Key << "pose" << YAML::Value << YAML::BeginMap;
    emitVector(out, "position", g.hand_pose.translation());
    out << YAML::Key << "orientation" << YAML::Value << YAML::BeginMap << YAML::Key << "x"
        << YAML::Value << q.x() << YAML::Key << "y" << YAML::Value << q.y() << YAML::Key << "z"
        << YAML::Value << q.z() << YAML::Key << "w" << YAML::Value << q.w() << YAML::EndMap;
    out << YAML::EndMap << YAML::EndMap;
    out << YAML::Key << "grasp_quality" << YAML::Value << g.quality;
    emitTranslation(out, "pre_grasp_approach", hand_frame, approach,
                    g.retreat_m + params.approach_clearance_m, g.retreat_m);
    emitTranslation(out, "post_grasp_retreat", hand_frame, -approach, params.retreat_distance_m,
                    params.min_retreat_distance_m);
    emitTranslation(out, "post_place_retreat", hand_frame, -approach, params.retreat_distance_m,
                    params.min_retreat_distance_m);
    out << YAML::Key << "max_contact_force" << YAML::Value << params.max_contact_force_n;
    out << YAML::Key << "allowed_touch_objects" << YAML::Value << YAML::Flow
        << std::vector<std::string>{object};
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  return std::string(out.c_str()) + "\n";
}

std::string jointStatesJson(const nlohmann::json& file, const std::vector<GraspFields>& grasps,
                            const HandModel& hand) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& g : grasps) {
    list.push_back({{"id", g.id},
                    {"preshape", g.preshape},
                    {"name", jointNames(hand, g.joints)},
                    {"position", g.closed}});
  }
  const nlohmann::json out = {{"schema", "skelgrasp.joint_states/1"},
                              {"hand", hand.name()},
                              {"object", objectOf(file)},
                              {"grasps", list}};
  return out.dump(2) + "\n";
}

}  // namespace

std::vector<std::string> exportFormatNames() {
  return {"moveit", "joint_states"};
}

ExportFormat parseExportFormat(const std::string& name) {
  if (name == "moveit") return ExportFormat::kMoveIt;
  if (name == "joint_states") return ExportFormat::kJointStates;
  throw InvalidArgument("unknown export format '" + name + "' (known: moveit, joint_states)");
}

std::string defaultExportFileName(ExportFormat format) {
  return format == ExportFormat::kMoveIt ? "grasps.moveit.yaml" : "grasps.joint_states.json";
}

std::string exportGrasps(const nlohmann::json& grasps_json, const HandModel& hand,
                         ExportFormat format, const ExportParams& params) {
  if (!(params.approach_clearance_m >= 0) || !(params.min_retreat_distance_m >= 0) ||
      !(params.retreat_distance_m >= params.min_retreat_distance_m) ||
      !(params.posture_time_s >= 0) || !(params.max_contact_force_n >= 0)) {
    throw InvalidArgument(
        "export parameters must be finite, non-negative and retreat >= min retreat");
  }
  graspsFileKind(grasps_json);  // a file without a schema, or another tool's, is refused
  const auto& list = requiredField(grasps_json, "grasps", "grasps file");
  if (!list.is_array()) throw InvalidArgument("grasps file: \"grasps\" is not a list");
  if (list.size() > kMaxGraspsPerFile) {
    throw InvalidArgument(fmt::format("grasps file holds {} grasps, more than the {} one file may",
                                      list.size(), kMaxGraspsPerFile));
  }
  const auto& file_hand = requiredField(grasps_json, "hand", "grasps file");
  if (!file_hand.is_string() || file_hand.get<std::string>() != hand.name()) {
    throw InvalidArgument(
        fmt::format("grasps file was planned with hand {}, not {}", file_hand.dump(), hand.name()));
  }
  frameOf(grasps_json, params);  // names checked before any grasp is read
  std::vector<GraspFields> grasps;
  for (std::size_t i = 0; i < list.size(); ++i) grasps.push_back(readGrasp(list[i], i, hand));
  return format == ExportFormat::kMoveIt ? moveItYaml(grasps_json, grasps, hand, params)
                                         : jointStatesJson(grasps_json, grasps, hand);
}

}  // namespace skelgrasp::grasping
