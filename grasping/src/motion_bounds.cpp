// How far a link can move when joints turn: the lever of every joint above a link, for the
// conservative advancement of the fast closing.
#include <cmath>

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

MotionBounds::MotionBounds(const HandModel& hand) : levers_(hand.links().size()) {
  const auto& links = hand.links();
  const auto& joints = hand.joints();
  for (std::size_t l = 0; l < links.size(); ++l) {
    std::vector<std::pair<Eigen::Vector3d, double>> hull;
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

}  // namespace skelgrasp::grasping::internal
