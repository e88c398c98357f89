#pragma once
// A world of the engine (bullet_scene.cpp) holding the hand as a fixed-base multibody and the
// object as a free rigid body. Bullet's types stay in the .cpp files of physics/src.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "skelgrasp/common/pose.h"
#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/physics/execution.h"
#include "skelgrasp/physics/physical_object.h"

namespace skelgrasp::physics::internal {

// How a hand joint is driven.
struct JointDrive {
  enum class Mode {
    kFixed,  // not driven (fixed joints)
    kClose,  // a servo at `velocity` towards closing, its torque saturating at torque_limit
    kHold,   // a spring-damper towards `target` (PD torque, saturating at torque_limit)
  };
  Mode mode = Mode::kFixed;
  double velocity = 0;        // kClose: the signed closing speed (rad/s or m/s)
  double closing_torque = 0;  // kClose: the servo's torque limit while closing
  double target = 0;          // kHold: the position the spring pulls to (rad or m)
  double stiffness = 0;       // kHold: N m/rad (or N/m); the scene lowers it where the engine's
                              // step would not resolve it (Scene::holdStiffness)
  double torque_limit = 0;    // N m (revolute) or N (prismatic)
};

// The object's rigid-body state in the world (world = the object frame at the grasp).
struct ObjectState {
  bool fixed = false;            // held where it is (a static body): the fingers close against it
  Pose pose = Pose::Identity();  // object frame in the world
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();  // of the centre of mass
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
};

// Everything an execution needs to restart from a state: the hand's joints and the object's.
struct SceneState {
  Eigen::VectorXd joints;
  Eigen::VectorXd joint_velocities;
  ObjectState object;
};

class Scene {
 public:
  // The hand's root at `hand_pose` (world), its joints at `state.joints`, driven by `drives` (one
  // per hand joint); the object (none: a hand alone) at `state.object`.
  Scene(const grasping::HandModel& hand, const Pose& hand_pose,
        const std::vector<JointDrive>& drives, const PhysicalObject* object,
        const SceneState& state, const JudgeParams& params);
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  // A constant force on the object's centre of mass (N, world).
  void setObjectForce(const Eigen::Vector3d& force);
  void step();
  // Changes how hand joint `joint` is driven from the next step on (a closing joint that stopped
  // becomes a hold; a kFixed joint stays undriven).
  void setDrive(int joint, const JointDrive& drive);
  // Speed of hand joint `joint` (rad/s or m/s).
  double jointSpeed(int joint) const;
  // The stiffness a hold of joint `joint` gets when `requested` is asked for: at most what the
  // time step resolves stably for the links the joint moves.
  double holdStiffness(int joint, double requested) const;

  SceneState state() const;
  ObjectState objectState() const;
  // Pose of every hand link in the world (the multibody's forward kinematics).
  std::vector<Pose> linkPoses() const;
  // Hand links with a contact point on the object within `distance_m` after the last step.
  std::vector<int> touchingLinks(double distance_m) const;
  // Largest joint speed of the hand (rad/s or m/s).
  double maxJointSpeed() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace skelgrasp::physics::internal
