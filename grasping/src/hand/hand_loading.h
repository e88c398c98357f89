#pragma once
// Internal: the pieces of hand loading (URDF through urdfdom, meshes through assimp, the grasp
// description through nlohmann::json).
#include <string>
#include <vector>

#include "skelgrasp/grasping/hand/hand_model.h"

namespace skelgrasp::grasping::internal {

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
