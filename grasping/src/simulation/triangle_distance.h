#pragma once
// Internal: exact distances between a triangle and a point, a segment or a solid box, for the
// object's distance field (grid values, closest points and link gaps of the fast closing).
#include <Eigen/Core>
#include <optional>

namespace skelgrasp::grasping::internal {

// Where on a triangle the closest point lies: its face, an edge (k: from vertex k to k+1) or a
// vertex (k). Selects the pseudo-normal that gives the sign of the distance.
enum class TriangleFeature { kFace, kEdge, kVertex };

struct TrianglePoint {
  Eigen::Vector3d point;
  TriangleFeature feature = TriangleFeature::kFace;
  int index = 0;  // edge or vertex index
};

// Closest point of triangle (a, b, c) to p (Ericson, Real-Time Collision Detection, 5.1.5).
TrianglePoint closestOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                const Eigen::Vector3d& b, const Eigen::Vector3d& c);

// Closest points of segments p0-p1 and q0-q1 (Ericson, 5.1.9).
struct SegmentPoints {
  Eigen::Vector3d on_p, on_q;
};
SegmentPoints closestSegmentPoints(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                   const Eigen::Vector3d& q0, const Eigen::Vector3d& q1);

// Squared distance between segments p0-p1 and q0-q1.
double segmentSegmentDistanceSquared(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                     const Eigen::Vector3d& q0, const Eigen::Vector3d& q1);

// Separating-axis test of triangle (a, b, c) against the solid box [-half, half], both in the
// box's frame (Akenine-Moeller): true when they intersect, touching included.
bool boxTriangleOverlap(const Eigen::Vector3d& half, const Eigen::Vector3d& a,
                        const Eigen::Vector3d& b, const Eigen::Vector3d& c);

// Distance between the solid axis-aligned box [-half, half] and triangle (a, b, c) given in the
// box's frame; 0 when they intersect.
double boxTriangleDistance(const Eigen::Vector3d& half, const Eigen::Vector3d& a,
                           const Eigen::Vector3d& b, const Eigen::Vector3d& c);

// The closest points of the solid box [-half, half] and triangle (a, b, c), both in the box's
// frame, and their distance; nullopt when they intersect (no unique pair).
struct BoxTrianglePoints {
  double distance = 0;
  Eigen::Vector3d on_box, on_triangle;
};
std::optional<BoxTrianglePoints> boxTriangleClosestPoints(const Eigen::Vector3d& half,
                                                          const Eigen::Vector3d& a,
                                                          const Eigen::Vector3d& b,
                                                          const Eigen::Vector3d& c);

// A lower bound of boxTriangleDistance from separating axes: the gap between the projections of
// box and triangle on each box axis and on the triangle's unit normal `normal` (zero for a
// degenerate triangle). Projection onto a unit axis shortens no distance, so every such gap is
// at most the distance; for a finger pad facing the triangle it is the distance.
inline double boxTriangleSeparation(const Eigen::Vector3d& half, const Eigen::Vector3d& a,
                                    const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                    const Eigen::Vector3d& normal) {
  const Eigen::Vector3d lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
  double gap = std::max((lo - half).maxCoeff(), (-half - hi).maxCoeff());
  gap = std::max(gap, std::abs(normal.dot(a)) - half.dot(normal.cwiseAbs()));
  return gap;
}

// Distance from p to the solid box [-half, half] (0 inside).
inline double pointBoxDistance(const Eigen::Vector3d& half, const Eigen::Vector3d& p) {
  return (p.cwiseAbs() - half).cwiseMax(0.0).norm();
}

}  // namespace skelgrasp::grasping::internal
