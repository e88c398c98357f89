#include "skelgrasp/geometry/mesh_query.h"

#include <gtest/gtest.h>

#include "skelgrasp/geometry/shapes.h"

namespace skelgrasp::geometry {
namespace {

TEST(MeshQuery, InsideOutsideAndDistanceOfABox) {
  const MeshQuery query(geometry::shapes::makeBox({0.2, 0.2, 0.2}, 2));
  EXPECT_TRUE(query.contains({0, 0, 0}));
  EXPECT_TRUE(query.contains({0.09, -0.09, 0.05}));
  EXPECT_FALSE(query.contains({0.11, 0, 0}));
  EXPECT_NEAR(query.distance({0.3, 0, 0}), 0.2, 1e-12);
  EXPECT_NEAR(query.distance({0.05, 0, 0}), 0.05, 1e-12);
  EXPECT_TRUE(query.closestPoint({0.3, 0.01, 0.02}).isApprox(Eigen::Vector3d(0.1, 0.01, 0.02)));
  const auto [point, face] = query.closestPointAndFace({0, 0, 0.5});
  EXPECT_NEAR(point.z(), 0.1, 1e-12);
  EXPECT_LT(face, geometry::shapes::makeBox({0.2, 0.2, 0.2}, 2).numFaces());
  const auto hit = query.firstHit({0.5, 0.01, 0.02}, {-1, 0, 0});
  ASSERT_TRUE(hit.has_value());
  EXPECT_TRUE(hit->isApprox(Eigen::Vector3d(0.1, 0.01, 0.02), 1e-12));
  EXPECT_FALSE(query.firstHit({0.5, 0.01, 0.02}, {1, 0, 0}).has_value());
}

}  // namespace
}  // namespace skelgrasp::geometry
