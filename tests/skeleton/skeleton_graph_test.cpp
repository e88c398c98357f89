#include <gtest/gtest.h>

#include <cmath>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/skeleton/skeleton.h"

namespace skelgrasp::skeleton {
namespace {

std::vector<Eigen::Vector3d> line(int n, double step = 0.01) {
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < n; ++i) pts.emplace_back(i * step, 0, 0);
  return pts;
}

std::vector<std::array<int, 2>> chainEdges(int first, int last) {
  std::vector<std::array<int, 2>> edges;
  for (int i = first; i < last; ++i) edges.push_back({i, i + 1});
  return edges;
}

TEST(SkeletonGraph, PathIsOneSegmentBetweenTwoEndpoints) {
  const auto skel = analyzeSkeletonGraph(line(6), chainEdges(0, 5), {0, 1, 2, 5, 5});
  EXPECT_EQ(skel.countType(VertexType::kEndpoint), 2u);
  EXPECT_EQ(skel.countType(VertexType::kConnecting), 4u);
  ASSERT_EQ(skel.segments.size(), 1u);
  const auto& seg = skel.segments[0];
  EXPECT_EQ(seg.vertices, (std::vector<int>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(seg.ends[0], SegmentEnd::kEndpoint);
  EXPECT_EQ(seg.ends[1], SegmentEnd::kEndpoint);
  EXPECT_NEAR(seg.length, 0.05, 1e-12);
  EXPECT_EQ(skel.cycleRank(), 0);
  EXPECT_EQ(skel.vertices[5].surface_points, (std::vector<int>{3, 4}));
  for (const auto& v : skel.vertices) EXPECT_NEAR(v.curvature, 0.0, 1e-9);
}

TEST(SkeletonGraph, StarHasABranchAndThreeSegments) {
  // Centre 0 with arms 1-2, 3-4, 5-6.
  std::vector<Eigen::Vector3d> pts = {{0, 0, 0}, {1, 0, 0},  {2, 0, 0}, {0, 1, 0},
                                      {0, 2, 0}, {-1, 0, 0}, {-2, 0, 0}};
  const auto skel = analyzeSkeletonGraph(pts, {{0, 1}, {1, 2}, {0, 3}, {3, 4}, {0, 5}, {5, 6}}, {});
  EXPECT_EQ(skel.vertices[0].type, VertexType::kBranch);
  EXPECT_EQ(skel.vertices[0].segment, -1);
  EXPECT_TRUE(std::isnan(skel.vertices[0].curvature));
  ASSERT_EQ(skel.segments.size(), 3u);
  for (const auto& seg : skel.segments) {
    EXPECT_EQ(seg.ends[0], SegmentEnd::kEndpoint);
    EXPECT_EQ(seg.ends[1], SegmentEnd::kBranch);
    EXPECT_EQ(seg.end_vertices[1], 0);
    EXPECT_EQ(seg.vertices.size(), 2u);
    EXPECT_NEAR(seg.length, 2.0, 1e-12);  // includes the edge to the branch vertex
  }
}

TEST(SkeletonGraph, CycleIsALoopWithCurvatureOneOverRadius) {
  const int n = 64;
  const double radius = 0.05;
  std::vector<Eigen::Vector3d> pts;
  std::vector<std::array<int, 2>> edges;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * kPi * i / n;
    pts.emplace_back(radius * std::cos(a), radius * std::sin(a), 0);
    edges.push_back({i, (i + 1) % n});
  }
  GraphAnalysisParams params;
  params.curvature_stencil_m = 0.01;
  const auto skel = analyzeSkeletonGraph(pts, edges, {}, params);
  EXPECT_EQ(skel.countType(VertexType::kEndpoint), 0u);
  EXPECT_EQ(skel.countType(VertexType::kBranch), 0u);
  ASSERT_EQ(skel.segments.size(), 1u);
  EXPECT_TRUE(skel.segments[0].isLoop());
  EXPECT_EQ(skel.segments[0].vertices.size(), static_cast<std::size_t>(n));
  EXPECT_NEAR(skel.segments[0].length, 2 * n * radius * std::sin(kPi / n), 1e-12);
  EXPECT_EQ(skel.cycleRank(), 1);
  for (const auto& v : skel.vertices) EXPECT_NEAR(v.curvature, 1 / radius, 0.05 / radius);
}

TEST(SkeletonGraph, HandleOnOneBranchVertexIsASegmentFromAndToThatVertex) {
  // Stem 0-1-2(branch); loop 2-3-4-5-2; tail 2-6.
  std::vector<Eigen::Vector3d> pts = {{0, 0, 0}, {1, 0, 0},  {2, 0, 0}, {3, 1, 0},
                                      {4, 0, 0}, {3, -1, 0}, {2, 1, 0}};
  const auto skel =
      analyzeSkeletonGraph(pts, {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {4, 5}, {5, 2}, {2, 6}}, {});
  EXPECT_EQ(skel.cycleRank(), 1);
  int handles = 0;
  for (const auto& seg : skel.segments) {
    if (seg.ends[0] == SegmentEnd::kBranch && seg.ends[1] == SegmentEnd::kBranch) {
      ++handles;
      EXPECT_EQ(seg.end_vertices[0], 2);
      EXPECT_EQ(seg.end_vertices[1], 2);
      EXPECT_EQ(seg.vertices.size(), 3u);
    }
  }
  EXPECT_EQ(handles, 1);
  EXPECT_EQ(skel.segments.size(), 3u);
}

TEST(SkeletonGraph, DegenerateSkeletonsHaveADefinedResult) {
  // A ball collapsing to one vertex: one endpoint forming a one-vertex segment.
  auto one = analyzeSkeletonGraph({{0, 0, 0}}, {}, {0, 0, 0});
  ASSERT_EQ(one.segments.size(), 1u);
  EXPECT_EQ(one.vertices[0].type, VertexType::kEndpoint);
  EXPECT_EQ(one.segments[0].vertices, (std::vector<int>{0}));
  EXPECT_EQ(one.vertices[0].surface_points.size(), 3u);
  // Two vertices: two endpoints, one segment.
  auto two = analyzeSkeletonGraph({{0, 0, 0}, {0.01, 0, 0}}, {{0, 1}}, {});
  ASSERT_EQ(two.segments.size(), 1u);
  EXPECT_EQ(two.countType(VertexType::kEndpoint), 2u);
  EXPECT_NEAR(two.segments[0].length, 0.01, 1e-12);
}

TEST(SkeletonGraph, BranchToBranchEdgesBelongToNoSegment) {
  // Two adjacent branch vertices 0-1, each with two arms: a branching region, four segments.
  std::vector<Eigen::Vector3d> pts = {{0, 0, 0},   {1, 0, 0}, {-1, 1, 0},
                                      {-1, -1, 0}, {2, 1, 0}, {2, -1, 0}};
  const auto skel = analyzeSkeletonGraph(pts, {{0, 1}, {0, 2}, {0, 3}, {1, 4}, {1, 5}}, {});
  EXPECT_EQ(skel.countType(VertexType::kBranch), 2u);
  EXPECT_EQ(skel.segments.size(), 4u);
}

TEST(SkeletonGraph, RejectsMalformedGraphs) {
  EXPECT_THROW(analyzeSkeletonGraph(line(2), {{0, 2}}, {}), InvalidArgument);
  EXPECT_THROW(analyzeSkeletonGraph(line(2), {{0, 0}}, {}), InvalidArgument);
  EXPECT_THROW(analyzeSkeletonGraph(line(2), {{0, 1}, {1, 0}}, {}), InvalidArgument);
  EXPECT_THROW(analyzeSkeletonGraph(line(2), {{0, 1}}, {5}), InvalidArgument);
}

TEST(PolylineCurvature, MatchesCircleForUnevenSpacing) {
  const double r = 0.1;
  const std::array<double, 3> angles = {0.0, 0.05, 0.17};
  std::array<Eigen::Vector3d, 3> pts;
  std::array<double, 3> s;
  for (int i = 0; i < 3; ++i) {
    pts[i] = {r * std::cos(angles[i]), r * std::sin(angles[i]), 0};
    s[i] = r * angles[i];
  }
  EXPECT_NEAR(polylineCurvature(pts, s, s[1]), 1 / r, 0.05 / r);
  EXPECT_NEAR(polylineCurvature(pts, s, s[0]), 1 / r, 0.1 / r);
}

}  // namespace
}  // namespace skelgrasp::skeleton
