#pragma once
// nlohmann::json conversions for the shared types, and atomic JSON file output.
#include <nlohmann/json.hpp>

#include <string>

#include "skelgrasp/common/atomic_file.h"  // writeFileAtomically, for existing callers
#include "skelgrasp/common/mesh_topology.h"
#include "skelgrasp/common/pose.h"

namespace skelgrasp {

nlohmann::json toJson(const Eigen::Vector3d& v);
nlohmann::json toJson(const MeshTopology& topology);
// {"position": [x, y, z], "quaternion_wxyz": [w, x, y, z]}
nlohmann::json poseToJson(const Pose& pose);
Pose poseFromJson(const nlohmann::json& j);
// A double that may be NaN: NaN becomes null.
nlohmann::json numberOrNull(double value);

// Written atomically (atomic_file.h): readers never see a half-written file. Creates parent
// directories. Throws IoError.
void writeJsonFile(const std::string& path, const nlohmann::json& j, int indent = 2);
// Throws IoError naming the file on missing file or parse error.
nlohmann::json readJsonFile(const std::string& path);

}  // namespace skelgrasp
