// The skeleton depends on the input only: the same mesh gives the same skeleton, bit for bit,
// within one process (the ordered arena keeps CGAL's address-ordered edge collapses stable) and
// whatever address space the arena starts with (a small first reservation forces retries).
#include <gtest/gtest.h>

#include <cmath>

#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/skeleton/extraction.h"
#include "test_support.h"

namespace skelgrasp::skeleton {
namespace {

// Small enough that every contraction below runs out of it at least once (they use ~1 KiB per
// vertex of the regularised mesh, thousands of vertices).
constexpr std::size_t kTinyArenaBytes = 64 * 1024;

// Equal, or both NaN (curvature is NaN where it is undefined).
bool sameNumber(double a, double b) {
  return a == b || (std::isnan(a) && std::isnan(b));
}

// The whole skeleton, bit for bit: every vertex field, the edges, every segment field, and the
// regularised mesh it was contracted from.
void expectIdentical(const SkeletonResult& a, const SkeletonResult& b, const std::string& what) {
  ASSERT_TRUE(a.status.ok()) << what << ": " << a.status.message;
  ASSERT_TRUE(b.status.ok()) << what << ": " << b.status.message;
  const Skeleton &sa = a.skeleton, &sb = b.skeleton;
  ASSERT_EQ(sa.vertices.size(), sb.vertices.size()) << what;
  for (std::size_t i = 0; i < sa.vertices.size(); ++i) {
    const auto &va = sa.vertices[i], &vb = sb.vertices[i];
    ASSERT_EQ(va.position, vb.position) << what << " vertex " << i;
    ASSERT_EQ(va.type, vb.type) << what << " vertex " << i;
    ASSERT_EQ(va.segment, vb.segment) << what << " vertex " << i;
    ASSERT_EQ(va.neighbours, vb.neighbours) << what << " vertex " << i;
    ASSERT_EQ(va.surface_points, vb.surface_points) << what << " vertex " << i;
    ASSERT_TRUE(sameNumber(va.curvature, vb.curvature))
        << what << " vertex " << i << ": " << va.curvature << " vs " << vb.curvature;
  }
  EXPECT_EQ(sa.edges, sb.edges) << what;
  EXPECT_EQ(sa.num_surface_points, sb.num_surface_points) << what;
  ASSERT_EQ(sa.segments.size(), sb.segments.size()) << what;
  for (std::size_t k = 0; k < sa.segments.size(); ++k) {
    const auto &ga = sa.segments[k], &gb = sb.segments[k];
    EXPECT_EQ(ga.id, gb.id) << what << " segment " << k;
    EXPECT_EQ(ga.vertices, gb.vertices) << what << " segment " << k;
    EXPECT_EQ(ga.ends, gb.ends) << what << " segment " << k;
    EXPECT_EQ(ga.end_vertices, gb.end_vertices) << what << " segment " << k;
    EXPECT_EQ(ga.length, gb.length) << what << " segment " << k;
  }
  EXPECT_EQ(a.regularised_mesh.vertices, b.regularised_mesh.vertices) << what;
  EXPECT_EQ(a.regularised_mesh.faces, b.regularised_mesh.faces) << what;
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
    expectDeterministic(geometry::shapes::makeNamedShape(shape), shape);
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
  EXPECT_THROW(extractSkeleton(geometry::shapes::makeNamedShape("capsule"), params),
               InvalidArgument);
}

}  // namespace
}  // namespace skelgrasp::skeleton
