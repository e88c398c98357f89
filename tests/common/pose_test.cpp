#include "skelgrasp/common/pose.h"

#include <gtest/gtest.h>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"

namespace skelgrasp {
namespace {

TEST(Pose, ParsesAndPrintsXyzQuaternion) {
  const Pose pose = parsePose("0.1 -0.2 0.3 0.7071068 0 0.7071068 0");
  EXPECT_TRUE(pose.translation().isApprox(Eigen::Vector3d(0.1, -0.2, 0.3)));
  EXPECT_TRUE(
      (pose.rotation() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX(), 1e-6));
  const auto v = toXyzQuatWxyz(pose);
  EXPECT_NEAR(v[3], 0.7071068, 1e-6);
  EXPECT_NEAR(v[5], 0.7071068, 1e-6);
  const Pose back = poseFromJson(poseToJson(pose));
  EXPECT_TRUE(back.isApprox(pose, 1e-12));
}

TEST(Pose, RejectsMalformedText) {
  EXPECT_THROW(parsePose("1 2 3"), InvalidArgument);
  EXPECT_THROW(parsePose("1 2 3 1 0 0 x"), InvalidArgument);
  EXPECT_THROW(parsePose("1 2 3 1 0 0 0x"), InvalidArgument);   // trailing junk in a token
  EXPECT_THROW(parsePose("0 0 0 2 0 0 0"), InvalidArgument);    // not a unit quaternion
  EXPECT_THROW(parsePose("0 0 0 1 0 0 0 0"), InvalidArgument);  // 8 numbers
  EXPECT_THROW(parsePose(""), InvalidArgument);
}

// The message of the InvalidArgument that parsePose(text) throws ("" if none).
std::string poseError(const std::string& text) {
  try {
    parsePose(text);
  } catch (const InvalidArgument& e) {
    return e.what();
  }
  return "";
}

TEST(Pose, RejectsCommasWithAClearMessage) {
  EXPECT_NE(poseError("0,0,0,1,0,0,0").find("not commas"), std::string::npos);
  EXPECT_NE(poseError("0, 0, 0, 1, 0, 0, 0").find("not commas"), std::string::npos);
}

TEST(Pose, RejectsNonFiniteAndFarAwayPositions) {
  EXPECT_NE(poseError("nan 0 0 1 0 0 0").find("not a finite number"), std::string::npos);
  EXPECT_NE(poseError("0 0 0 inf 0 0 0").find("not a finite number"), std::string::npos);
  EXPECT_NE(poseError("0 0 1e400 1 0 0 0").find("not a finite number"), std::string::npos);
  EXPECT_NE(poseError("1e300 0 0 1 0 0 0").find("from the origin"), std::string::npos);
  // Just inside and just outside the documented bound.
  EXPECT_NO_THROW(parsePose(std::to_string(kMaxPoseDistanceM) + " 0 0 1 0 0 0"));
  EXPECT_THROW(parsePose("0 " + std::to_string(kMaxPoseDistanceM * 1.001) + " 0 1 0 0 0"),
               InvalidArgument);
}

TEST(Pose, NormalisesANearUnitQuaternionAndRejectsAFarOne) {
  // |q| = 1.0005: within 1e-3, normalised to the identity rotation.
  const Pose near = parsePose("0.1 0 0 1.0005 0 0 0");
  EXPECT_TRUE(near.linear().isApprox(Eigen::Matrix3d::Identity(), 1e-12));
  EXPECT_NEAR(near.linear().determinant(), 1.0, 1e-12);
  // |q| = 1.002: rejected, the message gives the length.
  EXPECT_NE(poseError("0 0 0 1.002 0 0 0").find("length 1.002"), std::string::npos);
  EXPECT_NE(poseError("0 0 0 0 0 0 0").find("length 0"), std::string::npos);
}

TEST(Pose, ParsesARowMajorHomogeneousMatrix) {
  // 90 degrees about z, then a translation.
  const Pose pose = parsePose("0 -1 0 0.1  1 0 0 0.2  0 0 1 0.3  0 0 0 1");
  EXPECT_TRUE(pose.translation().isApprox(Eigen::Vector3d(0.1, 0.2, 0.3)));
  EXPECT_TRUE((pose.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY()));
  // Same pose as 7 numbers.
  const Pose same = parsePose("0.1 0.2 0.3 0.70710678 0 0 0.70710678");
  EXPECT_TRUE(pose.isApprox(same, 1e-7));
  // Rotation slightly off (printed to few digits): made exactly orthonormal.
  const Pose rounded = parsePose("0 -1 0 0  1.0004 0 0 0  0 0 1 0  0 0 0 1");
  EXPECT_TRUE((rounded.linear().transpose() * rounded.linear()).isIdentity(1e-12));
}

TEST(Pose, RejectsABadHomogeneousMatrix) {
  EXPECT_NE(poseError("2 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1").find("not orthonormal"),
            std::string::npos);
  EXPECT_NE(poseError("1 0 0 0  0 1 0 0  0 0 1 0  0 0 1 1").find("last row"), std::string::npos);
  EXPECT_NE(poseError("-1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1").find("reflection"), std::string::npos);
  EXPECT_NE(poseError("1 0 0 5e3  0 1 0 0  0 0 1 0  0 0 0 1").find("from the origin"),
            std::string::npos);
  EXPECT_NE(poseError("1 0 0 0  0 1 0 nan  0 0 1 0  0 0 0 1").find("not a finite number"),
            std::string::npos);
}

TEST(Pose, FrameFromZYIsRightHandedAndOrthonormal) {
  const Eigen::Matrix3d r = frameFromZY({0, 0, 2}, {1, 1, 0});
  EXPECT_TRUE((r.transpose() * r).isIdentity(1e-12));
  EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
  EXPECT_TRUE(r.col(2).isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE(r.col(1).isApprox(Eigen::Vector3d(1, 1, 0).normalized()));
}

}  // namespace
}  // namespace skelgrasp
