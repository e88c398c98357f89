#pragma once
// Internal: the pieces of hand loading (URDF through urdfdom, meshes through assimp, the grasp
// description through nlohmann::json).
#include <cstdint>
#include <string>
#include <vector>

#include "skelgrasp/grasping/hand/hand_model.h"

namespace skelgrasp::grasping::internal {

// Bounds of the files a hand is made of, checked before a byte is parsed: a real hand's URDF is
// tens of kilobytes with a few dozen links, its description a few kilobytes, its link meshes at
// most a few megabytes. Beyond these a file is a mistake or hostile (`/dev/zero` grew past 4 GB;
// 10 000 links took 3.4 GB; a 130 MB STL finger 5.1 GB and 98 s).
inline constexpr std::uintmax_t kMaxUrdfBytes = 8u << 20;
inline constexpr std::uintmax_t kMaxGraspDescriptionBytes = 4u << 20;
inline constexpr std::uintmax_t kMaxLinkMeshBytes = 16u << 20;
// Most links (and joints) of one hand.
inline constexpr std::size_t kMaxHandLinks = 1000;
// Any length in a hand's files (a shape's size, an origin's or a grasp centre's offset), in
// metres: a hand is well under a metre across, so beyond this a value is a unit or typing mistake
// that would only put fingers through the object.
inline constexpr double kMaxHandLengthM = 10;
// Joint limits, mimic factors and coupling ratios beyond this (rad, m or a ratio) belong to no
// hand.
inline constexpr double kMaxJointLimit = 1e3;

// The text of a regular file of at most `max_bytes`; `what` names it in errors ("URDF").
// Throws IoError(path, problem).
std::string readBoundedText(const std::string& path, std::uintmax_t max_bytes,
                            const std::string& what);

struct ParsedUrdf {
  std::string name;
  std::vector<Link> links;
  std::vector<Joint> joints;
  int root_link = 0;
};

// Throws IoError(origin, problem).
ParsedUrdf parseUrdf(const std::string& urdf_xml, const std::string& base_dir,
                     const std::string& origin);

// Any mesh format assimp reads (STL, DAE, OBJ, PLY, ...), scaled per axis. Throws IoError.
TriangleMesh loadMeshFile(const std::string& path, const Eigen::Vector3d& scale);

// Applies a grasp description (JSON text) to a model. Throws IoError(origin, problem).
void applyGraspDescription(HandModel& hand, const std::string& description_json,
                           const std::string& origin);

}  // namespace skelgrasp::grasping::internal
