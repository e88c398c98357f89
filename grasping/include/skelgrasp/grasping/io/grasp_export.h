#pragma once
// Grasps in formats robot stacks load (docs/export.md): MoveIt's moveit_msgs/Grasp list as YAML,
// and the hand's closed configuration as sensor_msgs/JointState-like name/position lists (JSON).
// The input is our own grasps.json (schemas skelgrasp.grasps/1-3 and skelgrasp.run/1-4).
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/grasping/hand/hand_model.h"

namespace skelgrasp::grasping {

enum class ExportFormat { kMoveIt, kJointStates };

// "moveit" or "joint_states"; throws InvalidArgument naming the known formats.
ExportFormat parseExportFormat(const std::string& name);
std::vector<std::string> exportFormatNames();
// The file name an export is written to by default, e.g. "grasps.moveit.yaml".
std::string defaultExportFileName(ExportFormat format);

struct ExportParams {
  // Frame of grasp_pose. nullopt: the frame the grasps.json states (run: "scan"), else the
  // object's name (plan: poses are in the mesh's frame).
  std::optional<std::string> frame_id;
  // pre_grasp_approach: the hand moves along its approach direction from
  // retreat_m + approach_clearance_m before the grasp pose, at least retreat_m.
  double approach_clearance_m = 0.05;
  // post_grasp_retreat: back along the approach direction by this much (at least
  // min_retreat_distance_m) after closing.
  double retreat_distance_m = 0.10;
  double min_retreat_distance_m = 0.05;
  // time_from_start of the single posture point (s).
  double posture_time_s = 0.5;
  // max_contact_force (N); 0 disables MoveIt's force limit.
  double max_contact_force_n = 0;
};

// The export text of every grasp in `grasps_json` (a parsed grasps.json) for `hand`, which must be
// the hand the grasps were planned with (its name is checked against the file's "hand").
// Throws InvalidArgument for a grasps.json without the fields an export needs, for joint names the
// hand does not have, or for a hand that is not the file's.
std::string exportGrasps(const nlohmann::json& grasps_json, const HandModel& hand,
                         ExportFormat format, const ExportParams& params = {});

}  // namespace skelgrasp::grasping
