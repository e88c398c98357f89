// Memory estimates of Poisson reconstruction and regularisation (docs/limits.md).
#include <gtest/gtest.h>

#include "skelgrasp/common/resources.h"
#include "skelgrasp/geometry/regularisation.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/reconstruction/meshing.h"

namespace skelgrasp::reconstruction {
namespace {

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
// A typical single-view object: tens of thousands of points.
constexpr std::size_t kTypicalObjectPoints = 30000;

TEST(PoissonEstimate, GrowsWithDepthAndPoints) {
  PoissonParams params;
  double previous = 0;
  for (int depth = 2; depth <= 14; ++depth) {
    params.depth = depth;
    const double bytes = estimatePoissonBytes(kTypicalObjectPoints, params);
    EXPECT_GT(bytes, previous) << depth;
    previous = bytes;
  }
  params.depth = 8;
  EXPECT_LT(estimatePoissonBytes(1000, params), estimatePoissonBytes(1000000, params));
}

TEST(PoissonEstimate, DefaultsAreFarBelowTheLimitAndDepth14IsNot) {
  EXPECT_LT(estimatePoissonBytes(kTypicalObjectPoints, PoissonParams{}), 0.5 * kGiB);
  PoissonParams deep;
  deep.depth = 14;
  // Issue 13: depth 14 was killed by the kernel at 8-23 GB.
  EXPECT_GT(estimatePoissonBytes(kTypicalObjectPoints, deep), 8 * kGiB);
}

TEST(RegularisationEstimate, WrapGrowsWithAlphaDivisorAndRemeshWithShorterEdges) {
  const TriangleMesh mug = geometry::shapes::makeNamedShape("mug");
  geometry::RegularisationParams params;
  double previous = 0;
  for (double divisor : {10.0, 50.0, 200.0, 1000.0, 1e6}) {
    params.alpha_divisor = divisor;
    const double triangles = geometry::estimateAlphaWrapTriangles(mug, params);
    EXPECT_GT(triangles, previous) << divisor;
    previous = triangles;
  }
  EXPECT_EQ(geometry::estimateRemeshTriangles(mug, geometry::RegularisationParams{}),
            0.0);  // remeshing off
  previous = 0;
  for (double edge : {0.01, 0.003, 0.001, 1e-6}) {
    params.remesh_target_edge_m = edge;
    const double triangles = geometry::estimateRemeshTriangles(mug, params);
    EXPECT_GT(triangles, previous) << edge;
    previous = triangles;
  }
}

TEST(RegularisationEstimate, RemeshCountsTrianglesOfTheArea) {
  // A 1 m cube (area 6 m^2) at 0.1 m edges: 6 / (sqrt(3)/4 x 0.01) = 1386 equilateral triangles,
  // 1680 with the measured 2.8 A / e^2.
  const TriangleMesh cube = geometry::shapes::makeBox({1, 1, 1});
  geometry::RegularisationParams params;
  params.remesh_target_edge_m = 0.1;
  EXPECT_NEAR(geometry::estimateRemeshTriangles(cube, params), 1680, 30);
}

TEST(RegularisationEstimate, DefaultsAreFarBelowTheLimit) {
  const TriangleMesh mug = geometry::shapes::makeNamedShape("mug");
  EXPECT_LT(geometry::estimateRegularisedBytes(
                geometry::estimateAlphaWrapTriangles(mug, geometry::RegularisationParams{})),
            0.5 * kGiB);
}

TEST(RegularisationEstimate, RegulariseRefusesBeforeWrapping) {
  const TriangleMesh mug = geometry::shapes::makeNamedShape("mug");
  geometry::RegularisationParams fine;
  fine.alpha_divisor = 1e6;
  EXPECT_THROW(geometry::regularise(mug, fine), ResourceLimitExceeded);
  geometry::RegularisationParams remesh;
  remesh.remesh_target_edge_m = 1e-6;
  EXPECT_THROW(geometry::regularise(mug, remesh), ResourceLimitExceeded);
}

}  // namespace
}  // namespace skelgrasp::reconstruction
