// Error bounds of a reconstructed surface (reconstruction/surface_error.h): observed vertices get
// twice the sensor's noise at their distance, filled-in ones grow with the distance to the data up
// to the cap, and the clearance around a point is the largest bound of the surface nearest it.
#include "skelgrasp/reconstruction/surface_error.h"

#include <gtest/gtest.h>

#include "skelgrasp/geometry/shapes.h"

namespace skelgrasp::reconstruction {
namespace {

// A 10 cm box 0.8 m in front of the sensor (+x), its near half observed.
struct SeenBox {
  TriangleMesh mesh = geometry::shapes::makeBox({0.1, 0.1, 0.1}, 8);
  std::vector<std::uint8_t> observed;
  Eigen::Vector3d sensor = Eigen::Vector3d(-0.8, 0, 0);
  SeenBox() {
    for (const auto& v : mesh.vertices) observed.push_back(v.x() < 0 ? 1 : 0);
  }
};

TEST(SurfaceError, ObservedVerticesGetTwiceTheSensorNoise) {
  const SeenBox box;
  const SurfaceErrorParams params;
  const auto result = surfaceErrorBounds(box.mesh, box.observed, box.sensor, params);
  ASSERT_TRUE(result.status.ok()) << result.status.message;
  ASSERT_EQ(result.bound_m.size(), box.mesh.vertices.size());
  for (std::size_t i = 0; i < box.mesh.vertices.size(); ++i) {
    if (!box.observed[i]) continue;
    const double z = (box.mesh.vertices[i] - box.sensor).norm();
    EXPECT_NEAR(result.bound_m[i], 2 * (0.0012 + 0.0019 * (z - 0.4) * (z - 0.4)), 1e-12);
  }
  EXPECT_GT(result.observed, 0u);
  EXPECT_GT(result.filled, 0u);
  EXPECT_NEAR(result.observed_median_m, 0.003, 0.0002);  // 2 x 1.5 mm at 0.75-0.8 m
}

TEST(SurfaceError, FilledInBoundsGrowWithTheDistanceToTheDataUpToTheCap) {
  const SeenBox box;
  SurfaceErrorParams params;
  const auto result = surfaceErrorBounds(box.mesh, box.observed, box.sensor, params);
  double back = 0, seam = 1;
  for (std::size_t i = 0; i < box.mesh.vertices.size(); ++i) {
    if (box.observed[i]) continue;
    const Eigen::Vector3d& v = box.mesh.vertices[i];
    EXPECT_LE(result.bound_m[i], params.max_bound_m + 1e-15);
    EXPECT_GT(result.bound_m[i], 0.003);  // more than an observed vertex
    if (v.x() > 0.049) back = std::max(back, result.bound_m[i]);
    if (v.x() < 0.02) seam = std::min(seam, result.bound_m[i]);
  }
  // The back face is 5-10 cm from the data: 3 mm + 0.2 x that, capped at 10 mm.
  EXPECT_NEAR(back, params.max_bound_m, 1e-12);
  EXPECT_LT(seam, 0.006);
  params.filled_growth = 0;
  const auto flat = surfaceErrorBounds(box.mesh, box.observed, box.sensor, params);
  EXPECT_NEAR(flat.filled_median_m, flat.observed_median_m, 0.0003);
}

TEST(SurfaceError, ClearanceIsTheLargestBoundOfTheNearestSurface) {
  const SeenBox box;
  const auto result = surfaceErrorBounds(box.mesh, box.observed, box.sensor);
  const SurfaceClearance clearance(box.mesh, result.bound_m);
  // Just outside the observed face: its own bound; outside the back face: the cap.
  EXPECT_NEAR(clearance.at({-0.06, 0, 0}), 0.003, 0.0003);
  EXPECT_NEAR(clearance.at({0.06, 0, 0}), SurfaceErrorParams{}.max_bound_m, 1e-12);
  // From the centre every face is as near: the largest bound of the whole box.
  EXPECT_NEAR(clearance.at({0, 0, 0}), SurfaceErrorParams{}.max_bound_m, 1e-12);
}

TEST(SurfaceError, BadInputIsReported) {
  const SeenBox box;
  std::vector<std::uint8_t> short_flags(3, 1);
  EXPECT_EQ(surfaceErrorBounds(box.mesh, short_flags, box.sensor).status.code,
            StatusCode::kInvalidInput);
  const std::vector<std::uint8_t> none(box.mesh.vertices.size(), 0);
  const auto unseen = surfaceErrorBounds(box.mesh, none, box.sensor);
  EXPECT_EQ(unseen.status.code, StatusCode::kNoResult);
  EXPECT_EQ(unseen.bound_m, std::vector<double>(box.mesh.vertices.size(), 0.01));
  SurfaceErrorParams bad;
  bad.max_bound_m = 0;
  EXPECT_THROW(surfaceErrorBounds(box.mesh, box.observed, box.sensor, bad), InvalidArgument);
  EXPECT_THROW(SurfaceClearance(box.mesh, {0.1}), InvalidArgument);
}

}  // namespace
}  // namespace skelgrasp::reconstruction
