#pragma once
// The physics judge: one grasp executed in a rigid-body simulation (Bullet, docs/physics.md).
// The hand is welded at the grasp pose in its preshape; every finger joint is driven towards its
// closing direction by torque-limited position control until it stops at the object (held where
// it is meanwhile, as the planners assume) or its limit, then grips; the object, a free body, is
// let go and settles; then its weight (or a given force) pulls it along +-x, +-y, +-z in turn, each
// from the settled state. The grasp holds when the object moves less than a bound and turns less
// than another relative to the hand in all six.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/pose.h"
#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/physics/physical_object.h"

namespace skelgrasp::physics {

// The judge's default friction: the planners' and r's mu.
inline constexpr double kDefaultFriction = 0.35;
// Standard gravity (m/s^2): the default disturbance is the object's weight.
inline constexpr double kStandardGravity = 9.81;

struct JudgeParams {
  // Coulomb friction between fingers and object (>= 0).
  double friction = kDefaultFriction;
  // Magnitude of the disturbance force (N, > 0). Unset: the object's weight, mass x 9.81.
  std::optional<double> disturbance_force_n;
  // Longest time the fingers close before the disturbances start (s); the closing ends earlier
  // once every finger joint has stopped (settled).
  double closing_time_s = 1.5;
  // How long each disturbance pulls (s). A direction ends earlier once the object has stayed put
  // over a window of `still_time_s` (it moved, at its centre of mass and at its largest radius by
  // the turn, less than still_speed x still_time: under a constant force nothing changes after
  // that), or once it has moved or turned past the bounds. The closing ends the same way once
  // every finger joint has stopped.
  double disturbance_time_s = 1.0;
  double still_time_s = 0.1;
  double still_speed_m_s = 0.004;
  // The hold criterion, relative to the settled pose (DexGraspBench's bounds).
  double max_displacement_m = 0.02;
  double max_rotation_rad = radiansFromDegrees(15.0);
  // An open hand penetrating the object deeper than this at the start fails (m).
  double max_start_penetration_m = 0.001;
  // Finger force limit at the fingertip (N, > 0) that sets each finger joint's torque limit:
  // torque = force x the joint's lever to its fingertip (grasping/hand_strength.h). Unset: the
  // hand's description's, else grasping::kDefaultFingertipForceN.
  std::optional<double> fingertip_force_n;
  // Closing speed of the finger joints (rad/s; prismatic joints: closing_speed x 0.05 m/s): a
  // finger that meets nothing reaches its limit well within closing_time_s.
  double closing_speed_rad_s = 2.0;
  // Engine integration step (s) and constraint solver iterations per step.
  double time_step_s = 1.0 / 250.0;
  int solver_iterations = 30;
};

// Where an execution failed.
enum class ExecutionPhase {
  kNone,         // it held
  kStart,        // the open hand penetrates the object (start_penetration_m)
  kClosing,      // the fingers closed without holding the object (no finger contact at the end,
                 // or it was pushed out of the hand while closing)
  kDisturbance,  // the object moved or turned past the bounds under a disturbance
};
const char* toString(ExecutionPhase phase);

struct DisturbanceResult {
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // unit, object frame at the grasp
  double displacement_m = 0;  // centre of mass, from the settled pose, at the end
  double rotation_rad = 0;
  double simulated_s = 0;  // until decided (held still, moved out, or the full time)
  bool held = false;
};

struct ExecutionResult {
  bool holds = false;
  ExecutionPhase failed_phase = ExecutionPhase::kNone;
  std::string reason;  // one line for a user: what failed and where
  // Deepest penetration of an open hand's link into the object at the start (m, >= 0), and that
  // link's name.
  double start_penetration_m = 0;
  std::string penetrating_link;
  // The closing and release: how far the object moved when the closed hand let it go (it is held
  // while the fingers close), the links touching it once it settled and the joints reached.
  double closing_displacement_m = 0;
  double closing_rotation_rad = 0;
  std::vector<std::string> touching_links;
  Eigen::VectorXd joints;
  // +x, -x, +y, -y, +z, -z; empty when the execution failed before the disturbances.
  std::vector<DisturbanceResult> disturbances;
  int steps = 0;     // engine steps in all
  double cpu_s = 0;  // thread CPU time of the execution
  // Where the time went: thread CPU time and engine steps of each phase (the start test takes no
  // steps; the release is the closed hand letting the object go).
  struct PhaseCost {
    double cpu_s = 0;
    int steps = 0;
  };
  PhaseCost start_cost, closing_cost, release_cost, disturbance_cost;
};

// The torque limit of every joint of `hand` (N m, or N for prismatic joints; 0 for fixed joints)
// under `params` (its fingertip force, else the hand's description's, else the default):
// grasping::jointTorqueLimits.
std::vector<double> jointTorqueLimits(const grasping::HandModel& hand, const JudgeParams& params);

// Executes the grasp of `preshape` with the hand root at `hand_pose` (object frame). Throws
// InvalidArgument for parameters outside the ranges above. Deterministic: the same inputs give the
// same result on any thread.
ExecutionResult executeGrasp(const grasping::HandModel& hand, const PhysicalObject& object,
                             const Pose& hand_pose, const grasping::Preshape& preshape,
                             const JudgeParams& params = {});

// The pose of every link of `hand` (world frame) as the engine places them with the root at
// `hand_pose` and the joints at `joints` (all joints, as HandModel::linkPoses takes them): the same
// poses, which the tests check for every built-in hand. Throws InvalidArgument for a joint vector
// of another size.
std::vector<Pose> engineLinkPoses(const grasping::HandModel& hand, const Pose& hand_pose,
                                  const Eigen::VectorXd& joints);

}  // namespace skelgrasp::physics
