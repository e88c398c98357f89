#pragma once
// Rigid poses are Eigen::Isometry3d (metres, radians). Text form used on the command line and in
// JSON: "x y z qw qx qy qz" (position, then a unit quaternion w-first).
#include <Eigen/Geometry>

#include <array>
#include <string>

namespace skelgrasp {

using Pose = Eigen::Isometry3d;

Pose makePose(const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation);

// Limits of a pose given as text (command line, capture descriptions, transform files).
// A position farther than this from the origin, in metres, is a unit or typing mistake: scenes
// the pipeline handles are a few metres across.
constexpr double kMaxPoseDistanceM = 1e3;
// A quaternion is accepted when | |q| - 1 | is at most this (and then normalised); a 4x4 matrix
// when its rotation block's R^T R differs from the identity by at most this in every entry.
constexpr double kPoseUnitTolerance = 1e-3;

// Parses 7 whitespace-separated finite numbers "x y z qw qx qy qz" (metres, w-first quaternion)
// or 16 "r00 r01 r02 x r10 ... 0 0 0 1" (row-major 4x4 homogeneous matrix). Throws
// InvalidArgument, naming the problem, for: commas or other separators, a token that is not a
// number, another count of numbers, a non-finite number, a position beyond kMaxPoseDistanceM, a
// quaternion or rotation block off unit/orthonormal by more than kPoseUnitTolerance, a reflection,
// or a last row other than 0 0 0 1. A near-unit quaternion or near-orthonormal rotation is made
// exact, with a warning when the correction is larger than printing rounding (1e-6).
Pose parsePose(const std::string& text);

// Position and w-first quaternion.
std::array<double, 7> toXyzQuatWxyz(const Pose& pose);

// Rotation whose z axis is `z` and whose y axis is as close as possible to `y_hint`.
Eigen::Matrix3d frameFromZY(const Eigen::Vector3d& z, const Eigen::Vector3d& y_hint);
// The pose at `position` with that frame (a grasp centre point: z = approach, y = finger spread).
Pose poseFromZY(const Eigen::Vector3d& position, const Eigen::Vector3d& z,
                const Eigen::Vector3d& y_hint);

// Any unit vector perpendicular to v.
Eigen::Vector3d anyPerpendicular(const Eigen::Vector3d& v);

}  // namespace skelgrasp
