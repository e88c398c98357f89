#include "skelgrasp/grasping/contacts_io.h"

#include <cmath>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh.h"
#include "skelgrasp/grasping/quality.h"

namespace skelgrasp::grasping {
namespace {

// Normals shorter than this cannot be normalised into a direction.
constexpr double kMinNormalLength = 1e-9;

Eigen::Vector3d readVector(const nlohmann::json& j, const std::string& path,
                           const std::string& what) {
  if (!j.is_array() || j.size() != 3) throw IoError(path, what + " must be an array of 3 numbers");
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) {
    if (!j[i].is_number()) throw IoError(path, what + " must be an array of 3 numbers");
    v[i] = j[i].get<double>();
  }
  if (!v.allFinite()) throw IoError(path, what + " is not finite");
  return v;
}

Eigen::Vector3d readPosition(const nlohmann::json& j, const std::string& path,
                             const std::string& what) {
  const Eigen::Vector3d p = readVector(j, path, what);
  if (p.cwiseAbs().maxCoeff() > kMaxContactCoordinateM) {
    throw IoError(path, what + " lies more than " + std::to_string(int(kMaxContactCoordinateM)) +
                            " m from the origin (coordinates are metres)");
  }
  return p;
}

}  // namespace

ContactsFile readContactsFile(const std::string& path) {
  const nlohmann::json j = readJsonFile(path);
  if (!j.is_object() || !j.contains("contacts") || !j["contacts"].is_array()) {
    throw IoError(path, "expected {\"contacts\": [{\"point\": [x,y,z], \"normal\": [x,y,z]}]}");
  }
  const auto& list = j["contacts"];
  if (list.empty()) throw IoError(path, "no contacts");
  if (list.size() > kMaxContactsInFile) {
    throw IoError(path, std::to_string(list.size()) + " contacts, at most " +
                            std::to_string(kMaxContactsInFile) + " are supported");
  }
  ContactsFile file;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string name = "contact " + std::to_string(i);
    const auto& c = list[i];
    if (!c.is_object() || !c.contains("point") || !c.contains("normal"))
      throw IoError(path, name + " needs \"point\" and \"normal\"");
    Contact contact;
    contact.point = readPosition(c["point"], path, name + " point");
    contact.normal = readVector(c["normal"], path, name + " normal");
    if (!(contact.normal.norm() > kMinNormalLength))
      throw IoError(path, name + " has a zero normal");
    contact.normal.normalize();
    file.contacts.push_back(contact);
  }
  AxisAlignedBox box;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& c : file.contacts) {
    box.extend(c.point);
    centroid += c.point / static_cast<double>(file.contacts.size());
  }
  file.center = j.contains("center") ? readPosition(j["center"], path, "center") : centroid;
  if (j.contains("torque_scale")) {
    const auto& s = j["torque_scale"];
    if (!s.is_number()) throw IoError(path, "torque_scale must be a number");
    file.torque_scale = s.get<double>();
    if (!(file.torque_scale > 0) || !std::isfinite(file.torque_scale))
      throw IoError(path, "torque_scale must be a positive number of metres");
  } else {
    file.torque_scale = torqueScaleLongestSide(box);
    if (!(file.torque_scale > 0)) {
      throw IoError(path, "the contacts all lie at one point: give \"torque_scale\" (metres)");
    }
  }
  return file;
}

}  // namespace skelgrasp::grasping
