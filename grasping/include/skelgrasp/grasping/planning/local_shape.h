#pragma once
// Local object properties at a skeleton vertex (paper Sec. IV-A): the grasping interval P_I, the
// grasping plane through the vertex with the skeleton tangent as normal, and the principal axes of
// the interval's surface points projected onto that plane.
#include <vector>

#include "skelgrasp/skeleton/skeleton.h"

namespace skelgrasp::grasping {

struct LocalShapeParams {
  // Intervals are cut before a vertex whose curvature exceeds this (1/m); 0 = no limit (as the
  // reference code, which has none).
  double curvature_limit_per_m = 0;
  // lambda1 / lambda2 below this: round (paper 1.2; reference code 1.3).
  double round_ratio = 1.2;
  // Fewer projected points than this: no shape analysis.
  int min_points = 6;
};

struct LocalShape {
  const char* reason = nullptr;  // why no shape: interval too short, too few points
  std::vector<int> interval;     // skeleton vertices of P_I (the vertex first)
  double length_before = 0;      // interval length walked on each side of the vertex (metres)
  double length_after = 0;
  Eigen::Vector3d tangent = Eigen::Vector3d::UnitZ();  // grasping-plane normal; at endpoints
                                                       // pointing from the end into the object
  // Standard deviations (metres) of the projected points along the principal axes ev1, ev2 of
  // the plane (lambda1 >= lambda2): the reference's "thickness" t1, t2, about 0.71 r for a round
  // section of radius r. Not widths.
  double lambda1 = 0, lambda2 = 0;
  Eigen::Vector3d ev1 = Eigen::Vector3d::UnitX(), ev2 = Eigen::Vector3d::UnitY();
  bool round = false;
  int points = 0;
};

// `surface_points` are the positions of the input mesh vertices that Skeleton::surface_points
// index. `half_length` is the interval length wanted on each side (endpoints: inwards only).
// Connecting vertices need the full half length on both sides (reason interval_too_short).
LocalShape analyzeLocalShape(const skeleton::Skeleton& skeleton,
                             const std::vector<Eigen::Vector3d>& surface_points, int vertex,
                             double half_length, const LocalShapeParams& params);

}  // namespace skelgrasp::grasping
