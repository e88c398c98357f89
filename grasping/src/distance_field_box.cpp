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
#include "skelgrasp/grasping/distance_field.h"
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
  const Eigen::Matrix3d to_box = box_pose.linear().transpose();
  const Eigen::Vector3d centre = box_pose.translation();
  const auto closest = internal::boxTriangleClosestPoints(
      half, to_box * (m.vertices[t[0]] - centre), to_box * (m.vertices[t[1]] - centre),
      to_box * (m.vertices[t[2]] - centre));
  if (!closest) return std::nullopt;  // touching within rounding
  return BoxClosestPoints{box_pose * closest->on_box,
                          SurfacePoint{box_pose * closest->on_triangle, face, closest->distance}};
}

std::optional<std::size_t> DistanceField::boxIntersection(
    const Pose& box_pose, const Eigen::Vector3d& half, std::optional<std::size_t> hint_face) const {
  const auto& m = *impl_;
  const Eigen::Matrix3d rotation = box_pose.linear();
  const Eigen::Matrix3d to_box = rotation.transpose();
  const Eigen::Vector3d centre = box_pose.translation();
  const auto inBox = [&](const Eigen::Vector3d& point) -> Eigen::Vector3d {
    return to_box * (point - centre);
  };
  const auto overlaps = [&](std::size_t f) {
    const auto& t = m.faces[f];
    return internal::boxTriangleOverlap(half, inBox(m.vertices[t[0]]), inBox(m.vertices[t[1]]),
                                        inBox(m.vertices[t[2]]));
  };
  if (hint_face && *hint_face < m.faces.size() && overlaps(*hint_face)) return hint_face;
  // Clear of the surface by more than the box's half diagonal: one field lookup says so.
  if (lowerBound(centre) > half.norm()) return std::nullopt;
  VisitedFaces& visited = visited_faces;
  visited.start(m.faces.size());
  if (hint_face && *hint_face < m.faces.size())
    visited.firstVisit(static_cast<std::uint32_t>(*hint_face));
  // A point the box shares with a face lies in the box's axis-aligned bounds, and the face is
  // listed in the cell holding that point: the cells there list every face that can intersect.
  const Eigen::Vector3d reach = rotation.cwiseAbs() * half;
  const Eigen::Vector3i a = m.cellOf(centre - reach), b = m.cellOf(centre + reach);
  const double cell_radius = m.cell * std::sqrt(3.0) / 2;
  const Eigen::Vector3d step_x = to_box.col(0) * m.cell;
  const auto squaredOutside = [&](const Eigen::Vector3d& in_box) {
    return (in_box.cwiseAbs() - half).cwiseMax(0.0).squaredNorm();
  };
  for (int z = a.z(); z <= b.z(); ++z) {
    for (int y = a.y(); y <= b.y(); ++y) {
      const std::size_t row = m.cellIndex({0, y, z});
      const std::size_t row_end = row + b.x() + 1;
      std::size_t c = m.nextOccupied(row + a.x(), row_end);
      if (c == row_end) continue;
      const Eigen::Vector3d row_start =
          inBox(m.origin + m.cell * Eigen::Vector3d(0.5, y + 0.5, z + 0.5));
      for (; c < row_end; c = m.nextOccupied(c + 1, row_end)) {
        // A cell the box does not reach holds no shared point; its faces that reach the box are
        // listed in the cells where they meet it.
        const auto x = static_cast<double>(c - row);
        if (squaredOutside(row_start + x * step_x) > cell_radius * cell_radius) continue;
        for (std::uint32_t k = m.cell_first[c]; k < m.cell_first[c + 1]; ++k) {
          const std::uint32_t f = m.cell_faces[k];
          if (!visited.firstVisit(f)) continue;
          const double face_radius = m.face_radii[f];
          if (squaredOutside(inBox(m.face_centres[f])) > face_radius * face_radius) continue;
          if (overlaps(f)) return f;
        }
      }
    }
  }
  return std::nullopt;
}

double DistanceField::boxGap(const Pose& box_pose, const Eigen::Vector3d& half, double upper,
                             std::optional<std::size_t> hint_face,
                             std::optional<std::size_t>* closest_face) const {
  const auto& m = *impl_;
  const Eigen::Matrix3d rotation = box_pose.linear();
  const Eigen::Matrix3d to_box = rotation.transpose();
  const Eigen::Vector3d centre = box_pose.translation();
  const auto inBox = [&](const Eigen::Vector3d& point) -> Eigen::Vector3d {
    return to_box * (point - centre);
  };
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
    const double d = internal::boxTriangleDistance(
        half, inBox(m.vertices[t[0]]), inBox(m.vertices[t[1]]), inBox(m.vertices[t[2]]));
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
  const Eigen::Vector3d reach = rotation.cwiseAbs() * half + Eigen::Vector3d::Constant(best);
  const Eigen::Vector3i a = m.cellOf(centre - reach), b = m.cellOf(centre + reach);
  const double cell_radius = m.cell * std::sqrt(3.0) / 2;
  // Distances are compared squared (no square root per cell or face); cell centres in the box's
  // frame are stepped along x instead of transformed per cell.
  const Eigen::Vector3d step_x = to_box.col(0) * m.cell;
  const auto squaredOutside = [&](const Eigen::Vector3d& in_box) {
    return (in_box.cwiseAbs() - half).cwiseMax(0.0).squaredNorm();
  };
  for (int z = a.z(); z <= b.z(); ++z) {
    for (int y = a.y(); y <= b.y(); ++y) {
      const std::size_t row = m.cellIndex({0, y, z});
      const std::size_t row_end = row + b.x() + 1;
      std::size_t c = m.nextOccupied(row + a.x(), row_end);
      if (c == row_end) continue;  // most rows a box reaches are empty (96 of 133 in an SDH plan)
      const Eigen::Vector3d row_start =
          inBox(m.origin + m.cell * Eigen::Vector3d(0.5, y + 0.5, z + 0.5));
      for (; c < row_end; c = m.nextOccupied(c + 1, row_end)) {
        const auto x = static_cast<double>(c - row);
        // A triangle reaching past its cell is also listed in the cells it reaches.
        const double cell_reach = best + cell_radius;
        if (squaredOutside(row_start + x * step_x) > cell_reach * cell_reach) continue;
        for (std::uint32_t k = m.cell_first[c]; k < m.cell_first[c + 1]; ++k) {
          const std::uint32_t f = m.cell_faces[k];
          if (!visited.firstVisit(f)) continue;
          // Cut when the face's bound exceeds best. Only when it exceeds: a face as close as the
          // best one must be tested for the least index among the closest faces.
          const double face_reach = best + m.face_radii[f];
          const double outside = squaredOutside(inBox(m.face_centres[f]));
          if (outside > face_reach * face_reach) continue;
          const auto& t = m.faces[f];
          const Eigen::Vector3d v0 = inBox(m.vertices[t[0]]), v1 = inBox(m.vertices[t[1]]),
                                v2 = inBox(m.vertices[t[2]]);
          // Separating axes cut most triangles the sphere bound lets through (same rule).
          const double separation =
              internal::boxTriangleSeparation(half, v0, v1, v2, to_box * m.face_normals[f]);
          if (separation > best) continue;
          const double d = internal::boxTriangleDistance(half, v0, v1, v2);
          if (d < best || (d == best && (!found || f < face))) {
            best = d;
            found = true;
            face = f;
          }
          if (best <= 0) {
            if (closest_face) *closest_face = face;
            return 0;
          }
        }
      }
    }
  }
  // The closest triangle is never cut (its bound is at most the gap, at most every `best`): no
  // exact distance at or below `best` means the gap is beyond `upper`.
  if (!found) return upper;
  if (closest_face) *closest_face = face;
  return best;
}

}  // namespace skelgrasp::grasping
