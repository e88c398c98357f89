#pragma once
// nlohmann::json conversions for the shared types, and atomic JSON file output.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <string>

#include "skelgrasp/common/atomic_file.h"  // writeFileAtomically, for existing callers
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/pose.h"

namespace skelgrasp {

nlohmann::json toJson(const Eigen::Vector3d& v);
// {"code": "ok" | ..., "message": ...}
nlohmann::json toJson(const Status& status);
// {"position": [x, y, z], "quaternion_wxyz": [w, x, y, z]}
nlohmann::json poseToJson(const Pose& pose);
Pose poseFromJson(const nlohmann::json& j);
// A double that may be NaN: NaN becomes null.
nlohmann::json numberOrNull(double value);
// A value that may be absent (not computed): absent becomes null.
nlohmann::json numberOrNull(const std::optional<double>& value);

// Written atomically (atomic_file.h): readers never see a half-written file. Creates parent
// directories. Throws IoError.
void writeJsonFile(const std::string& path, const nlohmann::json& j, int indent = 2);
// JSON files skelgrasp reads (descriptions, contacts, reports) are kilobytes to a few megabytes;
// nlohmann's document takes about ten times the text, so larger files are refused unread.
inline constexpr std::uintmax_t kMaxJsonFileBytes = 64u << 20;
// Throws IoError naming the file: "no such file", "is a directory", "file is empty", larger
// than `max_bytes`, or "not valid JSON at line N, column C: <reason>".
nlohmann::json readJsonFile(const std::string& path, std::uintmax_t max_bytes = kMaxJsonFileBytes);
// The problem of parsing `text`, as "not valid JSON at line N, column C: <reason>" (parse errors)
// or "not valid JSON: <reason>" (e.g. a number beyond double's range).
std::string describeJsonError(const nlohmann::json::exception& error, const std::string& text);

}  // namespace skelgrasp
