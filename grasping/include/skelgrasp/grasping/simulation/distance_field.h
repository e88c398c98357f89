#pragma once
// The signed distance field of an object to grasp: a regular grid over the object's bounding box
// (plus a margin) with exact distances to the surface in a narrow band, and a grid of triangles
// for exact queries near the surface. The fast closing reads conservative gap bounds from it in
// O(1) and asks the exact queries only near contact (docs/hands.md, "Benchmarks").
#include <cstddef>
#include <memory>
#include <optional>

#include "skelgrasp/common/mesh.h"
#include "skelgrasp/common/pose.h"

namespace skelgrasp::grasping {

struct DistanceFieldParams {
  // Grid spacing. The worst-case slack of lowerBound is spacing * sqrt(3) / 2 (1.7 mm at 2 mm),
  // taken up by exact queries near contact; memory is 4 bytes per node.
  double spacing_m = 0.002;
  // Nodes within this distance of the surface hold the exact distance; farther nodes hold only
  // the bound "at least band_m" (outside) or "inside". Wider bands cost build time.
  double band_m = 0.004;
  // Memory guard: when the grid over the box plus margin would have more nodes, the spacing grows
  // until it fits (default: 64 MB of floats).
  std::size_t max_nodes = 16'000'000;
  // The exact box gap walks the cells of the triangle grid around the box. True: a row's empty
  // cells are skipped 64 at a time (a bit scan), and rows with none occupied are not entered.
  // False: every cell is stepped through and its bit tested, the plain walk, kept so that
  // `skelgrasp bench ranking --compare cell-skipping` times both in one process. The gaps
  // and closest faces are the same either way (the cells are visited in the same order).
  bool skip_empty_cells = true;
  // The simulator tests a hand's box shapes for intersection with the object on this field's
  // triangle grid (DistanceField::boxIntersection) rather than on FCL's tree of bounding boxes,
  // and clears any shape whose covering spheres the field bounds away from the surface before
  // FCL's test of its cylinders, spheres and meshes. The fast closing tests a link near the object
  // at every step it crawls towards it, and there FCL walked deep into its tree: a fifth of an SDH
  // plan's time. The same verdicts up to rounding at touching (tested against FCL). False: FCL
  // alone, kept so that `skelgrasp bench ranking --compare box-tests` times both in one process.
  bool box_intersection_tests = true;
};

// Throws InvalidArgument for a spacing or band that is not positive: the one check of these params,
// shared by DistanceField and GraspObject (which builds its field on first use, so checks first).
void checkDistanceFieldParams(const DistanceFieldParams& params);

// A point on the surface with the face it lies on and its distance from the query point.
struct SurfacePoint {
  Eigen::Vector3d point;
  std::size_t face = 0;
  double distance = 0;
};

class DistanceField {
 public:
  // `signed_field`: negative inside (the mesh must be closed); else the unsigned distance.
  // Throws InvalidArgument for an empty mesh or a non-positive spacing or band.
  DistanceField(const TriangleMesh& mesh, bool signed_field,
                const DistanceFieldParams& params = {});
  ~DistanceField();
  DistanceField(const DistanceField&) = delete;
  DistanceField& operator=(const DistanceField&) = delete;

  double spacing() const;  // after the memory guard
  std::size_t nodeCount() const;
  bool isSigned() const;
  // Worst-case amount by which lowerBound lies below the true distance where the grid holds
  // exact values (half the cell diagonal).
  double errorBound() const;

  // Trilinear interpolation of the node values (within band_m of the surface: the distance to
  // within errorBound(); farther: clamped to about band_m).
  double value(const Eigen::Vector3d& p) const;
  // A guaranteed lower bound of the (signed) distance of p from the surface, anywhere in space.
  double lowerBound(const Eigen::Vector3d& p) const;

  // A guaranteed upper bound of the unsigned distance of p from the surface where the grid holds
  // exact values near p, else infinity.
  double unsignedUpperBound(const Eigen::Vector3d& p) const;

  // Exact closest surface point of p if it is within `radius` (from the triangle grid).
  std::optional<SurfacePoint> closestPointWithin(const Eigen::Vector3d& p, double radius) const;
  // Exact distance between the solid box of half extents `half` placed at `box_pose` and the
  // surface (0 when they intersect), or `upper` when it is at least `upper`.
  double boxDistance(const Pose& box_pose, const Eigen::Vector3d& half, double upper) const;
  // boxDistance, and a closest triangle's face when the gap is below `upper` (unset otherwise):
  // a caller that may need the closest points later (boxClosestPointsOnFace) gets them without a
  // second search, and may pass the face as the next query's hint. `hint_face` (any face index;
  // out of range: ignored) only speeds the search: its distance bounds the gap, so a face that
  // was closest to the box at a nearby pose halves the work. Of several faces at the same gap
  // above 0 the one of least index comes back, whatever the hint, so gap and face are the same
  // with any hint or none; at 0 (the box intersects the surface) it is one the box intersects.
  struct BoxGap {
    double distance = 0;
    std::optional<std::size_t> face;
  };
  BoxGap boxGapAndFace(const Pose& box_pose, const Eigen::Vector3d& half, double upper,
                       std::optional<std::size_t> hint_face = std::nullopt) const;

  // The closest points of that box and the surface (world frame) from a gap already searched
  // (boxGapAndFace at this pose, its face): those of the box and that face; nullopt when they
  // touch (within rounding). `on_surface.distance` is the gap.
  struct BoxClosestPoints {
    Eigen::Vector3d on_box;
    SurfacePoint on_surface;
  };
  // Whether the solid box of half extents `half` placed at `box_pose` intersects the surface
  // (touching counts): a face it intersects, none when they are disjoint (a box wholly inside a
  // closed surface meets no face). `hint_face` (any index; out of range: ignored) is tested first:
  // the face a link hit a step ago mostly still is one it hits. The verdict does not depend on it.
  std::optional<std::size_t> boxIntersection(
      const Pose& box_pose, const Eigen::Vector3d& half,
      std::optional<std::size_t> hint_face = std::nullopt) const;

  std::optional<BoxClosestPoints> boxClosestPointsOnFace(const Pose& box_pose,
                                                         const Eigen::Vector3d& half,
                                                         std::size_t face) const;

 private:
  // boxGapAndFace's search; the face only when closest_face is given.
  double boxGap(const Pose& box_pose, const Eigen::Vector3d& half, double upper,
                std::optional<std::size_t> hint_face,
                std::optional<std::size_t>* closest_face) const;

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace skelgrasp::grasping
