#pragma once
// Rigid poses are Eigen::Isometry3d (metres, radians). Text form used on the command line and in
// JSON: "x y z qw qx qy qz" (position, then a unit quaternion w-first).
#include <Eigen/Geometry>

#include <array>
#include <string>

namespace skelgrasp {

using Pose = Eigen::Isometry3d;

Pose makePose(const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation);

// Parses "x y z qw qx qy qz" (commas also accepted). Throws InvalidArgument on malformed text or a
// quaternion that is not close to unit length (it is normalised when within 1e-3).
Pose parsePose(const std::string& text);

// Position and w-first quaternion.
std::array<double, 7> toXyzQuatWxyz(const Pose& pose);

// Rotation whose z axis is `z` and whose y axis is as close as possible to `y_hint`.
Eigen::Matrix3d frameFromZY(const Eigen::Vector3d& z, const Eigen::Vector3d& y_hint);

// Any unit vector perpendicular to v.
Eigen::Vector3d anyPerpendicular(const Eigen::Vector3d& v);

}  // namespace skelgrasp
