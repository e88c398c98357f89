// Invariants of the skeleton stage over the real meshes in ../shared/data/objects: YCB google_16k,
// the paper's own Poisson meshes, and a sample of KIT models.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/mesh_query.h"
#include "skelgrasp/skeleton/extraction.h"
#include "test_support.h"

namespace skelgrasp::skeleton {
namespace {

std::vector<std::string> realMeshes() {
  std::vector<std::string> all = test::sharedFiles("objects/ycb", {".ply"});
  const auto simox = test::sharedFiles("objects/ycb_poisson_simox", {".stl"});
  all.insert(all.end(), simox.begin(), simox.end());
  const auto kit = test::sharedFiles("objects/kit", {".obj"});
  for (std::size_t i = 0; i < kit.size(); i += 6) all.push_back(kit[i]);  // every 6th KIT model
  if (all.empty()) all.push_back("");  // one placeholder case that skips
  return all;
}

bool isElongated(const std::string& path) {
  for (const char* name : {"banana", "spatula", "knife", "screwdriver", "hammer", "fork"}) {
    if (path.find(name) != std::string::npos) return true;
  }
  return false;
}

class RealMeshSkeleton : public ::testing::TestWithParam<std::string> {};

TEST_P(RealMeshSkeleton, SatisfiesTheStageInvariants) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  const std::string path = GetParam();
  const TriangleMesh input = loadMesh(path);
  const auto r = extractSkeleton(input);
  ASSERT_TRUE(r.status.ok()) << r.status.message;
  const auto& s = r.skeleton;

  // Regularised mesh: closed, one part, outward.
  EXPECT_TRUE(r.regularisation.output.closed);
  EXPECT_EQ(r.regularisation.output.components, 1u);
  EXPECT_GT(r.regularisation.output.signed_volume, 0);

  // Every input vertex belongs to exactly one skeleton vertex: sum |P_i| = |O|.
  std::vector<int> owners(input.numVertices(), 0);
  std::size_t total = 0;
  for (const auto& v : s.vertices) {
    total += v.surface_points.size();
    for (int p : v.surface_points) ++owners[p];
  }
  EXPECT_EQ(total, input.numVertices());
  EXPECT_EQ(std::count(owners.begin(), owners.end(), 1), static_cast<long>(input.numVertices()));

  // The skeleton is one connected graph.
  EXPECT_EQ(s.components(), 1);

  // Skeleton vertices lie inside the regularised mesh, up to 2 mm. Two kinds of objects are known
  // to put part of their curve skeleton outside, less than half the object's thinnest extent from
  // the surface (the vertex is in a cavity or a bend, not off the object):
  // hollow objects, whose axis runs through the cavity (cups, bowls, mugs, the skillet lid,
  // Duplo bricks with an open underside, toy-airplane parts with hex sockets), and thin bent parts
  // where contraction smooths across the bend (clamps, spatula, wrench, chain, hammer neck).
  // The YCB skillet lid is a scan of the rim and handle only (its glass is missing), so its
  // skeleton crosses the open ring: it is only held to its bounding box.
  const bool hollow_or_bent = std::regex_search(
      path, std::regex("cup|bowl|mug|duplo|airplane|clamp|spatula|wrench|chain|hammer"));
  const bool rim_only = path.find("skillet_lid") != std::string::npos;
  const geometry::MeshQuery query(r.regularised_mesh);
  const AxisAlignedBox box = r.regularised_mesh.bounds();
  const double thinnest = box.extent().minCoeff();
  const double tolerance = rim_only ? box.diagonal() : hollow_or_bent ? 0.5 * thinnest : 0.002;
  for (const auto& v : s.vertices) {
    EXPECT_TRUE((v.position.array() >= box.min.array() - 1e-6).all() &&
                (v.position.array() <= box.max.array() + 1e-6).all());
  }
  for (std::size_t i = 0; i < s.vertices.size(); ++i) {
    const auto& p = s.vertices[i].position;
    if (!query.contains(p)) {
      EXPECT_LT(query.distance(p), tolerance) << "skeleton vertex " << i << " outside";
    }
  }

  // Every vertex type is consistent with its degree, and segments cover all non-branch vertices.
  for (const auto& v : s.vertices) {
    if (v.type == VertexType::kBranch) {
      EXPECT_GT(v.degree(), 2);
    } else {
      EXPECT_GE(v.segment, 0);
    }
  }

  // A loop may stand for an end: the spatula's hanging hole, a real handle of its mesh (genus 1),
  // which the skeleton of the unwrapped mesh keeps.
  if (isElongated(path) && s.cycleRank() == 0) {
    EXPECT_GE(s.countType(VertexType::kEndpoint), 2u) << "elongated object with < 2 endpoints";
  }
}

std::string caseName(const ::testing::TestParamInfo<std::string>& info) {
  if (info.param.empty()) return "no_shared_data";
  std::string name = std::filesystem::path(info.param).parent_path().filename().string() + "_" +
                     std::filesystem::path(info.param).stem().string();
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}

INSTANTIATE_TEST_SUITE_P(Objects, RealMeshSkeleton, ::testing::ValuesIn(realMeshes()), caseName);

// The stage's default regularisation: a clean closed scan is contracted as it is, simplified to
// the contraction's budget; a scan with spurious handles (self-intersecting) is wrapped as before.
TEST(RealMeshSkeletonDefault, TakesCleanScansAsTheyAreAndWrapsTheOthers) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  const std::string root = test::sharedDataDir() + "/objects/ycb/";
  const auto lemon = extractSkeleton(loadMesh(root + "014_lemon.ply"));
  ASSERT_TRUE(lemon.status.ok()) << lemon.status.message;
  EXPECT_EQ(lemon.regularisation.method, "auto/as_is");
  EXPECT_GT(lemon.regularisation.decimated_from, kDefaultContractionVertices);
  EXPECT_LE(lemon.regularised_mesh.numVertices(), kDefaultContractionVertices + 1);
  EXPECT_EQ(lemon.skeleton.countType(VertexType::kEndpoint), 2u);
  EXPECT_EQ(lemon.skeleton.cycleRank(), 0);
  const auto can = extractSkeleton(loadMesh(root + "002_master_chef_can.ply"));
  ASSERT_TRUE(can.status.ok()) << can.status.message;
  EXPECT_EQ(can.regularisation.method, "auto/alpha_wrap");
  EXPECT_EQ(can.regularisation.input.genus.value(), 94);
  EXPECT_EQ(can.skeleton.cycleRank(), 0);  // none of the 94 spurious handles
}

}  // namespace
}  // namespace skelgrasp::skeleton
