#include "triangle_distance.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace skelgrasp::grasping::internal {

TrianglePoint closestOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {a, TriangleFeature::kVertex, 0};
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {b, TriangleFeature::kVertex, 1};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return {a + v * ab, TriangleFeature::kEdge, 0};
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {c, TriangleFeature::kVertex, 2};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return {a + w * ac, TriangleFeature::kEdge, 2};  // edge c-a
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + w * (c - b), TriangleFeature::kEdge, 1};
  }
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) return {a, TriangleFeature::kVertex, 0};  // degenerate triangle
  const double v = vb / denom, w = vc / denom;
  return {a + ab * v + ac * w, TriangleFeature::kFace, 0};
}

SegmentPoints closestSegmentPoints(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                   const Eigen::Vector3d& q0, const Eigen::Vector3d& q1) {
  // Ericson 5.1.9.
  constexpr double kTiny = 1e-20;
  const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  if (a <= kTiny && e <= kTiny) return {p0, q0};
  if (a <= kTiny) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= kTiny) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > kTiny * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return {p0 + d1 * s, q0 + d2 * t};
}

double segmentSegmentDistanceSquared(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                     const Eigen::Vector3d& q0, const Eigen::Vector3d& q1) {
  const SegmentPoints closest = closestSegmentPoints(p0, p1, q0, q1);
  return (closest.on_p - closest.on_q).squaredNorm();
}

namespace {

// Corner i of the box [-half, half]: bit k of i set = the + side on axis k.
Eigen::Vector3d boxCorner(const Eigen::Vector3d& half, int i) {
  return Eigen::Vector3d((i & 1) ? half.x() : -half.x(), (i & 2) ? half.y() : -half.y(),
                         (i & 4) ? half.z() : -half.z());
}

// The face region of a point (one coordinate beyond the box, the others within): axis * 2 + side,
// or -1 elsewhere.
int faceRegion(const Eigen::Vector3d& half, const Eigen::Vector3d& p) {
  int region = -1;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(p[k]) <= half[k]) continue;
    if (region >= 0) return -1;  // an edge or corner region
    region = 2 * k + (p[k] > 0 ? 1 : 0);
  }
  return region;
}

}  // namespace

bool boxTriangleOverlap(const Eigen::Vector3d& half, const Eigen::Vector3d& a,
                        const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d v[3] = {a, b, c};
  const auto separated = [&](const Eigen::Vector3d& axis) {
    const double length = axis.squaredNorm();
    if (length < 1e-24) return false;  // parallel edges: not a valid axis
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& p : v) {
      const double x = axis.dot(p);
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    const double reach = half.dot(axis.cwiseAbs());
    return lo > reach || hi < -reach;
  };
  for (int k = 0; k < 3; ++k) {
    if (separated(Eigen::Vector3d::Unit(k))) return false;
  }
  const Eigen::Vector3d edges[3] = {b - a, c - b, a - c};
  if (separated(edges[0].cross(edges[1]))) return false;
  for (const auto& edge : edges) {
    for (int k = 0; k < 3; ++k) {
      if (separated(Eigen::Vector3d::Unit(k).cross(edge))) return false;
    }
  }
  return true;
}

double boxTriangleDistance(const Eigen::Vector3d& half, const Eigen::Vector3d& a,
                           const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  // The box's face regions are convex and the distance is linear in each: a triangle inside one
  // (the common case under a finger pad) is closest at a vertex.
  const int region = faceRegion(half, a);
  if (region >= 0 && faceRegion(half, b) == region && faceRegion(half, c) == region) {
    const int axis = region / 2;
    return std::min({std::abs(a[axis]), std::abs(b[axis]), std::abs(c[axis])}) - half[axis];
  }
  if (boxTriangleOverlap(half, a, b, c)) return 0;
  // Disjoint convex polytopes: the closest pair is a vertex against the other's solid, or two
  // edges. A box corner or the inside of a box edge is the closest box point only to points in its
  // Voronoi region (beyond the box on the corner's three axes, on the edge's two), so a feature
  // whose region no vertex of the triangle (for an edge pair: of the triangle's edge) reaches is
  // skipped: about nine in ten of the 8 corner and 36 edge-pair tests near a finger pad.
  const Eigen::Vector3d tri[3] = {a, b, c};
  // reach[k][side]: bit e set if vertex e lies on or beyond the box's face `side` of axis k.
  int reach[3][2] = {{0, 0}, {0, 0}, {0, 0}};
  for (int e = 0; e < 3; ++e) {
    for (int k = 0; k < 3; ++k) {
      if (tri[e][k] >= half[k]) reach[k][1] |= 1 << e;
      if (tri[e][k] <= -half[k]) reach[k][0] |= 1 << e;
    }
  }
  double best =
      std::min({pointBoxDistance(half, a), pointBoxDistance(half, b), pointBoxDistance(half, c)});
  double best_squared = best * best;
  Eigen::Vector3d corners[8];
  for (int i = 0; i < 8; ++i) {
    corners[i] = boxCorner(half, i);
    if (!reach[0][i & 1] || !reach[1][(i >> 1) & 1] || !reach[2][(i >> 2) & 1]) continue;
    best_squared = std::min(
        best_squared, (closestOnTriangle(corners[i], a, b, c).point - corners[i]).squaredNorm());
  }
  for (int i = 0; i < 8; ++i) {
    for (int k = 0; k < 3; ++k) {
      const int j = i | (1 << k);
      if (j == i) continue;  // each box edge once: from the corner with bit k clear
      const int u = (k + 1) % 3, v = (k + 2) % 3;
      const int reach_u = reach[u][(i >> u) & 1], reach_v = reach[v][(i >> v) & 1];
      for (int e = 0; e < 3; ++e) {
        const int ends = (1 << e) | (1 << ((e + 1) % 3));
        if (!(reach_u & ends) || !(reach_v & ends)) continue;
        best_squared = std::min(
            best_squared,
            segmentSegmentDistanceSquared(corners[i], corners[j], tri[e], tri[(e + 1) % 3]));
      }
    }
  }
  return std::sqrt(best_squared);
}

std::optional<BoxTrianglePoints> boxTriangleClosestPoints(const Eigen::Vector3d& half,
                                                          const Eigen::Vector3d& a,
                                                          const Eigen::Vector3d& b,
                                                          const Eigen::Vector3d& c) {
  if (boxTriangleOverlap(half, a, b, c)) return std::nullopt;
  // Disjoint convex polytopes: the closest pair is a vertex of one against the other, or two
  // edges. All of them, without boxTriangleDistance's pruning: this runs once per contact.
  BoxTrianglePoints best{std::numeric_limits<double>::infinity(), Eigen::Vector3d::Zero(),
                         Eigen::Vector3d::Zero()};
  const auto consider = [&](const Eigen::Vector3d& on_box, const Eigen::Vector3d& on_triangle) {
    const double d = (on_box - on_triangle).norm();
    if (d < best.distance) best = {d, on_box, on_triangle};
  };
  const Eigen::Vector3d tri[3] = {a, b, c};
  for (const auto& v : tri) consider(v.cwiseMax(-half).cwiseMin(half), v);
  Eigen::Vector3d corners[8];
  for (int i = 0; i < 8; ++i) {
    corners[i] = boxCorner(half, i);
    consider(corners[i], closestOnTriangle(corners[i], a, b, c).point);
  }
  for (int i = 0; i < 8; ++i) {
    for (int k = 0; k < 3; ++k) {
      const int j = i | (1 << k);
      if (j == i) continue;  // each box edge once
      for (int e = 0; e < 3; ++e) {
        const SegmentPoints closest =
            closestSegmentPoints(corners[i], corners[j], tri[e], tri[(e + 1) % 3]);
        consider(closest.on_p, closest.on_q);
      }
    }
  }
  return best;
}

}  // namespace skelgrasp::grasping::internal
