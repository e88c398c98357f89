// One object seen in pieces around an occluder: a low box behind a can shows its left and its
// right end, which touch nowhere, so no convexity rule can join them (mOSD osd_test26). The
// pieces are joined when everything between them is hidden from the sensor by a third segment
// and they look alike (docs/perception.md, "Segmentation of touching objects").
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <utility>

#include "skelgrasp/common/logging.h"
#include "skelgrasp/geometry/point_index.h"
#include "skelgrasp/internal/segmentation.h"

namespace skelgrasp::internal {
namespace {

// Points of a gap closer than this to either end are the pieces' own surface, not the gap.
constexpr double kGapEndMarginM = 0.01;

// The points of each segment and their nearest-neighbour index, built once.
struct Piece {
  std::vector<Eigen::Vector3d> points;
  std::unique_ptr<geometry::PointIndex> index;
  Eigen::Vector3d mean_colour = Eigen::Vector3d::Zero();  // 0-255 per channel
  Eigen::Vector3d lower = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d upper = -lower;
};

// The closest pair of points of two pieces (each point of the smaller against the larger's
// index): the gap between them is where the occluder must stand.
std::pair<Eigen::Vector3d, Eigen::Vector3d> closestPair(const Piece& a, const Piece& b) {
  const Piece& small = a.points.size() <= b.points.size() ? a : b;
  const Piece& large = &small == &a ? b : a;
  double best = std::numeric_limits<double>::infinity();
  std::pair<Eigen::Vector3d, Eigen::Vector3d> pair;
  for (const auto& p : small.points) {
    const auto [k, d] = large.index->nearest(p);
    if (k >= 0 && d < best) {
      best = d;
      pair = {p, large.points[k]};
    }
  }
  if (&small != &a) std::swap(pair.first, pair.second);
  return pair;
}

// Whether every point of the gap a-b is hidden from the sensor: some point of another segment
// lies on (nearly) the same viewing ray, nearer by at least min_depth_m. Viewing rays are points
// of the unit sphere about the origin; `rays` indexes every candidate point's ray.
bool gapHidden(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& origin,
               const geometry::PointIndex& rays, const std::vector<double>& ranges,
               const std::vector<int>& segment_of, int piece_a, int piece_b,
               const perception::LccpParams& lp) {
  const double length = (b - a).norm();
  const int steps = static_cast<int>(std::ceil(length / lp.hidden_gap_step_m));
  int tested = 0;
  for (int s = 1; s < steps; ++s) {
    const Eigen::Vector3d q = a + (b - a) * (static_cast<double>(s) / steps);
    if ((q - a).norm() < kGapEndMarginM || (q - b).norm() < kGapEndMarginM) continue;
    const Eigen::Vector3d ray = q - origin;
    const double range = ray.norm();
    bool hidden = false;
    for (int k : rays.within(ray / range, lp.hidden_gap_ray_radius_rad)) {
      const int owner = segment_of[k];
      if (owner >= 0 && owner != piece_a && owner != piece_b &&
          ranges[k] < range - lp.hidden_gap_min_depth_m) {
        hidden = true;
        break;
      }
    }
    if (!hidden) return false;
    ++tested;
  }
  return tested > 0;  // a gap with no point between its ends is not a hidden one
}

int findRoot(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

std::size_t joinAcrossOccluders(const PointCloud& cloud, std::vector<std::vector<int>>& segments,
                                const perception::LccpParams& lp) {
  if (!lp.join_hidden_gaps || segments.size() < 3) return 0;  // pieces need an occluder
  const Eigen::Vector3d origin =
      cloud.sensor_origin.allFinite() ? cloud.sensor_origin : Eigen::Vector3d::Zero();
  const bool colours = cloud.hasColors();
  std::vector<Piece> pieces(segments.size());
  std::vector<Eigen::Vector3d> directions;
  std::vector<double> ranges;
  std::vector<int> segment_of;
  for (std::size_t s = 0; s < segments.size(); ++s) {
    for (int i : segments[s]) {
      const Eigen::Vector3d& p = cloud.points[i];
      pieces[s].points.push_back(p);
      pieces[s].lower = pieces[s].lower.cwiseMin(p);
      pieces[s].upper = pieces[s].upper.cwiseMax(p);
      if (colours) {
        pieces[s].mean_colour +=
            Eigen::Vector3d(cloud.colors[i][0], cloud.colors[i][1], cloud.colors[i][2]);
      }
      const double range = (p - origin).norm();
      if (!(range > 0)) continue;
      directions.push_back((p - origin) / range);
      ranges.push_back(range);
      segment_of.push_back(static_cast<int>(s));
    }
    if (!pieces[s].points.empty()) {
      pieces[s].mean_colour /= static_cast<double>(pieces[s].points.size());
    }
    pieces[s].index = std::make_unique<geometry::PointIndex>(pieces[s].points);
  }
  const geometry::PointIndex rays(directions);

  std::vector<int> parent(segments.size());
  std::iota(parent.begin(), parent.end(), 0);
  std::size_t joined = 0;
  for (std::size_t a = 0; a < segments.size(); ++a) {
    for (std::size_t b = a + 1; b < segments.size(); ++b) {
      if (pieces[a].points.empty() || pieces[b].points.empty()) continue;
      // Cheap tests first: the boxes' gap bounds the closest pair's, and the colours.
      const Eigen::Vector3d box_gap = (pieces[a].lower - pieces[b].upper)
                                          .cwiseMax(pieces[b].lower - pieces[a].upper)
                                          .cwiseMax(0.0);
      if (box_gap.norm() > lp.hidden_gap_max_m) continue;
      // Alike: pieces of one object share its colour (without colours, the gap alone decides).
      const double colour_distance = (pieces[a].mean_colour - pieces[b].mean_colour).norm();
      if (colours && colour_distance > lp.hidden_gap_max_colour_distance) continue;
      const auto [pa, pb] = closestPair(pieces[a], pieces[b]);
      if ((pa - pb).norm() > lp.hidden_gap_max_m) continue;
      if (!gapHidden(pa, pb, origin, rays, ranges, segment_of, static_cast<int>(a),
                     static_cast<int>(b), lp))
        continue;
      const int ra = findRoot(parent, static_cast<int>(a)),
                rb = findRoot(parent, static_cast<int>(b));
      if (ra == rb) continue;
      log().debug(
          "scene: segments of {} and {} points are one object behind an occluder (gap {:.3f} m "
          "from ({:.3f}, {:.3f}, {:.3f}) to ({:.3f}, {:.3f}, {:.3f}), colour distance {:.0f})",
          pieces[a].points.size(), pieces[b].points.size(), (pa - pb).norm(), pa.x(), pa.y(),
          pa.z(), pb.x(), pb.y(), pb.z(), colour_distance);
      parent[rb] = ra;
      ++joined;
    }
  }
  if (joined == 0) return 0;
  std::vector<std::vector<int>> merged(segments.size());
  for (std::size_t s = 0; s < segments.size(); ++s) {
    auto& into = merged[findRoot(parent, static_cast<int>(s))];
    into.insert(into.end(), segments[s].begin(), segments[s].end());
  }
  segments.clear();
  for (auto& m : merged) {
    if (!m.empty()) segments.push_back(std::move(m));
  }
  return joined;
}

}  // namespace skelgrasp::internal
