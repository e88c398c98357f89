#include "skelgrasp/grasping/hand/hand_strength.h"

#include <algorithm>

namespace skelgrasp::grasping {
namespace {

// Every link below `link` in the tree (itself included).
std::vector<int> subtreeLinks(const HandModel& hand, int link) {
  std::vector<int> links = {link};
  for (std::size_t k = 0; k < links.size(); ++k) {
    for (const auto& joint : hand.joints()) {
      if (joint.parent_link == links[k]) links.push_back(joint.child_link);
    }
  }
  return links;
}

// The corners of a link shape's bounding box in the link frame.
std::vector<Eigen::Vector3d> shapeCorners(const CollisionShape& shape) {
  Eigen::Vector3d half = Eigen::Vector3d::Zero();
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  switch (shape.type) {
    case ShapeType::kBox:
      half = 0.5 * shape.box_size;
      break;
    case ShapeType::kSphere:
      half = Eigen::Vector3d::Constant(shape.radius);
      break;
    case ShapeType::kCylinder:
      half = Eigen::Vector3d(shape.radius, shape.radius, 0.5 * shape.length);
      break;
    case ShapeType::kMesh: {
      const AxisAlignedBox box = shape.mesh->bounds();
      half = 0.5 * box.extent();
      centre = box.center();
      break;
    }
  }
  std::vector<Eigen::Vector3d> corners;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d sign((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
    corners.push_back(shape.origin * (centre + sign.cwiseProduct(half)));
  }
  return corners;
}

}  // namespace

double fingertipForceN(const HandModel& hand, std::optional<double> override_n) {
  return override_n.value_or(hand.strength().fingertip_force_n.value_or(kDefaultFingertipForceN));
}

std::vector<double> jointTorqueLimits(const HandModel& hand,
                                      std::optional<double> fingertip_force_n) {
  const double force = fingertipForceN(hand, fingertip_force_n);
  const auto& joints = hand.joints();
  const auto poses = hand.linkPoses(hand.zeroConfiguration());
  std::vector<double> limits(joints.size(), 0.0);
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const auto& joint = joints[j];
    if (!joint.movable()) continue;
    if (joint.type == JointType::kPrismatic) {
      limits[j] = force;
      continue;
    }
    const Pose frame = poses[joint.parent_link] * joint.origin;
    const Eigen::Vector3d axis = (frame.linear() * joint.axis).normalized();
    double lever = 0;
    for (int link : subtreeLinks(hand, joint.child_link)) {
      for (const auto& shape : hand.links()[link].shapes) {
        for (const auto& corner : shapeCorners(shape)) {
          const Eigen::Vector3d r = poses[link] * corner - frame.translation();
          lever = std::max(lever, (r - r.dot(axis) * axis).norm());
        }
      }
    }
    limits[j] = force * lever;
  }
  return limits;
}

}  // namespace skelgrasp::grasping
