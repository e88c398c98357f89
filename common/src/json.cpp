#include "skelgrasp/common/json.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "skelgrasp/common/error.h"

namespace skelgrasp {
namespace {

// Deepest nesting of arrays and objects readJsonFile accepts. skelgrasp's own files nest fewer
// than ten levels (a run file: document, objects, grasps, a grasp, its pose, a list).
constexpr int kMaxJsonNestingDepth = 64;

// Whether arrays and objects in `text` nest more than kMaxJsonNestingDepth levels deep (brackets
// inside strings do not count). A linear scan before parsing: nlohmann's callback parser, which
// could count the depth as it goes, walks the enclosing array at the end of every object, so a
// file of a million grasps took minutes to read.
bool nestsTooDeep(const std::string& text) {
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') {
        ++i;  // the escaped character, a quote included
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonNestingDepth) return true;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return false;
}

}  // namespace

nlohmann::json toJson(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

nlohmann::json toJson(const Status& s) {
  return {{"code", toString(s.code)}, {"message", s.message}};
}

nlohmann::json numberOrNull(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

nlohmann::json numberOrNull(const std::optional<double>& value) {
  return value ? numberOrNull(*value) : nlohmann::json(nullptr);
}

nlohmann::json poseToJson(const Pose& pose) {
  const auto v = toXyzQuatWxyz(pose);
  return {{"position", {v[0], v[1], v[2]}}, {"quaternion_wxyz", {v[3], v[4], v[5], v[6]}}};
}

Pose poseFromJson(const nlohmann::json& j) {
  try {
    const auto& p = j.at("position");
    const auto& q = j.at("quaternion_wxyz");
    if (p.size() != 3 || q.size() != 4) throw InvalidArgument("pose: wrong array sizes");
    return makePose({p[0].get<double>(), p[1].get<double>(), p[2].get<double>()},
                    Eigen::Quaterniond(q[0].get<double>(), q[1].get<double>(), q[2].get<double>(),
                                       q[3].get<double>()));
  } catch (const nlohmann::json::exception& e) {
    throw InvalidArgument(
        std::string("pose: expected {\"position\": [3], \"quaternion_wxyz\": [4]}: ") + e.what());
  }
}

void writeJsonFile(const std::string& path, const nlohmann::json& j, int indent) {
  writeFileAtomically(path, j.dump(indent) + "\n");
}

std::string describeJsonError(const nlohmann::json::exception& error, const std::string& text) {
  // nlohmann's messages are "[json.exception.parse_error.101] parse error at line L, column C:
  // <reason>" or "[json.exception.out_of_range.406] <reason>"; keep the reason only.
  std::string reason = error.what();
  const auto column_at = reason.find(", column ");
  const auto colon =
      column_at == std::string::npos ? reason.find("] ") : reason.find(": ", column_at);
  if (colon != std::string::npos) reason = reason.substr(colon + 2);
  const auto* parse_error = dynamic_cast<const nlohmann::json::parse_error*>(&error);
  if (!parse_error) return "not valid JSON: " + reason;
  // byte counts from 1 and points just past the offending character.
  const std::size_t end =
      std::min<std::size_t>(parse_error->byte > 0 ? parse_error->byte - 1 : 0, text.size());
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < end; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "not valid JSON at line " + std::to_string(line) + ", column " + std::to_string(column) +
         ": " + reason;
}

nlohmann::json readJsonFile(const std::string& path, std::uintmax_t max_bytes) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw IoError(path, "no such file");
  if (fs::is_directory(path, ec)) throw IoError(path, "is a directory, expected a JSON file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw IoError(path, "cannot read file size: " + ec.message());
  if (size > max_bytes) {
    throw IoError(path, "JSON file of " + std::to_string(size) + " bytes exceeds the limit of " +
                            std::to_string(max_bytes) + " bytes");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, "cannot open for reading");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw IoError(path, "read failed");
  const std::string text = buffer.str();
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) throw IoError(path, "file is empty");
  // Nesting deeper than any file skelgrasp writes is refused before parsing: a grasp "id" nested
  // 100 000 arrays deep (a 212 KB file) was copied into scores.json, and dumping it with an
  // indent asked for about 20 GB; recursion over such a value can also exhaust the stack.
  if (nestsTooDeep(text)) {
    throw IoError(path,
                  "JSON nesting deeper than " + std::to_string(kMaxJsonNestingDepth) + " levels");
  }
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    // parse errors, and out_of_range for numbers beyond double ("1e999")
    throw IoError(path, describeJsonError(e, text));
  }
}

}  // namespace skelgrasp
