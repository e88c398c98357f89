#include "skelgrasp/common/pose.h"

#include <fmt/format.h>

#include <Eigen/SVD>

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/logging.h"

namespace skelgrasp {

Pose makePose(const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation) {
  Pose pose = Pose::Identity();
  pose.linear() = orientation.normalized().toRotationMatrix();
  pose.translation() = position;
  return pose;
}

namespace {

// Corrections smaller than this come from printing a pose with 6-7 digits: made silently.
constexpr double kPoseRoundingTolerance = 1e-6;
// A y hint shorter than this after removing its z part is (nearly) parallel to z: any
// perpendicular is used instead (unit vectors, so dimensionless).
constexpr double kParallelHintNorm = 1e-9;

std::vector<double> poseNumbers(const std::string& text) {
  const auto fail = [&](const std::string& problem) {
    return InvalidArgument("pose '" + text + "': " + problem);
  };
  if (text.find(',') != std::string::npos) {
    throw fail("separate the numbers with spaces, not commas");
  }
  std::istringstream in(text);
  std::vector<double> values;
  for (std::string token; in >> token;) {
    const char* begin = token.c_str();
    char* end = nullptr;
    const double value = std::strtod(begin, &end);
    if (end != begin + token.size()) throw fail("'" + token + "' is not a number");
    if (!std::isfinite(value)) throw fail("'" + token + "' is not a finite number");
    values.push_back(value);
  }
  if (values.size() != 7 && values.size() != 16) {
    throw fail("expected 7 numbers \"x y z qw qx qy qz\" or 16 (a row-major 4x4 matrix), found " +
               std::to_string(values.size()));
  }
  return values;
}

Eigen::Quaterniond unitQuaternion(const std::string& text, const Eigen::Quaterniond& q) {
  const double norm = q.norm();
  if (!(std::abs(norm - 1.0) <= kPoseUnitTolerance)) {
    throw InvalidArgument(
        fmt::format("pose '{}': quaternion (qw qx qy qz) has length {:.6g}, expected 1 within {:g}",
                    text, norm, kPoseUnitTolerance));
  }
  if (std::abs(norm - 1.0) > kPoseRoundingTolerance) {
    log().warn("pose '{}': quaternion length {:.6g} normalised to 1", text, norm);
  }
  return q.normalized();
}

Eigen::Matrix3d rotationBlock(const std::string& text, const Eigen::Matrix4d& m) {
  const Eigen::RowVector4d last = m.row(3);
  if ((last - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > kPoseRoundingTolerance) {
    throw InvalidArgument("pose '" + text + "': last row of the 4x4 matrix must be 0 0 0 1");
  }
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  const double off = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(off <= kPoseUnitTolerance)) {
    throw InvalidArgument(
        fmt::format("pose '{}': rotation block is not orthonormal (R^T R - I up to {:.3g}, at "
                    "most {:g} allowed)",
                    text, off, kPoseUnitTolerance));
  }
  if (r.determinant() < 0) {
    throw InvalidArgument("pose '" + text + "': rotation block is a reflection (determinant -1)");
  }
  // Nearest rotation: the orthonormal polar factor U V^T.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  if (off > kPoseRoundingTolerance) {
    log().warn("pose '{}': rotation block off orthonormal by {:.3g}, made orthonormal", text, off);
  }
  return svd.matrixU() * svd.matrixV().transpose();
}

}  // namespace

Pose parsePose(const std::string& text) {
  const std::vector<double> v = poseNumbers(text);
  Pose pose = Pose::Identity();
  if (v.size() == 7) {
    pose.linear() =
        unitQuaternion(text, Eigen::Quaterniond(v[3], v[4], v[5], v[6])).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  } else {
    const Eigen::Matrix4d m =
        Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(v.data());
    pose.linear() = rotationBlock(text, m);
    pose.translation() = m.topRightCorner<3, 1>();
  }
  if (!(pose.translation().stableNorm() <= kMaxPoseDistanceM)) {
    throw InvalidArgument(
        fmt::format("pose '{}': position is {:.3g} m from the origin, at most {:g} m allowed", text,
                    pose.translation().stableNorm(), kMaxPoseDistanceM));
  }
  return pose;
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
  if (y.norm() < kParallelHintNorm) y = anyPerpendicular(zn);
  y.normalize();
  Eigen::Matrix3d r;
  r.col(0) = y.cross(zn);
  r.col(1) = y;
  r.col(2) = zn;
  return r;
}

Pose poseFromZY(const Eigen::Vector3d& position, const Eigen::Vector3d& z,
                const Eigen::Vector3d& y_hint) {
  Pose pose = Pose::Identity();
  pose.linear() = frameFromZY(z, y_hint);
  pose.translation() = position;
  return pose;
}

}  // namespace skelgrasp
