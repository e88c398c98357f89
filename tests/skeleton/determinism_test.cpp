// The skeleton depends on the input only: the same mesh gives the same skeleton, bit for bit,
// within one process (the ordered arena keeps CGAL's address-ordered edge collapses stable) and
// whatever address space the arena starts with (a small first reservation forces retries).
#include <gtest/gtest.h>

#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/common/primitives.h"
#include "skelgrasp/skeleton/extraction.h"
#include "test_support.h"

namespace skelgrasp::skeleton {
namespace {

// Small enough that every contraction below runs out of it at least once (they use ~1 KiB per
// vertex of the regularised mesh, thousands of vertices).
constexpr std::size_t kTinyArenaBytes = 64 * 1024;

void expectIdentical(const SkeletonResult& a, const SkeletonResult& b, const std::string& what) {
  ASSERT_TRUE(a.status.ok()) << what << ": " << a.status.message;
  ASSERT_TRUE(b.status.ok()) << what << ": " << b.status.message;
  ASSERT_EQ(a.skeleton.vertices.size(), b.skeleton.vertices.size()) << what;
  for (std::size_t i = 0; i < a.skeleton.vertices.size(); ++i) {
    ASSERT_EQ(a.skeleton.vertices[i].position, b.skeleton.vertices[i].position) << what << " " << i;
    ASSERT_EQ(a.skeleton.vertices[i].surface_points, b.skeleton.vertices[i].surface_points)
        << what << " " << i;
  }
  EXPECT_EQ(a.skeleton.edges, b.skeleton.edges) << what;
  EXPECT_EQ(a.skeleton.segments.size(), b.skeleton.segments.size()) << what;
}

void expectDeterministic(const TriangleMesh& mesh, const std::string& what) {
  const SkeletonResult first = extractSkeleton(mesh);
  const SkeletonResult second = extractSkeleton(mesh);
  expectIdentical(first, second, what + " (twice)");
  SkeletonParams tiny;
  tiny.contraction.arena_reserve_bytes = kTinyArenaBytes;
  expectIdentical(first, extractSkeleton(mesh, tiny), what + " (arena retries)");
}

TEST(SkeletonDeterminism, GeneratedShapesGiveTheSameSkeletonEveryTime) {
  for (const char* shape : {"capsule", "y_shape", "mug", "hammer"}) {
    expectDeterministic(primitives::makeNamedShape(shape), shape);
  }
}

TEST(SkeletonDeterminism, RealMeshGivesTheSameSkeletonEveryTime) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  const auto files = test::sharedFiles("objects/ycb", {".ply"});
  ASSERT_FALSE(files.empty());
  expectDeterministic(loadMesh(files.front()), files.front());
}

TEST(SkeletonDeterminism, ZeroArenaIsACallerMistake) {
  SkeletonParams params;
  params.contraction.arena_reserve_bytes = 0;
  EXPECT_THROW(extractSkeleton(primitives::makeNamedShape("capsule"), params), InvalidArgument);
}

}  // namespace
}  // namespace skelgrasp::skeleton
