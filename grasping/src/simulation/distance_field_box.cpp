// DistanceField's exact queries on its grid of triangles: the closest surface point within a
// radius, and the exact gap of a solid box with the face it was found at (docs/hands.md, "The
// judge, old against new"). The field's data: distance_field_impl.h.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "distance_field_impl.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/grasping/simulation/distance_field.h"
#include "triangle_distance.h"

namespace skelgrasp::grasping {

namespace {

// Faces already seen by the current exact-gap query of this thread: a triangle reaching past its
// cell is listed in every cell it reaches (two to four of them on a 16k-triangle YCB mesh), and
// its bound and distance are the same in each. A generation counter avoids clearing the stamps.
struct VisitedFaces {
  std::vector<std::uint32_t> stamp;
  std::uint32_t generation = 0;
  void start(std::size_t faces) {
    if (stamp.size() < faces) stamp.resize(faces, 0);
    if (++generation == 0) {  // wrapped: old stamps could match again
      std::fill(stamp.begin(), stamp.end(), 0);
      generation = 1;
    }
  }
  bool firstVisit(std::uint32_t face) {
    if (stamp[face] == generation) return false;
    stamp[face] = generation;
    return true;
  }
};
thread_local VisitedFaces visited_faces;

// A solid box placed in the object's frame, as the exact box queries see it.
struct PlacedBox {
  PlacedBox(const Pose& pose, const Eigen::Vector3d& half_extents)
      : to_box(pose.linear().transpose()),
        centre(pose.translation()),
        half(half_extents),
        bounds_half(pose.linear().cwiseAbs() * half_extents) {}
  Eigen::Vector3d inBox(const Eigen::Vector3d& point) const { return to_box * (point - centre); }
  // Squared distance from the box of a point given in the box's frame (0 inside): distances are
  // compared squared, no square root per cell or face.
  double squaredOutside(const Eigen::Vector3d& in_box) const {
    return (in_box.cwiseAbs() - half).cwiseMax(0.0).squaredNorm();
  }
  Eigen::Matrix3d to_box;
  Eigen::Vector3d centre, half;
  Eigen::Vector3d bounds_half;  // half extents of the box's axis-aligned bounds
};

// Calls visit(cell, cell centre in the box's frame) for each occupied cell of the triangle grid
// `grid` (DistanceField::Impl) within `margin` of the box's axis-aligned bounds, row by row, until
// visit returns false; false then. A row without an occupied cell costs a bit scan and no
// transform (most rows a box reaches are empty: 96 of 133 in an SDH plan), and the cell centres
// of a row are stepped along x in the box's frame instead of transformed one by one.
template <typename Grid, typename Visit>
bool forOccupiedCellsNear(const Grid& grid, const PlacedBox& box, double margin, Visit&& visit) {
  const Eigen::Vector3d reach = box.bounds_half + Eigen::Vector3d::Constant(margin);
  const Eigen::Vector3i a = grid.cellOf(box.centre - reach), b = grid.cellOf(box.centre + reach);
  const Eigen::Vector3d step_x = box.to_box.col(0) * grid.cell;
  for (int z = a.z(); z <= b.z(); ++z) {
    for (int y = a.y(); y <= b.y(); ++y) {
      const std::size_t row = grid.cellIndex({0, y, z});
      const std::size_t row_end = row + b.x() + 1;
      std::size_t c = grid.nextOccupied(row + a.x(), row_end);
      if (c == row_end) continue;
      const Eigen::Vector3d row_start =
          box.inBox(grid.origin + grid.cell * Eigen::Vector3d(0.5, y + 0.5, z + 0.5));
      for (; c < row_end; c = grid.nextOccupied(c + 1, row_end)) {
        if (!visit(c, Eigen::Vector3d(row_start + static_cast<double>(c - row) * step_x)))
          return false;
      }
    }
  }
  return true;
}

}  // namespace

std::optional<SurfacePoint> DistanceField::closestPointWithin(const Eigen::Vector3d& p,
                                                              double radius) const {
  const auto& m = *impl_;
  const Eigen::Vector3i a = m.cellOf(p - Eigen::Vector3d::Constant(radius));
  const Eigen::Vector3i b = m.cellOf(p + Eigen::Vector3d::Constant(radius));
  double best = radius * radius;
  std::optional<SurfacePoint> found;
  for (int z = a.z(); z <= b.z(); ++z) {
    for (int y = a.y(); y <= b.y(); ++y) {
      for (int x = a.x(); x <= b.x(); ++x) {
        const std::size_t c = m.cellIndex({x, y, z});
        for (std::uint32_t k = m.cell_first[c]; k < m.cell_first[c + 1]; ++k) {
          const std::uint32_t f = m.cell_faces[k];
          const double reach = (p - m.face_centres[f]).norm() - m.face_radii[f];
          if (reach > 0 && reach * reach > best) continue;
          const auto& t = m.faces[f];
          const auto closest =
              internal::closestOnTriangle(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
          const double d2 = (p - closest.point).squaredNorm();
          if (d2 <= best) {
            best = d2;
            found = SurfacePoint{closest.point, f, 0};
          }
        }
      }
    }
  }
  if (found) found->distance = std::sqrt(best);
  return found;
}

double DistanceField::boxDistance(const Pose& box_pose, const Eigen::Vector3d& half,
                                  double upper) const {
  return boxGap(box_pose, half, upper, std::nullopt, nullptr);
}

DistanceField::BoxGap DistanceField::boxGapAndFace(const Pose& box_pose,
                                                   const Eigen::Vector3d& half, double upper,
                                                   std::optional<std::size_t> hint_face) const {
  BoxGap gap;
  gap.distance = boxGap(box_pose, half, upper, hint_face, &gap.face);
  return gap;
}

std::optional<DistanceField::BoxClosestPoints> DistanceField::boxClosestPointsOnFace(
    const Pose& box_pose, const Eigen::Vector3d& half, std::size_t face) const {
  const auto& m = *impl_;
  if (face >= m.faces.size()) throw InvalidArgument("distance field: face index out of range");
  const auto& t = m.faces[face];
  const PlacedBox box(box_pose, half);
  const auto closest = internal::boxTriangleClosestPoints(
      half, box.inBox(m.vertices[t[0]]), box.inBox(m.vertices[t[1]]), box.inBox(m.vertices[t[2]]));
  if (!closest) return std::nullopt;  // touching within rounding
  return BoxClosestPoints{box_pose * closest->on_box,
                          SurfacePoint{box_pose * closest->on_triangle, face, closest->distance}};
}

std::optional<std::size_t> DistanceField::boxIntersection(
    const Pose& box_pose, const Eigen::Vector3d& half, std::optional<std::size_t> hint_face) const {
  const auto& m = *impl_;
  const PlacedBox box(box_pose, half);
  const auto overlaps = [&](std::size_t f) {
    const auto& t = m.faces[f];
    return internal::boxTriangleOverlap(half, box.inBox(m.vertices[t[0]]),
                                        box.inBox(m.vertices[t[1]]), box.inBox(m.vertices[t[2]]));
  };
  if (hint_face && *hint_face < m.faces.size() && overlaps(*hint_face)) return hint_face;
  // Clear of the surface by more than the box's half diagonal: one field lookup says so.
  if (lowerBound(box.centre) > half.norm()) return std::nullopt;
  VisitedFaces& visited = visited_faces;
  visited.start(m.faces.size());
  if (hint_face && *hint_face < m.faces.size())
    visited.firstVisit(static_cast<std::uint32_t>(*hint_face));
  // A point the box shares with a face lies in the box's axis-aligned bounds, and the face is
  // listed in the cell holding that point: the cells there list every face that can intersect.
  // A cell the box does not reach holds no shared point.
  const double cell_radius = m.cell * std::sqrt(3.0) / 2;
  std::optional<std::size_t> hit;
  forOccupiedCellsNear(m, box, 0.0, [&](std::size_t c, const Eigen::Vector3d& cell_centre) {
    if (box.squaredOutside(cell_centre) > cell_radius * cell_radius) return true;
    for (std::uint32_t k = m.cell_first[c]; k < m.cell_first[c + 1]; ++k) {
      const std::uint32_t f = m.cell_faces[k];
      if (!visited.firstVisit(f)) continue;
      const double face_radius = m.face_radii[f];
      if (box.squaredOutside(box.inBox(m.face_centres[f])) > face_radius * face_radius) continue;
      if (overlaps(f)) {
        hit = f;
        return false;
      }
    }
    return true;
  });
  return hit;
}

double DistanceField::boxGap(const Pose& box_pose, const Eigen::Vector3d& half, double upper,
                             std::optional<std::size_t> hint_face,
                             std::optional<std::size_t>* closest_face) const {
  const auto& m = *impl_;
  const PlacedBox box(box_pose, half);
  double best = upper;
  bool found = false;  // an exact distance at or below `upper`, of face `face`
  std::size_t face = 0;
  VisitedFaces& visited = visited_faces;
  visited.start(m.faces.size());
  // The caller's hint first: any face's exact distance bounds the gap from above, and the closest
  // face of the same box a moment ago (the fast closing moves a link a few millimetres at a time)
  // mostly still is the closest, or nearly. Such a bound halves the search's time.
  if (hint_face && *hint_face < m.faces.size()) {
    const auto& t = m.faces[*hint_face];
    const double d =
        internal::boxTriangleDistance(half, box.inBox(m.vertices[t[0]]),
                                      box.inBox(m.vertices[t[1]]), box.inBox(m.vertices[t[2]]));
    visited.firstVisit(static_cast<std::uint32_t>(*hint_face));
    if (d <= best) {
      best = d;
      found = true;
      face = *hint_face;
      if (best <= 0) {
        if (closest_face) *closest_face = face;
        return 0;
      }
    }
  }
  // And a start from the field: the distance of points on the box's surface (corners, edge
  // midpoints, face centres) bounds the gap from above, so that few triangles pass the
  // bounding-sphere test below.
  double field_bound = best;
  for (int x = -1; x <= 1; ++x) {
    for (int y = -1; y <= 1; ++y) {
      for (int z = -1; z <= 1; ++z) {
        if (x || y || z) {
          field_bound =
              std::min(field_bound,
                       unsignedUpperBound(box_pose * half.cwiseProduct(Eigen::Vector3d(x, y, z))));
        }
      }
    }
  }
  if (field_bound < best) {
    // Below the hint's distance: the hint is not a closest face, and the closest one, never cut
    // (below), comes with a distance at most this bound.
    best = field_bound;
    found = false;
  }
  const double cell_radius = m.cell * std::sqrt(3.0) / 2;
  // Stops at a face the box intersects: no gap is below 0.
  const bool touching =
      !forOccupiedCellsNear(m, box, best, [&](std::size_t c, const Eigen::Vector3d& cell_centre) {
        // A triangle reaching past its cell is also listed in the cells it reaches.
        const double cell_reach = best + cell_radius;
        if (box.squaredOutside(cell_centre) > cell_reach * cell_reach) return true;
        for (std::uint32_t k = m.cell_first[c]; k < m.cell_first[c + 1]; ++k) {
          const std::uint32_t f = m.cell_faces[k];
          if (!visited.firstVisit(f)) continue;
          // Cut when the face's bound exceeds best. Only when it exceeds: a face as close as the
          // best one must be tested for the least index among the closest faces.
          const double face_reach = best + m.face_radii[f];
          const double outside = box.squaredOutside(box.inBox(m.face_centres[f]));
          if (outside > face_reach * face_reach) continue;
          const auto& t = m.faces[f];
          const Eigen::Vector3d v0 = box.inBox(m.vertices[t[0]]), v1 = box.inBox(m.vertices[t[1]]),
                                v2 = box.inBox(m.vertices[t[2]]);
          // Separating axes cut most triangles the sphere bound lets through (same rule).
          const double separation =
              internal::boxTriangleSeparation(half, v0, v1, v2, box.to_box * m.face_normals[f]);
          if (separation > best) continue;
          const double d = internal::boxTriangleDistance(half, v0, v1, v2);
          if (d < best || (d == best && (!found || f < face))) {
            best = d;
            found = true;
            face = f;
          }
          if (best <= 0) return false;
        }
        return true;
      });
  if (touching) {
    if (closest_face) *closest_face = face;
    return 0;
  }
  // The closest triangle is never cut (its bound is at most the gap, at most every `best`): no
  // exact distance at or below `best` means the gap is beyond `upper`.
  if (!found) return upper;
  if (closest_face) *closest_face = face;
  return best;
}

}  // namespace skelgrasp::grasping
