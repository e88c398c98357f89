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
  EXPECT_THROW(parsePose("0 0 0 2 0 0 0"), InvalidArgument);  // not a unit quaternion
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
