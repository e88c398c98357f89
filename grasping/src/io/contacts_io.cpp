#include "skelgrasp/grasping/io/contacts_io.h"

#include <fmt/format.h>

#include <cmath>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/grasping/quality/quality.h"

namespace skelgrasp::grasping {
namespace {

// Bytes of one contact in the file, generously ({"point": [...], "normal": [...]} with long
// numbers and indentation): sizes the file limit from the contact limit.
constexpr std::uintmax_t kMaxBytesPerContact = 1024;
constexpr std::uintmax_t kMinContactFileLimitBytes = 1 << 20;

Eigen::Vector3d readVector(const std::string& path, const std::string& where,
                           const nlohmann::json& j) {
  if (!j.is_array() || j.size() != 3) throw IoError(path, where + " must be an array of 3 numbers");
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) {
    if (!j[i].is_number()) throw IoError(path, where + " must be an array of 3 numbers");
    v[i] = j[i].get<double>();
  }
  if (!v.allFinite()) throw IoError(path, where + " is not finite");
  return v;
}

}  // namespace

ContactSet readContactsFile(const std::string& path, const ContactFileLimits& limits) {
  const std::uintmax_t max_bytes = std::max<std::uintmax_t>(
      kMinContactFileLimitBytes, limits.max_contacts * kMaxBytesPerContact);
  const nlohmann::json j = readJsonFile(path, max_bytes);
  const std::string layout =
      "expected {\"contacts\": [{\"point\": [x,y,z], \"normal\": [x,y,z]}, ...]}";
  if (!j.is_object() || !j.contains("contacts") || !j["contacts"].is_array()) {
    throw IoError(path, layout);
  }
  const auto& list = j["contacts"];
  if (list.empty()) throw IoError(path, "no contacts");
  if (list.size() > limits.max_contacts) {
    throw IoError(path, fmt::format("{} contacts, more than the limit of {} (the wrench-space hull "
                                    "grows with contacts x cone edges in 6-D)",
                                    list.size(), limits.max_contacts));
  }
  auto checkDistance = [&](const std::string& where, const Eigen::Vector3d& p) {
    if (p.stableNorm() > limits.max_distance_m) {
      throw IoError(
          path, fmt::format("{} is {:.3g} m from the origin, beyond the limit of {:.3g} m", where,
                            p.stableNorm(), limits.max_distance_m));
    }
  };
  ContactSet set;
  AxisAlignedBox box;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string where = "contact " + std::to_string(i);
    const auto& c = list[i];
    if (!c.is_object() || !c.contains("point") || !c.contains("normal")) {
      throw IoError(path, where + ": " + layout);
    }
    Contact contact;
    contact.point = readVector(path, where + " point", c["point"]);
    checkDistance(where + " point", contact.point);
    contact.normal = readVector(path, where + " normal", c["normal"]);
    const double length = contact.normal.stableNorm();
    if (!(length > 1e-9)) throw IoError(path, where + " normal has zero length");
    if (std::abs(length - 1.0) > limits.normal_tolerance) {
      log().warn("{}: {} normal has length {:.4g}; normalised", path, where, length);
    }
    contact.normal /= length;
    box.extend(contact.point);
    set.center += contact.point / static_cast<double>(list.size());
    set.contacts.push_back(contact);
  }
  if (j.contains("center")) {
    set.center = readVector(path, "center", j["center"]);
    checkDistance("center", set.center);
  }
  set.torque_scale = torqueScaleLongestSide(box);
  if (j.contains("torque_scale")) {
    if (!j["torque_scale"].is_number()) throw IoError(path, "torque_scale must be a number");
    set.torque_scale = j["torque_scale"].get<double>();
    if (!(set.torque_scale > 0) || !std::isfinite(set.torque_scale)) {
      throw IoError(path, "torque_scale must be a positive finite number");
    }
  }
  return set;
}

}  // namespace skelgrasp::grasping
