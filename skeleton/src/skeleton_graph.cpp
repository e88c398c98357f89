#include <algorithm>
#include <cmath>
#include <set>

#include "skelgrasp/common/error.h"
#include "skelgrasp/skeleton/skeleton.h"

namespace skelgrasp::skeleton {

namespace {

// Below this speed (metres per unit of the curve parameter) the curve is stationary and its
// curvature undefined: reported as 0.
constexpr double kStationarySpeed = 1e-12;
}  // namespace

const char* toString(VertexType type) {
  switch (type) {
    case VertexType::kBranch:
      return "branch";
    case VertexType::kEndpoint:
      return "endpoint";
    case VertexType::kConnecting:
      return "connecting";
  }
  return "unknown";
}

const char* toString(SegmentEnd end) {
  switch (end) {
    case SegmentEnd::kEndpoint:
      return "endpoint";
    case SegmentEnd::kBranch:
      return "branch";
    case SegmentEnd::kLoop:
      return "loop";
  }
  return "unknown";
}

std::size_t Skeleton::countType(VertexType type) const {
  return static_cast<std::size_t>(std::count_if(vertices.begin(), vertices.end(),
                                                [type](const auto& v) { return v.type == type; }));
}

int Skeleton::components() const {
  std::vector<int> label(vertices.size(), -1);
  int count = 0;
  for (std::size_t start = 0; start < vertices.size(); ++start) {
    if (label[start] >= 0) continue;
    std::vector<int> stack{static_cast<int>(start)};
    label[start] = count;
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      for (int n : vertices[v].neighbours) {
        if (label[n] < 0) {
          label[n] = count;
          stack.push_back(n);
        }
      }
    }
    ++count;
  }
  return count;
}

int Skeleton::cycleRank() const {
  return static_cast<int>(edges.size()) - static_cast<int>(vertices.size()) + components();
}

double polylineCurvature(const std::array<Eigen::Vector3d, 3>& p, const std::array<double, 3>& s,
                         double t) {
  // Lagrange basis L_i(t) = prod_{j != i} (t - s_j) / (s_i - s_j); first and second derivatives.
  Eigen::Vector3d d1 = Eigen::Vector3d::Zero(), d2 = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const double denom = (s[i] - s[j]) * (s[i] - s[k]);
    d1 += p[i] * ((t - s[j]) + (t - s[k])) / denom;
    d2 += p[i] * 2.0 / denom;
  }
  const double speed = d1.norm();
  if (speed < kStationarySpeed) return 0.0;
  return d1.cross(d2).norm() / (speed * speed * speed);
}

namespace {

// Curvature along an ordered polyline; `closed` wraps around. Entries for which no stencil of
// three distinct points exists are NaN.
std::vector<double> curvatureAlong(const std::vector<Eigen::Vector3d>& pts, bool closed,
                                   double stencil) {
  const int n = static_cast<int>(pts.size());
  std::vector<double> kappa(n, std::numeric_limits<double>::quiet_NaN());
  if (n < 3) return kappa;
  // Cumulative arc length (for a loop, unrolled on demand through modular indices).
  std::vector<double> arc(n + 1, 0.0);
  for (int i = 1; i <= n; ++i) arc[i] = arc[i - 1] + (pts[i % n] - pts[i - 1]).norm();
  const double total = closed ? arc[n] : arc[n - 1];
  auto position = [&](int i) -> double {  // arc length of (possibly wrapped) index i
    if (!closed) return arc[i];
    const int wraps = (i >= 0) ? i / n : -((-i + n - 1) / n);
    return arc[((i % n) + n) % n] + wraps * total;
  };
  auto point = [&](int i) -> const Eigen::Vector3d& { return pts[((i % n) + n) % n]; };
  for (int i = 0; i < n; ++i) {
    int lo = i, hi = i;
    const double s0 = position(i);
    while ((closed || lo > 0) && s0 - position(lo) < stencil && i - lo < n / 2) --lo;
    while ((closed || hi < n - 1) && position(hi) - s0 < stencil && hi - i < n / 2) ++hi;
    // Three stencil points; at an open end both extra points lie on the inner side.
    std::array<int, 3> idx;
    if (lo < i && hi > i) {
      idx = {lo, i, hi};
    } else if (lo == i && hi > i) {
      if (hi == i + 1 && hi + 1 < n) ++hi;
      if (hi == i + 1) continue;
      int mid = i + 1;
      while (mid + 1 < hi && position(mid) - s0 < 0.5 * (position(hi) - s0)) ++mid;
      idx = {i, mid, hi};
    } else if (hi == i && lo < i) {
      if (lo == i - 1 && lo > 0) --lo;
      if (lo == i - 1) continue;
      int mid = i - 1;
      while (mid - 1 > lo && s0 - position(mid) < 0.5 * (s0 - position(lo))) --mid;
      idx = {lo, mid, i};
    } else {
      continue;
    }
    const std::array<double, 3> s{position(idx[0]), position(idx[1]), position(idx[2])};
    if (!(s[0] < s[1] && s[1] < s[2])) continue;
    kappa[i] = polylineCurvature({point(idx[0]), point(idx[1]), point(idx[2])}, s, s0);
  }
  return kappa;
}

}  // namespace

Skeleton analyzeSkeletonGraph(const std::vector<Eigen::Vector3d>& positions,
                              const std::vector<std::array<int, 2>>& edges,
                              const std::vector<int>& point_to_vertex,
                              const GraphAnalysisParams& params) {
  const int n = static_cast<int>(positions.size());
  Skeleton skel;
  skel.vertices.resize(n);
  skel.num_surface_points = point_to_vertex.size();
  std::set<std::pair<int, int>> seen;
  for (const auto& e : edges) {
    if (e[0] < 0 || e[1] < 0 || e[0] >= n || e[1] >= n) {
      throw InvalidArgument("analyzeSkeletonGraph: edge index out of range");
    }
    if (e[0] == e[1]) throw InvalidArgument("analyzeSkeletonGraph: self-loop edge");
    if (!seen.insert({std::min(e[0], e[1]), std::max(e[0], e[1])}).second) {
      throw InvalidArgument("analyzeSkeletonGraph: duplicate edge");
    }
    skel.vertices[e[0]].neighbours.push_back(e[1]);
    skel.vertices[e[1]].neighbours.push_back(e[0]);
  }
  skel.edges = edges;
  for (int v = 0; v < n; ++v) {
    auto& vert = skel.vertices[v];
    vert.position = positions[v];
    const int d = vert.degree();
    vert.type = d > 2    ? VertexType::kBranch
                : d == 2 ? VertexType::kConnecting
                         : VertexType::kEndpoint;
  }
  for (std::size_t i = 0; i < point_to_vertex.size(); ++i) {
    const int v = point_to_vertex[i];
    if (v < 0 || v >= n) throw InvalidArgument("analyzeSkeletonGraph: point mapped out of range");
    skel.vertices[v].surface_points.push_back(static_cast<int>(i));
  }

  auto isBranch = [&](int v) { return skel.vertices[v].type == VertexType::kBranch; };
  auto distance = [&](int a, int b) { return (positions[a] - positions[b]).norm(); };

  // Walks from `from` into `next` through connecting vertices; appends visited non-branch vertices
  // to `chain` and returns the vertex that stopped the walk (branch or endpoint; `from` side
  // excluded). For a pure cycle returns the start vertex again.
  auto walk = [&](int from, int next, std::vector<int>& chain) -> int {
    int prev = from, cur = next;
    while (true) {
      if (isBranch(cur)) return cur;
      if (!chain.empty() && cur == chain.front()) return cur;  // closed the loop
      chain.push_back(cur);
      const auto& nb = skel.vertices[cur].neighbours;
      if (nb.size() < 2) return cur;  // endpoint
      const int following = nb[0] == prev ? nb[1] : nb[0];
      prev = cur;
      cur = following;
    }
  };

  auto addSegment = [&](Segment seg) {
    seg.id = static_cast<int>(skel.segments.size());
    for (int v : seg.vertices) skel.vertices[v].segment = seg.id;
    double len = 0;
    for (std::size_t i = 1; i < seg.vertices.size(); ++i) {
      len += distance(seg.vertices[i - 1], seg.vertices[i]);
    }
    if (seg.isLoop() && seg.vertices.size() > 1) {
      len += distance(seg.vertices.back(), seg.vertices.front());
    }
    if (seg.ends[0] == SegmentEnd::kBranch)
      len += distance(seg.end_vertices[0], seg.vertices.front());
    if (seg.ends[1] == SegmentEnd::kBranch)
      len += distance(seg.vertices.back(), seg.end_vertices[1]);
    seg.length = len;
    skel.segments.push_back(std::move(seg));
  };

  // 1. Chains that start at an endpoint (isolated vertices form a one-vertex segment).
  for (int v = 0; v < n; ++v) {
    if (skel.vertices[v].type != VertexType::kEndpoint || skel.vertices[v].segment >= 0) continue;
    Segment seg;
    seg.vertices.push_back(v);
    seg.end_vertices[0] = v;
    if (skel.vertices[v].degree() == 0) {
      seg.end_vertices[1] = v;
      addSegment(std::move(seg));
      continue;
    }
    std::vector<int> rest;
    const int stop = walk(v, skel.vertices[v].neighbours[0], rest);
    seg.vertices.insert(seg.vertices.end(), rest.begin(), rest.end());
    seg.end_vertices[1] = stop;
    seg.ends[1] = isBranch(stop) ? SegmentEnd::kBranch : SegmentEnd::kEndpoint;
    addSegment(std::move(seg));
  }
  // 2. Chains of connecting vertices between branch vertices.
  for (int b = 0; b < n; ++b) {
    if (!isBranch(b)) continue;
    for (int start : skel.vertices[b].neighbours) {
      if (isBranch(start) || skel.vertices[start].segment >= 0) continue;
      Segment seg;
      const int stop = walk(b, start, seg.vertices);
      seg.ends = {SegmentEnd::kBranch, SegmentEnd::kBranch};
      seg.end_vertices = {b, stop};
      SKELGRASP_DEMAND(isBranch(stop));
      addSegment(std::move(seg));
    }
  }
  // 3. What is left are cycles of connecting vertices only.
  for (int v = 0; v < n; ++v) {
    if (skel.vertices[v].segment >= 0 || isBranch(v)) continue;
    Segment seg;
    seg.vertices.push_back(v);
    walk(v, skel.vertices[v].neighbours[0], seg.vertices);
    seg.ends = {SegmentEnd::kLoop, SegmentEnd::kLoop};
    seg.end_vertices = {-1, -1};
    addSegment(std::move(seg));
  }

  // Curvature per segment; the stencil continues into bounding branch vertices.
  for (const auto& seg : skel.segments) {
    std::vector<int> chain;
    if (seg.ends[0] == SegmentEnd::kBranch) chain.push_back(seg.end_vertices[0]);
    chain.insert(chain.end(), seg.vertices.begin(), seg.vertices.end());
    if (seg.ends[1] == SegmentEnd::kBranch) chain.push_back(seg.end_vertices[1]);
    std::vector<Eigen::Vector3d> pts;
    for (int v : chain) pts.push_back(positions[v]);
    const auto kappa = curvatureAlong(pts, seg.isLoop(), params.curvature_stencil_m);
    for (std::size_t i = 0; i < chain.size(); ++i) {
      if (!isBranch(chain[i])) skel.vertices[chain[i]].curvature = kappa[i];
    }
  }
  return skel;
}

}  // namespace skelgrasp::skeleton
