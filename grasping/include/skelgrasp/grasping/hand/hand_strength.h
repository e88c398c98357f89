#pragma once
// How strongly a hand's fingers can press: each joint's torque limit from a force at the
// fingertip (HandModel::strength(), docs/physics.md, "Finger strength"). The physics judge drives
// the joints with these limits, and the load capacity of a grasp (load_capacity.h) bounds its
// contact forces by them.
#include <optional>
#include <vector>

#include "skelgrasp/grasping/hand/hand_model.h"

namespace skelgrasp::grasping {

// A conservative fingertip force (N) for hands whose datasheet gives none: a judge stronger than
// the real hand proves nothing.
inline constexpr double kDefaultFingertipForceN = 5.0;

// A closed hand grips with this share of each joint's torque limit and keeps the rest in reserve
// for a load that pulls on a finger: the physics judge's grips, and the share of the limits a
// grasp's load check may draw on (load_capacity.h).
inline constexpr double kGripTorqueShare = 0.5;

// The fingertip force of `hand`: `override_n` when set, else the hand's description, else
// kDefaultFingertipForceN.
double fingertipForceN(const HandModel& hand, std::optional<double> override_n = std::nullopt);

// The torque limit of every joint (N m; prismatic joints: N; fixed joints: 0): the fingertip force
// times the joint's lever, the farthest point of the links it moves from its axis, at the hand's
// zero configuration (prismatic joints: the force itself).
std::vector<double> jointTorqueLimits(const HandModel& hand,
                                      std::optional<double> fingertip_force_n = std::nullopt);

}  // namespace skelgrasp::grasping
