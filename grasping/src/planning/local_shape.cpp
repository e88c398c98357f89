#include "skelgrasp/grasping/planning/local_shape.h"

#include <Eigen/Eigenvalues>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/pose.h"
#include "skelgrasp/grasping/grasp.h"

namespace skelgrasp::grasping {
namespace {

// Skeleton displacements shorter than this (metres) give no direction.
constexpr double kZeroLengthM = 1e-9;

using skeleton::Segment;
using skeleton::SegmentEnd;
using skeleton::Skeleton;
using skeleton::VertexType;

struct Walk {
  std::vector<int> vertices;  // visited, excluding the start
  double length = 0;
  int far_vertex = -1;  // last vertex with a position reached (may be a branch vertex)
};

// Walks from position `index` of the segment in direction `step` (+1/-1), collecting vertices
// until `half_length` is consumed (the vertex crossing it is included), the segment ends (a
// bounding branch vertex adds its edge length but no points), or the curvature limit cuts it.
Walk walkSide(const Skeleton& skel, const Segment& seg, int index, int step, double half_length,
              double curvature_limit) {
  Walk walk;
  const int n = static_cast<int>(seg.vertices.size());
  const int start = seg.vertices[index];
  walk.far_vertex = start;
  Eigen::Vector3d last = skel.vertices[start].position;
  for (int k = 1; walk.length < half_length; ++k) {
    int next_index = index + step * k;
    if (seg.isLoop()) {
      if (k >= n / 2 + 1) break;  // do not run into the other side
      next_index = ((next_index % n) + n) % n;
    } else if (next_index < 0 || next_index >= n) {
      const int end = step < 0 ? seg.end_vertices[0] : seg.end_vertices[1];
      const SegmentEnd kind = step < 0 ? seg.ends[0] : seg.ends[1];
      if (kind == SegmentEnd::kBranch && end >= 0) {
        walk.length += (skel.vertices[end].position - last).norm();
        walk.far_vertex = end;
      }
      break;
    }
    const int v = seg.vertices[next_index];
    const double kappa = skel.vertices[v].curvature;
    if (curvature_limit > 0 && std::isfinite(kappa) && kappa > curvature_limit) break;
    walk.length += (skel.vertices[v].position - last).norm();
    last = skel.vertices[v].position;
    walk.vertices.push_back(v);
    walk.far_vertex = v;
  }
  return walk;
}

}  // namespace

LocalShape analyzeLocalShape(const Skeleton& skel,
                             const std::vector<Eigen::Vector3d>& surface_points, int vertex,
                             double half_length, const LocalShapeParams& params) {
  if (vertex < 0 || vertex >= static_cast<int>(skel.vertices.size())) {
    throw InvalidArgument("analyzeLocalShape: vertex out of range");
  }
  LocalShape shape;
  const auto& v = skel.vertices[vertex];
  SKELGRASP_DEMAND(v.type != VertexType::kBranch && v.segment >= 0);
  const Segment& seg = skel.segments[v.segment];
  const int index = static_cast<int>(std::find(seg.vertices.begin(), seg.vertices.end(), vertex) -
                                     seg.vertices.begin());
  SKELGRASP_DEMAND(index < static_cast<int>(seg.vertices.size()));
  const Eigen::Vector3d s = v.position;
  shape.interval.push_back(vertex);

  if (v.type == VertexType::kEndpoint) {
    // Inwards only; an endpoint interval is always usable, however short.
    const bool at_front = index == 0;
    const Walk in =
        walkSide(skel, seg, index, at_front ? +1 : -1, half_length, params.curvature_limit_per_m);
    shape.interval.insert(shape.interval.end(), in.vertices.begin(), in.vertices.end());
    shape.length_after = in.length;
    const Eigen::Vector3d inward = skel.vertices[in.far_vertex].position - s;
    if (inward.norm() > kZeroLengthM) {
      shape.tangent = inward.normalized();
    } else {
      // An isolated vertex (a ball contracted to a point): along the points' longest axis.
      Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
      for (int p : v.surface_points)
        scatter += (surface_points[p] - s) * (surface_points[p] - s).transpose();
      shape.tangent = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvectors().col(2);
    }
  } else {
    const Walk before = walkSide(skel, seg, index, -1, half_length, params.curvature_limit_per_m);
    const Walk after = walkSide(skel, seg, index, +1, half_length, params.curvature_limit_per_m);
    shape.length_before = before.length;
    shape.length_after = after.length;
    shape.interval.insert(shape.interval.end(), before.vertices.begin(), before.vertices.end());
    shape.interval.insert(shape.interval.end(), after.vertices.begin(), after.vertices.end());
    if (before.length < half_length || after.length < half_length) {
      shape.reason = reason::kIntervalTooShort;
      return shape;
    }
    const Eigen::Vector3d chord =
        skel.vertices[after.far_vertex].position - skel.vertices[before.far_vertex].position;
    shape.tangent = chord.norm() > kZeroLengthM ? Eigen::Vector3d(chord.normalized())
                                                : Eigen::Vector3d::UnitZ();
  }

  // Project the interval's surface points onto the grasping plane and take the 2D principal axes.
  const Eigen::Vector3d u = anyPerpendicular(shape.tangent), w = shape.tangent.cross(u);
  std::vector<Eigen::Vector2d> projected;
  for (int iv : shape.interval) {
    for (int p : skel.vertices[iv].surface_points) {
      const Eigen::Vector3d d = surface_points[p] - s;
      projected.emplace_back(d.dot(u), d.dot(w));
    }
  }
  shape.points = static_cast<int>(projected.size());
  if (shape.points < params.min_points) {
    shape.reason = reason::kTooFewSurfacePoints;
    return shape;
  }
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : projected) mean += p;
  mean /= projected.size();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  for (const auto& p : projected) covariance += (p - mean) * (p - mean).transpose();
  covariance /= projected.size();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(covariance);
  const Eigen::Vector2d major = eigen.eigenvectors().col(1), minor = eigen.eigenvectors().col(0);
  shape.lambda1 = std::sqrt(std::max(0.0, eigen.eigenvalues()[1]));
  shape.lambda2 = std::sqrt(std::max(0.0, eigen.eigenvalues()[0]));
  shape.ev1 = (major.x() * u + major.y() * w).normalized();
  shape.ev2 = (minor.x() * u + minor.y() * w).normalized();
  shape.round = shape.lambda2 > 0 && shape.lambda1 / shape.lambda2 < params.round_ratio;
  return shape;
}

}  // namespace skelgrasp::grasping
