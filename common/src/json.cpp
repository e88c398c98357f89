#include "skelgrasp/common/json.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "skelgrasp/common/error.h"

namespace skelgrasp {

nlohmann::json toJson(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

nlohmann::json numberOrNull(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

nlohmann::json toJson(const MeshTopology& t) {
  return {{"vertices", t.vertices},
          {"faces", t.faces},
          {"edges", t.edges},
          {"boundary_edges", t.boundary_edges},
          {"non_manifold_edges", t.non_manifold_edges},
          {"inconsistently_oriented_edges", t.inconsistently_oriented_edges},
          {"components", t.components},
          {"closed", t.closed},
          {"euler_characteristic", t.euler_characteristic},
          {"genus", t.genus ? nlohmann::json(*t.genus) : nlohmann::json(nullptr)},
          {"signed_volume_m3", t.signed_volume}};
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

nlohmann::json readJsonFile(const std::string& path) {
  std::ifstream in(path);
  if (!in)
    throw IoError(path, std::filesystem::exists(path) ? "cannot open for reading" : "no such file");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw IoError(path, std::string("invalid JSON: ") + e.what());
  }
}

}  // namespace skelgrasp
