// How far a link can move when joints turn: the lever of every joint above a link, for the
// conservative advancement of the fast closing.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "simulator_internal.h"

namespace skelgrasp::grasping::internal {
namespace {

// Points (with a padding radius) whose padded convex hull contains the shape, in the link frame.
void addHullPoints(const CollisionShape& shape,
                   std::vector<std::pair<Eigen::Vector3d, double>>& out) {
  const auto put = [&](const Eigen::Vector3d& p, double pad) {
    out.emplace_back(shape.origin * p, pad);
  };
  switch (shape.type) {
    case ShapeType::kBox:
      for (int c = 0; c < 8; ++c) {
        const Eigen::Vector3d sign((c & 1) ? 1 : -1, (c & 2) ? 1 : -1, (c & 4) ? 1 : -1);
        put(0.5 * shape.box_size.cwiseProduct(sign), 0);
      }
      break;
    case ShapeType::kSphere:
      put(Eigen::Vector3d::Zero(), shape.radius);
      break;
    case ShapeType::kCylinder:
      for (double z : {-0.5, 0.5}) put(Eigen::Vector3d(0, 0, z * shape.length), shape.radius);
      break;
    case ShapeType::kMesh: {
      Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
      Eigen::Vector3d hi = -lo;
      for (const auto& v : shape.mesh->vertices) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
      }
      for (int c = 0; c < 8; ++c) {
        put(Eigen::Vector3d((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(),
                            (c & 4) ? hi.z() : lo.z()),
            0);
      }
      break;
    }
  }
}

}  // namespace

MotionBounds::MotionBounds(const HandModel& hand)
    : levers_(hand.links().size()), hulls_(hand.links().size()) {
  const auto& links = hand.links();
  const auto& joints = hand.joints();
  for (std::size_t l = 0; l < links.size(); ++l) {
    auto& hull = hulls_[l];
    for (const auto& shape : links[l].shapes) addHullPoints(shape, hull);
    if (hull.empty()) continue;
    // Largest distance of the link's geometry from the origin of the current frame (the link's,
    // then each ancestor's): bounds its distance from any axis through that origin.
    double reach = 0;
    for (const auto& [p, pad] : hull) reach = std::max(reach, p.norm() + pad);
    bool direct = true;
    for (int link = static_cast<int>(l); links[link].parent_joint >= 0;) {
      const Joint& joint = joints[links[link].parent_joint];
      if (joint.type == JointType::kRevolute) {
        double radius = reach;
        if (direct) {
          // The axis passes through the link's own origin: the exact distance from the axis.
          const Eigen::Vector3d axis = joint.axis.normalized();
          radius = 0;
          for (const auto& [p, pad] : hull)
            radius = std::max(radius, (p - p.dot(axis) * axis).norm() + pad);
        }
        levers_[l].push_back({links[link].parent_joint, radius});
      } else if (joint.type == JointType::kPrismatic) {
        levers_[l].push_back({links[link].parent_joint, 1.0});
        reach += std::max(std::abs(joint.lower), std::abs(joint.upper));
      }
      // The joint's own frame sits at its origin in the parent link: the geometry is at most
      // that much farther from the parent's origin (it can swing about it).
      reach += joint.origin.translation().norm();
      direct = false;
      link = joint.parent_link;
    }
  }
}

double MotionBounds::displacement(int link, const Eigen::VectorXd& joint_change) const {
  double bound = 0;
  for (const auto& lever : levers_[link])
    bound += std::abs(joint_change[lever.joint]) * lever.radius;
  return bound;
}

namespace {

// Links this close along the common axis count as meeting (FCL's collision tolerance is far
// below it).
constexpr double kSeparationMarginM = 1e-6;
// Axes whose directions differ by less than this (sine of the angle) are parallel.
constexpr double kParallelTolerance = 1e-9;

// Joints from the root down to `link`.
std::vector<int> chainOf(const HandModel& hand, int link) {
  std::vector<int> chain;
  for (int j = hand.links()[link].parent_joint; j >= 0;
       j = hand.links()[hand.joints()[j].parent_link].parent_joint) {
    chain.push_back(j);
  }
  return {chain.rbegin(), chain.rend()};
}

}  // namespace

void allowSeparatedPairs(const HandModel& hand, const HandGeometry& geometry,
                         const Eigen::VectorXd& start, AllowedPairs& allowed) {
  const std::vector<char>& moves = geometry.closing_joints;
  const std::vector<Pose> poses = hand.linkPoses(start);
  const auto& joints = hand.joints();
  std::vector<std::vector<int>> chains(hand.links().size());
  for (std::size_t l = 0; l < chains.size(); ++l) chains[l] = chainOf(hand, static_cast<int>(l));

  const auto separated = [&](int a, int b) {
    const auto &ca = chains[a], &cb = chains[b];
    std::size_t common = 0;
    while (common < ca.size() && common < cb.size() && ca[common] == cb[common]) ++common;
    std::optional<Eigen::Vector3d> u;
    for (const auto* chain : {&ca, &cb}) {
      for (std::size_t i = common; i < chain->size(); ++i) {
        const int j = (*chain)[i];
        if (!moves[j]) continue;
        if (joints[j].type != JointType::kRevolute) return false;
        const Eigen::Vector3d axis =
            ((poses[joints[j].parent_link] * joints[j].origin).linear() * joints[j].axis)
                .normalized();
        if (!u) u = axis;
        if (axis.cross(*u).norm() > kParallelTolerance) return false;
      }
    }
    // No joint moves one against the other: they keep the preshape's relative pose, in which
    // they do not intersect (intersecting pairs are allowed already).
    if (!u) return true;
    const auto extent = [&](int link) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const auto& [p, pad] : geometry.motion.hull(link)) {
        const double x = u->dot(poses[link] * p);
        lo = std::min(lo, x - pad);
        hi = std::max(hi, x + pad);
      }
      return std::make_pair(lo, hi);
    };
    const auto [alo, ahi] = extent(a);
    const auto [blo, bhi] = extent(b);
    return ahi + kSeparationMarginM < blo || bhi + kSeparationMarginM < alo;
  };
  for (int l : geometry.finger_links) {
    for (int other : geometry.finger_links) {
      if (hand.fingerOfLink(other) != hand.fingerOfLink(l) && !allowed.allowed(l, other) &&
          separated(l, other))
        allowed.allowSeparated(l, other);
    }
    for (int s : geometry.static_links) {
      if (!allowed.allowed(l, s) && separated(l, s)) allowed.allowSeparated(l, s);
    }
  }
}

}  // namespace skelgrasp::grasping::internal
