#include "skelgrasp/geometry/mesh_topology.h"

#include <gtest/gtest.h>

#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "test_support.h"

namespace skelgrasp::geometry {
namespace {

TEST(MeshTopology, ClosedPrimitivesHaveTheirGenus) {
  const auto sphere = analyzeTopology(geometry::shapes::makeSphere(0.1));
  EXPECT_TRUE(sphere.closed);
  EXPECT_EQ(sphere.components, 1u);
  EXPECT_EQ(sphere.genus.value(), 0);
  EXPECT_EQ(sphere.inconsistently_oriented_edges, 0u);
  EXPECT_GT(sphere.signed_volume, 0);

  const auto torus = analyzeTopology(geometry::shapes::makeTorus(0.1, 0.02));
  EXPECT_TRUE(torus.closed);
  EXPECT_EQ(torus.genus.value(), 1);
  EXPECT_EQ(torus.euler_characteristic, 0);
}

TEST(MeshTopology, OpenMeshHasBoundaryAndNoGenus) {
  TriangleMesh mesh = geometry::shapes::makeBox({1, 1, 1});
  mesh.faces.pop_back();
  const auto t = analyzeTopology(mesh);
  EXPECT_FALSE(t.closed);
  EXPECT_EQ(t.boundary_edges, 3u);
  EXPECT_FALSE(t.genus.has_value());
}

TEST(MeshTopology, CountsPartsAndNonManifoldEdges) {
  TriangleMesh mesh = geometry::shapes::makeBox({1, 1, 1});
  TriangleMesh other = geometry::shapes::makeBox({1, 1, 1});
  other.transform(Eigen::Isometry3d(Eigen::Translation3d(5, 0, 0)));
  mesh.append(other);
  auto t = analyzeTopology(mesh);
  EXPECT_EQ(t.components, 2u);
  EXPECT_EQ(t.genus.value(), 0);
  // A third triangle on an existing edge makes it non-manifold.
  mesh.vertices.push_back({0, 0, 3});
  mesh.faces.emplace_back(mesh.faces[0][0], mesh.faces[0][1],
                          static_cast<int>(mesh.vertices.size()) - 1);
  t = analyzeTopology(mesh);
  EXPECT_EQ(t.non_manifold_edges, 1u);
  EXPECT_FALSE(t.closed);
}

TEST(MeshTopology, FlippedMeshHasNegativeVolume) {
  TriangleMesh mesh = geometry::shapes::makeSphere(0.05);
  mesh.flipOrientation();
  EXPECT_LT(analyzeTopology(mesh).signed_volume, 0);
}

TEST(MeshTopology, MatchesDocumentedGenusOfRealMeshes) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  const std::string root = test::sharedDataDir() + "/objects/ycb/";
  // Values from the data's SOURCES.md.
  EXPECT_EQ(analyzeTopology(loadMesh(root + "002_master_chef_can.ply")).genus.value(), 94);
  EXPECT_EQ(analyzeTopology(loadMesh(root + "025_mug.ply")).genus.value(), 3);
  const auto lid = analyzeTopology(loadMesh(root + "028_skillet_lid.ply"));
  EXPECT_EQ(lid.components, 2u);
}

}  // namespace
}  // namespace skelgrasp::geometry
