#pragma once
// Reading our grasps.json files back: `plan`'s (schema skelgrasp.grasps/*, docs/planning.md) and
// `run`'s (skelgrasp.run/*, docs/pipeline.md), or a file another tool's grasps were converted to.
// The field readers are shared by every command that reads grasps (export, score), so a bad file
// gets the same message from each.
#include <nlohmann/json.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/common/pose.h"
#include "skelgrasp/grasping/hand/hand_model.h"

namespace skelgrasp::grasping {

// Limits of the values a grasps file hands to a robot (export) or to the simulation (score,
// simulate): beyond them a value is a corrupt or hostile file, never a grasp.
// A hand pose farther than this from the object's frame, in metres, holds nothing of it.
inline constexpr double kMaxGraspPositionM = 100;
// A grasp's "retreat_m" (how far the hand backed off along its approach) beyond this, in metres,
// is longer than any hand.
inline constexpr double kMaxRetreatM = 1;
// Closed joint values may pass the URDF limits by this much (rad or m): rounding of the written
// value, never a joint driven past its stop.
inline constexpr double kJointLimitTolerance = 1e-3;

// The field `key` of `j`; InvalidArgument "<where> has no "<key>"" when it is missing.
const nlohmann::json& requiredField(const nlohmann::json& j, const char* key,
                                    const std::string& where);
// A field that must be a finite number.
double finiteNumberField(const nlohmann::json& j, const char* key, const std::string& where);
// A grasp's "hand_pose" ({"position": [3], "quaternion_wxyz": [4]}, the quaternion normalised);
// InvalidArgument when it is missing, malformed, not finite, its position is beyond
// kMaxGraspPositionM or its quaternion's length differs from 1 by more than kPoseUnitTolerance
// (the tolerance of --pose).
Pose handPoseField(const nlohmann::json& grasp, const std::string& where);
// A grasp's "retreat_m": finite, in [0, kMaxRetreatM].
double retreatField(const nlohmann::json& grasp, const std::string& where);
// A grasp's closed "joints" ({"name": value}): every movable joint of `hand` present, no other
// name, each value finite and within the joint's URDF limits widened by kJointLimitTolerance.
// Returns the values in the hand's joint order (NaN for fixed joints).
std::vector<double> closedJointsField(const nlohmann::json& grasp, const HandModel& hand,
                                      const std::string& where);
// A grasp's "preshape", checked against the hand (InvalidArgument naming the hand's preshapes).
// Without one: defaultPreshapeName(hand) when `required` is false, else InvalidArgument.
std::string preshapeField(const nlohmann::json& grasp, const HandModel& hand,
                          const std::string& where, bool required);
// The preshape a grasp without one is placed with: "power" when the hand has it, else the hand's
// only preshape; InvalidArgument when neither exists.
std::string defaultPreshapeName(const HandModel& hand);

enum class GraspsFileKind {
  kPlan,  // "schema": "skelgrasp.grasps/<n>": a top-level "grasps" list
  kRun,   // "schema": "skelgrasp.run/<n>": "grasps" of every object, each with "object": id
};
// From the file's "schema"; InvalidArgument for a missing or foreign schema.
GraspsFileKind graspsFileKind(const nlohmann::json& file);

// What placing a grasp again needs: where the hand is and how it is opened.
struct GraspPlacement {
  nlohmann::json id;  // the input grasp's "id" as written (any JSON value), null without one
  Pose hand_pose = Pose::Identity();  // hand root in the mesh's frame
  std::string preshape;
};

// Most grasps one file may hold: far beyond what a planner returns for one object, small enough
// that the file's placements and their scores fit in memory.
inline constexpr std::size_t kMaxGraspsPerFile = 1'000'000;

// The grasps of a parsed grasps.json to place with `hand`: every grasp of a plan file; of a run
// file the grasps of object `object`, which must be given when the file lists more than one
// object (a run file with one object needs none). A file naming another hand than `hand` is
// refused (its poses are another hand's root poses). Only "hand_pose" is required per grasp;
// "preshape" defaults to defaultPreshapeName(hand). Throws InvalidArgument saying which grasp and
// field is wrong.
std::vector<GraspPlacement> readGraspPlacements(const nlohmann::json& file, const HandModel& hand,
                                                const std::optional<long long>& object = {});

}  // namespace skelgrasp::grasping
