#include "skelgrasp/reconstruction/meshing.h"

#include <gtest/gtest.h>

#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/mesh_topology.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/geometry/surface_distance.h"
#include "test_support.h"

namespace skelgrasp::reconstruction {
namespace {

TEST(Meshing, ObservedFlagsRoundTripThroughThePly) {
  const TriangleMesh sphere = geometry::shapes::makeSphere(0.05, 32, 16);
  std::vector<Eigen::Vector3d> seen;
  for (const auto& v : sphere.vertices) {
    if (v.z() > 0.02) seen.push_back(v);
  }
  const auto flags = observedFlags(sphere, seen, 0.001);
  for (std::size_t i = 0; i < flags.size(); ++i) {
    EXPECT_EQ(flags[i], sphere.vertices[i].z() > 0.02 ? 1 : 0);
  }
  const std::string path = test::tempDir("observed") + "/mesh.ply";
  saveObservedMesh(path, sphere, flags);
  EXPECT_EQ(loadObservedFlags(path), flags);
  EXPECT_EQ(loadMesh(path).numVertices(), sphere.numVertices());
  EXPECT_THROW(saveObservedMesh(path, sphere, {1, 0}), InvalidArgument);
}

TEST(Meshing, RejectsCloudsWithoutNormalsAndBadParameters) {
  PointCloud cloud;
  cloud.points.assign(20, Eigen::Vector3d::Zero());
  EXPECT_THROW(meshObject(cloud, std::nullopt), InvalidArgument);
  cloud.normals.assign(20, Eigen::Vector3d::UnitZ());
  MeshingParams p;
  p.poisson.depth = 1;
  EXPECT_THROW(meshObject(cloud, std::nullopt, p), InvalidArgument);
  PointCloud few;
  few.points.assign(3, Eigen::Vector3d::Zero());
  few.normals.assign(3, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(meshObject(few, std::nullopt).status.code, StatusCode::kInvalidInput);
  EXPECT_EQ(parseTrimMode("density"), TrimMode::kDensity);
  EXPECT_THROW(parseTrimMode("cut"), InvalidArgument);
}

TEST(SurfaceDistance, ChamferOfConcentricSpheresIsTheGap) {
  const TriangleMesh a = geometry::shapes::makeSphere(0.05, 96, 48);
  TriangleMesh b = a;
  b.scale(1.1);
  const geometry::ChamferDistance same = geometry::chamferDistance(a, a, 2000);
  EXPECT_LT(same.symmetric_m, 1e-9);
  const geometry::ChamferDistance gap = geometry::chamferDistance(a, b, 2000);
  EXPECT_NEAR(gap.symmetric_m, 0.005, 2e-4);
  EXPECT_NEAR(gap.max_m, 0.005, 3e-4);
  const auto samples = geometry::sampleSurface(a, 500, 9);
  EXPECT_EQ(samples, geometry::sampleSurface(a, 500, 9));  // seeded
  for (const auto& p : samples) EXPECT_NEAR(p.norm(), 0.05, 2e-4);
}

}  // namespace
}  // namespace skelgrasp::reconstruction
