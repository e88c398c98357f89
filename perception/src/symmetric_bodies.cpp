// One rotationally symmetric body cut in two: seen from above, a mug shows the outside of its near
// wall and, over the rim, the inside of its far wall. LCCP cuts the two apart at the rim (the PCL
// stereo mug, the GPD mug), yet seen from above both lie on one circle about the mug's axis, which
// two objects side by side never do: each has its own axis. The pieces are joined when one
// vertical circle carries most of the points of both and they close a ring around it
// (docs/perception.md, "Segmentation").
#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "skelgrasp/common/logging.h"
#include "skelgrasp/internal/segmentation.h"

namespace skelgrasp::internal {
namespace {

// Circle candidates drawn, points evaluated per piece (a regular subsample of larger pieces) and
// the angular bins the ring coverage is counted in (10 degrees each).
constexpr int kCircleSamples = 400;
constexpr std::size_t kEvaluatedPoints = 600;
constexpr int kAngleBins = 36;
constexpr unsigned kSeed = 20140623;  // any fixed value: the fit is deterministic

struct Circle {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 0;
};

// The circle through three points; radius 0 when they are (nearly) collinear.
Circle circleThrough(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r) {
  const Eigen::Vector2d b = q - p, c = r - p;
  const double d = 2.0 * (b.x() * c.y() - b.y() * c.x());
  Circle out;
  if (std::abs(d) < 1e-12) return out;
  const double b2 = b.squaredNorm(), c2 = c.squaredNorm();
  const Eigen::Vector2d u((c.y() * b2 - b.y() * c2) / d, (b.x() * c2 - c.x() * b2) / d);
  out.centre = p + u;
  out.radius = u.norm();
  return out;
}

// Every k-th point so that at most kEvaluatedPoints remain, projected on the plane.
std::vector<Eigen::Vector2d> footprint(const PointCloud& cloud, const std::vector<int>& members,
                                       const perception::SupportPlane& plane) {
  const Eigen::Vector3d across = plane.normal.unitOrthogonal();
  const Eigen::Vector3d along = plane.normal.cross(across);
  const std::size_t step = std::max<std::size_t>(1, members.size() / kEvaluatedPoints);
  std::vector<Eigen::Vector2d> out;
  out.reserve(members.size() / step + 1);
  for (std::size_t k = 0; k < members.size(); k += step) {
    const Eigen::Vector3d& p = cloud.points[members[k]];
    out.emplace_back(across.dot(p), along.dot(p));
  }
  return out;
}

struct RingSupport {
  double fraction = 0;                  // of the piece's points on the ring
  std::array<bool, kAngleBins> bins{};  // the directions from the centre those points lie in
};

RingSupport support(const std::vector<Eigen::Vector2d>& points, const Circle& circle,
                    double tolerance_m) {
  RingSupport s;
  if (points.empty()) return s;
  std::size_t on = 0;
  for (const auto& p : points) {
    const Eigen::Vector2d r = p - circle.centre;
    if (std::abs(r.norm() - circle.radius) > tolerance_m) continue;
    ++on;
    const double angle = std::atan2(r.y(), r.x()) + M_PI;  // [0, 2 pi]
    const int bin = std::min(kAngleBins - 1, static_cast<int>(angle / (2 * M_PI) * kAngleBins));
    s.bins[bin] = true;
  }
  s.fraction = static_cast<double>(on) / static_cast<double>(points.size());
  return s;
}

}  // namespace

bool oneSymmetricBody(const PointCloud& cloud, const std::vector<int>& a, const std::vector<int>& b,
                      const perception::SupportPlane& plane, const perception::LccpParams& lp) {
  const auto pa = footprint(cloud, a, plane);
  const auto pb = footprint(cloud, b, plane);
  if (pa.size() < 3 || pb.size() < 3) return false;
  std::vector<Eigen::Vector2d> both = pa;
  both.insert(both.end(), pb.begin(), pb.end());
  std::mt19937 rng(kSeed);
  std::uniform_int_distribution<std::size_t> pick(0, both.size() - 1);
  double best = 0;
  Circle best_circle;
  for (int s = 0; s < kCircleSamples; ++s) {
    const Circle c = circleThrough(both[pick(rng)], both[pick(rng)], both[pick(rng)]);
    if (c.radius < lp.symmetric_min_radius_m || c.radius > lp.symmetric_max_radius_m) continue;
    const double tolerance = lp.symmetric_ring_tolerance * c.radius;
    const double score =
        std::min(support(pa, c, tolerance).fraction, support(pb, c, tolerance).fraction);
    if (score > best) {
      best = score;
      best_circle = c;
    }
  }
  if (best_circle.radius == 0) return false;
  const double tolerance = lp.symmetric_ring_tolerance * best_circle.radius;
  const RingSupport sa = support(pa, best_circle, tolerance);
  const RingSupport sb = support(pb, best_circle, tolerance);
  int covered = 0;
  for (int k = 0; k < kAngleBins; ++k) covered += (sa.bins[k] || sb.bins[k]) ? 1 : 0;
  const double coverage = static_cast<double>(covered) / kAngleBins;
  log().debug(
      "scene: symmetric-body test, {} + {} points, radius {:.3f} m, on ring {:.2f} / {:.2f}, "
      "coverage {:.2f}",
      a.size(), b.size(), best_circle.radius, sa.fraction, sb.fraction, coverage);
  return std::min(sa.fraction, sb.fraction) >= lp.symmetric_min_ring_fraction &&
         coverage >= lp.symmetric_min_coverage;
}

}  // namespace skelgrasp::internal
