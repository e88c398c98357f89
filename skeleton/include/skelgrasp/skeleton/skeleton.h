#pragma once
// The object skeleton S = (V, E) of the paper (Sec. III): vertices with positions and the input
// surface points that collapsed into them, classified as branch / endpoint / connecting, and
// grouped into segments.
#include <array>
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace skelgrasp::skeleton {

enum class VertexType {
  kBranch,      // degree > 2
  kEndpoint,    // degree 1 (and, by convention, an isolated vertex: degree 0)
  kConnecting,  // degree 2
};
const char* toString(VertexType type);

enum class SegmentEnd {
  kEndpoint,  // the segment ends in an endpoint vertex (included in the segment)
  kBranch,    // the segment ends next to a branch vertex (not included)
  kLoop,      // the segment is a cycle without any branch or endpoint
};
const char* toString(SegmentEnd end);

struct SkeletonVertex {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  VertexType type = VertexType::kConnecting;
  // Connecting and endpoint vertices: the segment they belong to. Branch vertices: -1.
  int segment = -1;
  std::vector<int> neighbours;
  // Indices of input-mesh vertices associated with this skeleton vertex (P_i). Every input vertex
  // is in exactly one list.
  std::vector<int> surface_points;
  // Curvature of the segment polyline at this vertex in 1/m; NaN for branch vertices and where a
  // segment has fewer than three points to differentiate.
  double curvature = std::numeric_limits<double>::quiet_NaN();

  int degree() const { return static_cast<int>(neighbours.size()); }
};

// A maximal chain of non-branch vertices (paper Eq. 4), possibly closed.
struct Segment {
  int id = -1;
  // Ordered along the chain. Endpoint vertices are part of the segment; bounding branch vertices
  // are not (they are in `end_vertices`). For a loop, vertices.back() connects to vertices.front().
  std::vector<int> vertices;
  std::array<SegmentEnd, 2> ends{SegmentEnd::kEndpoint, SegmentEnd::kEndpoint};
  // The vertex at each end: the endpoint vertex itself, or the branch vertex the chain attaches
  // to (both ends may name the same branch vertex: a handle on one branch); -1 for loops.
  std::array<int, 2> end_vertices{-1, -1};
  // Polyline length in metres, including the edges to bounding branch vertices and, for a loop,
  // the closing edge.
  double length = 0;

  bool isLoop() const { return ends[0] == SegmentEnd::kLoop; }
};

struct Skeleton {
  std::vector<SkeletonVertex> vertices;
  std::vector<std::array<int, 2>> edges;
  std::vector<Segment> segments;
  std::size_t num_surface_points = 0;  // |O|, the number of input vertices

  std::size_t countType(VertexType type) const;
  // Connected components of the graph.
  int components() const;
  // Number of independent cycles: |E| - |V| + components (0 for a tree, 1 for a torus or mug).
  int cycleRank() const;
};

struct GraphAnalysisParams {
  // Curvature is differentiated over neighbours at least this far along the polyline (metres),
  // which keeps sub-millimetre zig-zags of the contracted skeleton from dominating kappa.
  double curvature_stencil_m = 0.005;
};

// Classifies vertices, fills neighbours, builds segments and curvature from positions and edges.
// `point_to_vertex[i]` is the skeleton vertex of input point i (sets surface_points).
// Throws InvalidArgument on out-of-range indices, self-loops or duplicate edges.
Skeleton analyzeSkeletonGraph(const std::vector<Eigen::Vector3d>& positions,
                              const std::vector<std::array<int, 2>>& edges,
                              const std::vector<int>& point_to_vertex,
                              const GraphAnalysisParams& params = {});

// Curvature kappa = |s' x s''| / |s'|^3 at parameter t of the quadratic through three points with
// parameters t0 < t1 < t2 (arc length), by differentiating the Lagrange interpolant.
double polylineCurvature(const std::array<Eigen::Vector3d, 3>& points,
                         const std::array<double, 3>& params, double t);

}  // namespace skelgrasp::skeleton
