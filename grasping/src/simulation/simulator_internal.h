#pragma once
// Internal: the pieces of GraspSimulator::close — the hand's FCL geometry, the link pairs allowed
// to intersect, the finger advance (stepwise or fast) and the contact patch of a link.
#include <cstdint>
#include <optional>
#include <vector>

#include "fcl_conversions.h"
#include "skelgrasp/grasping/contact.h"
#include "skelgrasp/grasping/simulation/distance_field.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"

namespace skelgrasp::grasping::internal {

// A link the object blocked stops within a closing step of it (under 3 mm in an SDH plan of the
// power drill). One farther away has since been carried off by its finger's other joints and
// touches nothing: without this reach such links kept contacts (7 % of the touched links there,
// 3-134 mm from the object). The simulator's contact reach for touched links.
constexpr double kTouchedGapReachM = 0.01;

struct ShapeInstance {
  std::shared_ptr<fcl::CollisionGeometryd> geometry;
  std::unique_ptr<fcl::CollisionObjectd> object;
  Pose origin;
  double bounding_radius = 0;  // about the shape's origin
  // Surface points in the shape's frame, for the contact patch (built once, see contact_patch.cpp).
  std::vector<Eigen::Vector3d> surface_samples;
  // Spheres (centre in the shape's frame, radius) covering the shape: a cheap lower bound of its
  // distance to the object's surface (fast closing).
  std::vector<std::pair<Eigen::Vector3d, double>> sphere_cover;
  // Half extents of the box (shape frame) that holds the shape, for exact gaps from the object's
  // distance field: a box shape itself (is_box: the gap is the shape's), or the box about a
  // cylinder or a sphere (the gap bounds the shape's from below, tighter than the covering
  // spheres: the SDH's 6 cm palm disc). None for meshes.
  std::optional<Eigen::Vector3d> enclosing_half;
  bool is_box = false;
  // The last exact gap of this shape's box (shapeBoxGap): its pose, the bound it was searched to,
  // and the answer. Mutable like the placement in `object`: a shape belongs to one simulator,
  // used by one thread at a time.
  struct LastGap {
    Eigen::Matrix<double, 3, 4> pose;
    double upper = 0;
    DistanceField::BoxGap gap;
  };
  mutable std::optional<LastGap> last_gap;  // none before the first
  // The face the shape's box last intersected (linkHitsObject): its next test's hint.
  mutable std::optional<std::size_t> last_hit_face;
};

// The exact gap of the box that holds `shape` (its enclosing_half, which it must have) as placed,
// as DistanceField::boxGapAndFace(pose, half, upper). With `gap_hints`
// (ClosingParams::gap_hints) the shape's last gap serves twice: at the same pose the answer is
// read from it when it holds one for `upper` (the contact patch asks again where the finger
// advance last asked), and elsewhere its face is the search's hint (the fast closing moves a link
// a few millimetres at a time, so that face mostly still is the closest, or nearly). The same gap
// and face either way.
DistanceField::BoxGap shapeBoxGap(const ShapeInstance& shape, const DistanceField& field,
                                  double upper, bool gap_hints);

// Pose of a placed shape (object frame).
inline Pose shapePose(const ShapeInstance& shape) {
  return Pose(shape.object->getTransform().matrix());
}

// A lower bound of the distance from a placed shape to the object: its covering spheres' field
// bounds (one field lookup per sphere).
double sphereCoverLowerBound(const ShapeInstance& shape, const DistanceField& field);

// A lower bound of the distance from a link to the object from the object's distance field: its
// covering spheres, then, for box shapes that may be within `needed`, the exact gap. At least
// `needed` when the link is provably that far. With `gap_hints` the exact gaps start from the
// shapes' last ones (shapeBoxGap).
double linkObjectGap(const std::vector<ShapeInstance>& link, const DistanceField& field,
                     double needed, bool gap_hints);

// Upper bound of how far any point of a link moves when the joints change by a given amount along
// a straight path in joint space: sum over the joints above the link of |change| times the
// joint's lever (revolute: the largest distance of the link's geometry from the axis, through the
// chain of joint origins for joints higher up; prismatic: 1). Built once per hand.
class MotionBounds {
 public:
  explicit MotionBounds(const HandModel& hand);
  double displacement(int link, const Eigen::VectorXd& joint_change) const;
  // Points (link frame) with a padding radius whose padded convex hull contains the link.
  const std::vector<std::pair<Eigen::Vector3d, double>>& hull(int link) const {
    return hulls_[link];
  }

 private:
  struct Lever {
    int joint;
    double radius;  // metres per radian (revolute) or 1 (prismatic)
  };
  std::vector<std::vector<Lever>> levers_;                              // per link
  std::vector<std::vector<std::pair<Eigen::Vector3d, double>>> hulls_;  // per link
};

// Gap lower bounds the fast closing keeps valid while links move (finger_advance.h): a gap found
// once, less the displacement bounds (motion_bounds.cpp) both links have moved since. A jump
// attempt recomputes a gap only when its bound would limit the jump, so far from contact the
// distance queries run once per closing instead of once per attempt.
struct GapBound {
  double gap;
  double moved_a, moved_b;  // the two links' summed displacement bounds when `gap` was found
  double current(double now_a, double now_b) const {
    return gap - (now_a - moved_a) - (now_b - moved_b);
  }
};

// The kept gap bounds of one closing at a time, per link pair (row-major, the lower link first)
// and per link. They live as long as the simulator, so that a closing neither allocates nor clears
// a table of every link pair: an entry counts only while its stamp is the current closing's.
class KeptGaps {
 public:
  explicit KeptGaps(std::size_t links) : pairs_(links * links), objects_(links) {}
  // Forgets every entry (the next closing's).
  void startClosing() { ++closing_; }
  // Nullptr when none was kept in this closing.
  const GapBound* pair(int first, int second) const { return kept(pairs_[index(first, second)]); }
  const GapBound* object(int link) const { return kept(objects_[link]); }
  void keepPair(int first, int second, const GapBound& bound) {
    pairs_[index(first, second)] = {closing_, bound};
  }
  void keepObject(int link, const GapBound& bound) { objects_[link] = {closing_, bound}; }

 private:
  struct Entry {
    std::uint64_t closing = 0;  // 0: never kept (closings count from 1)
    GapBound bound{};
  };
  std::size_t index(int first, int second) const {
    return static_cast<std::size_t>(first) * objects_.size() + second;
  }
  const GapBound* kept(const Entry& e) const { return e.closing == closing_ ? &e.bound : nullptr; }

  std::vector<Entry> pairs_, objects_;
  std::uint64_t closing_ = 0;
};

// FCL objects of the hand's link shapes, built once per simulator and moved by placeLink.
struct HandGeometry {
  explicit HandGeometry(const HandModel& hand);
  std::vector<std::vector<ShapeInstance>> shapes;  // per link
  std::vector<int> finger_links;                   // links of fingers that take part in collisions
  std::vector<int> static_links;                   // links with geometry outside every finger
  std::vector<std::vector<int>> links_of_finger;
  // Per finger, the joints (root to leaves) whose child link moves when that finger's drives do
  // (below a joint the drives, their followers or a mimic of them move): placing a finger updates
  // only these link poses.
  std::vector<std::vector<int>> joints_moved_by_finger;
  // Per joint: whether any finger's closing turns it (drives, followers, their mimics).
  std::vector<char> closing_joints;
  // Per finger, the joints a closing may turn on whose values its collision links' poses and its
  // drives' limits depend: the closing joints above its links, and its drives and followers.
  // While these keep their values, a step of the finger tests against the same link placements.
  std::vector<std::vector<int>> joints_placing_finger;
  MotionBounds motion;
  KeptGaps kept_gaps;  // the fast closing's, of the closing under way
};

void placeLink(const Pose& link_pose, std::vector<ShapeInstance>& shapes);
bool linksCollide(const std::vector<ShapeInstance>& a, const std::vector<ShapeInstance>& b,
                  std::size_t& queries);
// Whether a placed link intersects the object: its box shapes on the object's distance field
// (DistanceFieldParams::box_intersection_tests; the face a shape hit last is tested first), its
// other shapes, or all with that off, by FCL.
bool linkHitsObject(const std::vector<ShapeInstance>& link, const GraspObject& object,
                    std::size_t& queries);

// Link pairs (finger-finger of different fingers, finger-static) that are not checked while
// closing: those already intersecting in the preshape are attached by design (a finger mounted
// in the palm box); for the fast closing also those that provably never meet
// (allowSeparatedPairs).
class AllowedPairs {
 public:
  explicit AllowedPairs(std::size_t links = 0) : links_(links), flags_(links * links, 0) {}
  bool allowed(int a, int b) const { return flags_[a * links_ + b] != 0; }
  void allow(int a, int b) { flags_[a * links_ + b] = kIntersecting; }
  // Allowed because they intersect in the preshape (not because they never meet).
  bool intersecting(int a, int b) const { return flags_[a * links_ + b] == kIntersecting; }
  // Allowed because they provably never meet (allowSeparatedPairs).
  void allowSeparated(int a, int b) { flags_[a * links_ + b] = kSeparated; }

 private:
  static constexpr char kIntersecting = 1, kSeparated = 2;
  std::size_t links_;
  std::vector<char> flags_;
};

// The hand's shapes must be placed at the preshape.
AllowedPairs allowedLinkPairs(const HandModel& hand, const HandGeometry& geometry,
                              std::size_t& queries);

// The fast closing also skips link pairs that provably never meet while the fingers close from
// `start`: when every joint the closing moves between the two links (below their common ancestor)
// is revolute about parallel axes (direction u), no point of either link changes its coordinate
// along u, so links whose extents along u are apart stay apart at any joint values (adjacent
// ARMAR-III fingers: 7 mm apart across their flexion axes). Those pairs are marked separated:
// the checked steps of the fast closing skip their collision tests (FCL queries of the fast
// closing in FastClosing.AgreesWithStepwise...: ARMAR-III 484 k -> 113 k).
void allowSeparatedPairs(const HandModel& hand, const HandGeometry& geometry,
                         const Eigen::VectorXd& start, AllowedPairs& allowed);

struct AdvanceSettings {
  ClosingMethod method = ClosingMethod::kFast;
  double step_rad = 0.02;
  double step_m = 0.0005;
  int max_passes = 10;
  int max_iterations_per_pass = 5000;
  // ClosingParams::jump_stops_at_blocking_link (fast closing only).
  bool jump_stops_at_blocking_link = true;
  // ClosingParams::skip_repeated_refusals (fast closing only).
  bool skip_repeated_refusals = true;
  // ClosingParams::gap_hints (fast closing only).
  bool gap_hints = true;
};

struct AdvanceResult {
  Eigen::VectorXd joints;
  std::vector<char> touched;  // per link: blocked by the object at some point
  int iterations = 0;
  int passes = 0;
};

// Advances every finger drive step by step from `start` (already normalised, collision-free)
// until each is blocked or at its limits; kFast jumps over the steps that provably stay clear. The
// finger links are placed at the result on return.
AdvanceResult advanceFingers(const HandModel& hand, HandGeometry& geometry,
                             const GraspObject& object, const Pose& hand_pose,
                             const AllowedPairs& allowed, const Eigen::VectorXd& start,
                             const AdvanceSettings& settings, std::size_t& queries);

// The contacts of one link (placed at `link_pose`) with the object: one at the centre of its
// touching patch, or with `corner_contacts` the corners of a wide patch
// (4 mm or more; up to four); none when the link is farther than `max_distance` (finite, >= 0).
// kFast finds the same gap and patch from the object's distance field and exact queries near the
// surface instead of FCL and CGAL (its exact box gaps with the shapes' hints when `gap_hints`).
std::vector<Contact> contactPatch(const HandModel& hand, const std::vector<ShapeInstance>& shapes,
                                  int link, const Pose& link_pose, const GraspObject& object,
                                  bool palm, double max_distance, ClosingMethod method,
                                  bool corner_contacts, bool gap_hints, std::size_t& queries);

std::vector<Eigen::Vector3d> surfaceSamples(const CollisionShape& shape);
std::vector<std::pair<Eigen::Vector3d, double>> sphereCover(const CollisionShape& shape);
double boundingRadius(const CollisionShape& shape);

}  // namespace skelgrasp::grasping::internal
