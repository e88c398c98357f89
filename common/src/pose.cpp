#include "skelgrasp/common/pose.h"

#include <cmath>
#include <sstream>
#include <vector>

#include "skelgrasp/common/error.h"

namespace skelgrasp {

Pose makePose(const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation) {
  Pose pose = Pose::Identity();
  pose.linear() = orientation.normalized().toRotationMatrix();
  pose.translation() = position;
  return pose;
}

Pose parsePose(const std::string& text) {
  std::string cleaned = text;
  for (char& c : cleaned) {
    if (c == ',') c = ' ';
  }
  std::istringstream in(cleaned);
  std::vector<double> values;
  double v;
  while (in >> v) values.push_back(v);
  if (!in.eof() || values.size() != 7) {
    throw InvalidArgument("pose '" + text + "': expected 7 numbers \"x y z qw qx qy qz\"");
  }
  for (double x : values) {
    if (!std::isfinite(x)) throw InvalidArgument("pose '" + text + "': non-finite value");
  }
  const Eigen::Quaterniond q(values[3], values[4], values[5], values[6]);
  if (std::abs(q.norm() - 1.0) > 1e-3) {
    throw InvalidArgument("pose '" + text + "': quaternion is not unit length (norm " +
                          std::to_string(q.norm()) + ")");
  }
  return makePose({values[0], values[1], values[2]}, q);
}

std::array<double, 7> toXyzQuatWxyz(const Pose& pose) {
  Eigen::Quaterniond q(pose.rotation());
  q.normalize();
  if (q.w() < 0) q.coeffs() *= -1;  // canonical hemisphere for stable output
  const auto& p = pose.translation();
  return {p.x(), p.y(), p.z(), q.w(), q.x(), q.y(), q.z()};
}

Eigen::Vector3d anyPerpendicular(const Eigen::Vector3d& v) {
  const Eigen::Vector3d a =
      std::abs(v.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return v.cross(a).normalized();
}

Eigen::Matrix3d frameFromZY(const Eigen::Vector3d& z, const Eigen::Vector3d& y_hint) {
  const Eigen::Vector3d zn = z.normalized();
  Eigen::Vector3d y = y_hint - y_hint.dot(zn) * zn;
  if (y.norm() < 1e-9) y = anyPerpendicular(zn);
  y.normalize();
  Eigen::Matrix3d r;
  r.col(0) = y.cross(zn);
  r.col(1) = y;
  r.col(2) = zn;
  return r;
}

}  // namespace skelgrasp
