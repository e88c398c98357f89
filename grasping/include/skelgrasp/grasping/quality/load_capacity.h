#pragma once
// The load capacity of a grasp: how many times its own weight the object can hang in each of the
// six directions +-x, +-y, +-z before the contacts must slip or a finger joint exceed its torque
// limit (docs/ranking.md, "Load check"). Force closure alone assumes fingers of unbounded
// strength: a fingertip pressing a few newtons far from the centre of mass holds the closure but
// not the object. This is the physics judge's disturbance test as a linear program on the grasp's
// contacts: the best contact forces within the friction cones (the hand's soft-finger torsion
// included) and within every joint's torque limit (hand_strength.h); the palm's links, welded to
// the arm, push as hard as needed.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/common/pose.h"
#include "skelgrasp/grasping/contact.h"
#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/grasping/quality/quality.h"

namespace skelgrasp::grasping {

// The object's mass the capacity is measured against by default: the physics judge's.
inline constexpr double kDefaultLoadMassKg = 0.1;
inline constexpr double kStandardGravityMS2 = 9.81;

struct LoadCapacityParams {
  double mass_kg = kDefaultLoadMassKg;  // > 0
  // Unset: the hand's (hand_strength.h).
  std::optional<double> fingertip_force_n;
  // The share of each joint's torque limit the contact forces may draw on, in (0, 1]: 1 for what
  // the hand could do at full strength, kGripTorqueShare for what its grip holds without reserve.
  // Closing joints (a finger's drives, their followers and the mimics of either) supply torque
  // towards closing only: a finger presses, it does not pull. Other joints turn either way.
  double torque_share = 1.0;
  // The capacity is reported up to this many weights (a grasp that reaches it in every direction
  // holds by the palm's and the friction cones' geometry alone).
  double max_capacity = 10.0;
};

struct LoadCapacity {
  // Weights the grasp can hang along +x, -x, +y, -y, +z, -z (object frame), each in
  // [0, max_capacity]; `min` the least of them.
  std::array<double, 6> per_direction{};
  double min = 0;
  std::string error;  // non-empty when an LP failed (the capacity then means nothing)

  // Whether the grasp carries the object's weight in every direction: the load check's verdict.
  bool carries() const { return error.empty() && min >= 1.0; }
};

// `contacts` in the object frame as the closing reached them with the hand root at `hand_pose`
// (object frame) and its joints at `joints`; `center_of_mass` where the weight acts; `quality`'s
// friction, cone edges and torsional friction (already resolved for the hand). Throws
// InvalidArgument for a mass or max_capacity that is not positive, a joint vector of another size,
// or a contact on a link the hand does not have.
LoadCapacity loadCapacity(const HandModel& hand, const Pose& hand_pose,
                          const Eigen::VectorXd& joints, const std::vector<Contact>& contacts,
                          const Eigen::Vector3d& center_of_mass, const QualityParams& quality,
                          const LoadCapacityParams& params = {});

}  // namespace skelgrasp::grasping
