// Finger advance of GraspSimulator::close: the hand's FCL geometry, the link pairs allowed to
// intersect, and the step-by-step closing of the reference implementation (fact sheet §8).
#include <algorithm>
#include <cmath>
#include <limits>

#include "finger_advance.h"

namespace skelgrasp::grasping {

const char* toString(ClosingMethod method) {
  return method == ClosingMethod::kStepwise ? "stepwise" : "fast";
}

ClosingMethod parseClosingMethod(const std::string& text) {
  if (text == "stepwise") return ClosingMethod::kStepwise;
  if (text == "fast") return ClosingMethod::kFast;
  throw InvalidArgument("unknown closing method '" + text + "' (use stepwise or fast)");
}

const char* toString(ContactPatch patch) {
  return patch == ContactPatch::kCentre ? "centre" : "corners";
}

ContactPatch parseContactPatch(const std::string& text) {
  if (text == "centre") return ContactPatch::kCentre;
  if (text == "corners") return ContactPatch::kCorners;
  throw InvalidArgument("unknown contact patch model '" + text + "' (use centre or corners)");
}

ContactPatch contactPatchFor(const std::string& text, bool reference_compat) {
  const ContactPatch asked = parseContactPatch(text);  // a typing mistake is one either way
  return reference_compat ? ContactPatch::kCentre : asked;
}

}  // namespace skelgrasp::grasping

namespace skelgrasp::grasping::internal {

namespace {

// The joints a finger's closing turns: its drives, their followers and every joint that mimics
// one of them (to a fixed point: a mimic of a mimic).
std::vector<char> jointsTurnedBy(const HandModel& hand, const Finger& finger) {
  std::vector<char> turns(hand.joints().size(), 0);
  for (const auto& drive : finger.drives) {
    turns[drive.joint] = 1;
    for (const auto& [joint, ratio] : drive.followers) turns[joint] = 1;
  }
  for (bool grew = true; grew;) {
    grew = false;
    for (std::size_t j = 0; j < turns.size(); ++j) {
      const int of = hand.joints()[j].mimic_of;
      if (!turns[j] && of >= 0 && turns[of]) {
        turns[j] = 1;
        grew = true;
      }
    }
  }
  return turns;
}

}  // namespace

HandGeometry::HandGeometry(const HandModel& hand) : motion(hand), kept_gaps(hand.links().size()) {
  const auto& links = hand.links();
  shapes.resize(links.size());
  links_of_finger.resize(hand.fingers().size());
  for (std::size_t l = 0; l < links.size(); ++l) {
    for (const auto& shape : links[l].shapes) {
      ShapeInstance instance;
      instance.geometry = toFclGeometry(shape);
      instance.object = std::make_unique<fcl::CollisionObjectd>(instance.geometry);
      instance.origin = shape.origin;
      instance.bounding_radius = boundingRadius(shape);
      instance.surface_samples = surfaceSamples(shape);
      instance.sphere_cover = sphereCover(shape);
      instance.is_box = shape.type == ShapeType::kBox;
      if (instance.is_box) instance.enclosing_half = 0.5 * shape.box_size;
      if (shape.type == ShapeType::kCylinder)
        instance.enclosing_half = Eigen::Vector3d(shape.radius, shape.radius, 0.5 * shape.length);
      if (shape.type == ShapeType::kSphere)
        instance.enclosing_half = Eigen::Vector3d::Constant(shape.radius);
      shapes[l].push_back(std::move(instance));
    }
    if (shapes[l].empty()) continue;
    const int link = static_cast<int>(l);
    const int finger = hand.fingerOfLink(link);
    if (finger < 0) {
      static_links.push_back(link);
    } else if (hand.modeOfLink(link) != CollisionMode::kNone) {
      finger_links.push_back(link);
      links_of_finger[finger].push_back(link);
    }
  }
  const auto& joints = hand.joints();
  closing_joints.assign(joints.size(), 0);
  for (const auto& finger : hand.fingers()) {
    const std::vector<char> turns = jointsTurnedBy(hand, finger);
    // A joint below a turned one moves its child link too.
    std::vector<char> link_moves(links.size(), 0);
    std::vector<int> order;
    for (int j : hand.jointOrder()) {
      closing_joints[j] = closing_joints[j] || turns[j];
      if (turns[j] || link_moves[joints[j].parent_link]) {
        link_moves[joints[j].child_link] = 1;
        order.push_back(j);
      }
    }
    joints_moved_by_finger.push_back(std::move(order));
  }
  // The joint above each link (-1 at the root), to walk each finger link's chain.
  std::vector<int> joint_above(links.size(), -1);
  for (std::size_t j = 0; j < joints.size(); ++j)
    joint_above[joints[j].child_link] = static_cast<int>(j);
  for (std::size_t f = 0; f < hand.fingers().size(); ++f) {
    std::vector<char> watched(joints.size(), 0);
    for (int l : links_of_finger[f]) {
      for (int j = joint_above[l]; j >= 0; j = joint_above[joints[j].parent_link])
        watched[j] = watched[j] || closing_joints[j];
    }
    for (const auto& drive : hand.fingers()[f].drives) {
      watched[drive.joint] = 1;
      for (const auto& [joint, ratio] : drive.followers) watched[joint] = 1;
    }
    std::vector<int> list;
    for (std::size_t j = 0; j < joints.size(); ++j) {
      if (watched[j]) list.push_back(static_cast<int>(j));
    }
    joints_placing_finger.push_back(std::move(list));
  }
}

void placeLink(const Pose& link_pose, std::vector<ShapeInstance>& shapes) {
  for (auto& s : shapes) {
    s.object->setTransform(toFcl(link_pose * s.origin));
    s.object->computeAABB();
  }
}

namespace {

bool collide(const fcl::CollisionObjectd& a, const fcl::CollisionObjectd& b, std::size_t& queries) {
  if (!a.getAABB().overlap(b.getAABB())) return false;
  ++queries;
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  fcl::collide(&a, &b, request, result);
  return result.isCollision();
}

// A shape whose covering spheres are provably this far from the object intersects it by no test:
// far above the rounding of FCL's (GJK's) verdicts at touching.
constexpr double kProvablyClearOfFclM = 1e-5;

// Exact box gaps are asked up to this distance: farther, the covering spheres' bound suffices and
// the query would scan every triangle within reach.
constexpr double kExactGapReachM = 0.01;

}  // namespace

double sphereCoverGap(const ShapeInstance& a, const ShapeInstance& b) {
  const Pose pose_a = shapePose(a), pose_b = shapePose(b);
  double gap = std::numeric_limits<double>::infinity();
  for (const auto& [ca, ra] : a.sphere_cover) {
    const Eigen::Vector3d centre = pose_a * ca;
    for (const auto& [cb, rb] : b.sphere_cover)
      gap = std::min(gap, (centre - pose_b * cb).norm() - ra - rb);
  }
  return gap;
}

bool linksCollide(const std::vector<ShapeInstance>& a, const std::vector<ShapeInstance>& b,
                  std::size_t& queries) {
  for (const auto& sa : a) {
    for (const auto& sb : b) {
      if (collide(*sa.object, *sb.object, queries)) return true;
    }
  }
  return false;
}

bool linkHitsObject(const std::vector<ShapeInstance>& link, const GraspObject& object,
                    std::size_t& queries) {
  const auto& collision = object.collisionData();
  const bool field_tests = object.fieldParams().box_intersection_tests;
  for (const auto& s : link) {
    const bool mesh = s.geometry->getObjectType() == fcl::OT_BVH;
    const fcl::CollisionObjectd& other = mesh ? collision.distanceObject() : *collision.obb_object;
    if (!field_tests) {
      if (collide(*s.object, other, queries)) return true;
      continue;
    }
    // The object's box first, as FCL does; then the covering spheres' field bounds, which clear
    // a shape a centimetre or more away in a few lookups, where the field's exact test would
    // walk every cell around a long finger box. With a margin over the rounding of FCL's test.
    if (!s.object->getAABB().overlap(other.getAABB())) continue;
    const DistanceField& field = object.distanceField();
    if (sphereCoverLowerBound(s, field) > kProvablyClearOfFclM) continue;
    if (s.is_box) {
      ++queries;
      const std::optional<std::size_t> face =
          field.boxIntersection(shapePose(s), *s.enclosing_half, s.last_hit_face);
      if (face) {
        s.last_hit_face = face;
        return true;
      }
      continue;
    }
    if (collide(*s.object, other, queries)) return true;
  }
  return false;
}

double sphereCoverLowerBound(const ShapeInstance& shape, const DistanceField& field) {
  const Pose pose = shapePose(shape);
  double bound = std::numeric_limits<double>::infinity();
  for (const auto& [centre, radius] : shape.sphere_cover)
    bound = std::min(bound, field.lowerBound(pose * centre) - radius);
  return bound;
}

DistanceField::BoxGap shapeBoxGap(const ShapeInstance& shape, const DistanceField& field,
                                  double upper, bool gap_hints) {
  SKELGRASP_DEMAND(shape.enclosing_half.has_value());
  const Pose pose = shapePose(shape);
  if (!gap_hints) return field.boxGapAndFace(pose, *shape.enclosing_half, upper);
  auto& last = shape.last_gap;
  const bool same_pose = last && last->pose == pose.matrix().topRows<3>();
  if (same_pose) {
    // A gap found at or below `upper` is the answer; a search to a larger bound that found none
    // says the gap is beyond `upper` too (boxGapAndFace answers `upper`, no face).
    if (last->gap.face && last->gap.distance <= upper) return last->gap;
    if (!last->gap.face && upper <= last->upper) return {upper, std::nullopt};
  }
  const std::optional<std::size_t> hint = last ? last->gap.face : std::nullopt;
  const DistanceField::BoxGap gap = field.boxGapAndFace(pose, *shape.enclosing_half, upper, hint);
  // A search that found no face elsewhere is not kept: the face of the last one is the better hint.
  if (gap.face || !hint || same_pose) last = {pose.matrix().topRows<3>(), upper, gap};
  return gap;
}

double linkObjectGap(const std::vector<ShapeInstance>& link, const DistanceField& field,
                     double needed, bool gap_hints) {
  // The spheres cost a field lookup each; the exact box gap (tens of microseconds) only runs for
  // shapes that may be within `needed`, where the spheres' slack (their bulge beyond the shape
  // plus the field's interpolation bound) would stop the advance millimetres early.
  double gap = std::numeric_limits<double>::infinity();
  for (const auto& s : link) {
    double shape_gap = sphereCoverLowerBound(s, field);
    // The exact gap is asked only up to kExactGapReachM: beyond it, it cannot raise the bound.
    const double exact_upper = std::min(needed, kExactGapReachM);
    if (shape_gap < exact_upper && s.enclosing_half) {
      const DistanceField::BoxGap exact = shapeBoxGap(s, field, exact_upper, gap_hints);
      shape_gap = std::max(shape_gap, exact.distance);
    }
    gap = std::min(gap, shape_gap);
  }
  return gap;
}

AllowedPairs allowedLinkPairs(const HandModel& hand, const HandGeometry& geometry,
                              std::size_t& queries) {
  AllowedPairs allowed(hand.links().size());
  const auto& shapes = geometry.shapes;
  for (int l : geometry.finger_links) {
    for (int other : geometry.finger_links) {
      if (hand.fingerOfLink(other) != hand.fingerOfLink(l) &&
          linksCollide(shapes[l], shapes[other], queries)) {
        allowed.allow(l, other);
      }
    }
    for (int s : geometry.static_links) {
      if (linksCollide(shapes[l], shapes[s], queries)) allowed.allow(l, s);
    }
  }
  return allowed;
}

AdvanceResult advanceFingers(const HandModel& hand, HandGeometry& geometry,
                             const GraspObject& object, const Pose& hand_pose,
                             const AllowedPairs& allowed, const Eigen::VectorXd& start,
                             const AdvanceSettings& settings, std::size_t& queries) {
  FingerAdvance advance(hand, geometry, object, hand_pose, allowed, start, queries);
  return advance.run(settings);
}

}  // namespace skelgrasp::grasping::internal
