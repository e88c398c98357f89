#include "bullet_scene.h"

#include <BulletCollision/Gimpact/btGImpactCollisionAlgorithm.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointMotor.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "bullet_shapes.h"
#include "skelgrasp/common/error.h"

namespace skelgrasp::physics::internal {
namespace {

using grasping::HandModel;
using grasping::JointType;

// Hand links weigh their collision volume at this density (kg/m^3; aluminium and plastic shells
// with motors), at least kMinLinkMassKg: only the fingers' inertia depends on it, the base is
// welded.
constexpr double kLinkDensityKgM3 = 1000.0;
constexpr double kMinLinkMassKg = 0.01;
// A hold's spring resolves in the explicit step while stiffness x step^2 stays below this share of
// the joint's inertia (a quarter: at critical damping, damping x step / inertia = 1).
constexpr double kStableStiffnessShare = 0.25;
// Collision groups: the hand collides with the object only (not with itself).
constexpr int kHandGroup = 1 << 6;
constexpr int kObjectGroup = 1 << 7;
// Each moving joint carries the reflected inertia of its drive (a motor's rotor through its
// gears: the armature of a joint): this many s^2 times its torque limit, in kg m^2 (prismatic: kg
// per N). Real finger drives reflect about 1e-3 kg m^2; it also keeps the grips' springs
// resolvable at the engine's step (stiffness x step^2 well below the inertia).
constexpr double kArmatureS2 = 2.5e-3;
// The hand's links are not simulated as a free body: the base's mass is a placeholder.
constexpr double kBaseMassKg = 1.0;

// Mass and diagonal inertia about the link frame's origin, from the shapes' boxes.
// The motion of `joint` at `value`: a turn about its axis or a shift along it.
Pose jointMotion(const grasping::Joint& joint, double value) {
  Pose motion = Pose::Identity();
  if (joint.type == JointType::kRevolute) {
    motion.linear() = Eigen::AngleAxisd(value, joint.axis.normalized()).toRotationMatrix();
  } else if (joint.type == JointType::kPrismatic) {
    motion.translation() = value * joint.axis.normalized();
  }
  return motion;
}

std::pair<double, btVector3> linkInertia(const grasping::Link& link) {
  double mass = 0;
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  for (const auto& shape : link.shapes) {
    const Eigen::Vector3d h = halfExtent(shape);
    const double m = kLinkDensityKgM3 * 8 * h.x() * h.y() * h.z();
    const Eigen::Vector3d s = 4 * h.cwiseProduct(h);  // (2h)^2
    Eigen::Matrix3d own = Eigen::Vector3d(s.y() + s.z(), s.x() + s.z(), s.x() + s.y()).asDiagonal();
    own *= m / 12.0;
    const Eigen::Matrix3d r = shape.origin.linear();
    const Eigen::Vector3d c = shapeCentre(shape);
    inertia += r * own * r.transpose() +
               m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
    mass += m;
  }
  if (mass < kMinLinkMassKg) {
    const double scale = mass > 0 ? kMinLinkMassKg / mass : 0;
    inertia *= scale;
    mass = kMinLinkMassKg;
  }
  // The multibody takes a diagonal inertia: the diagonal, with a floor so that no axis is free.
  const double floor = mass * 1e-6;
  return {mass, btVector3(std::max(inertia(0, 0), floor), std::max(inertia(1, 1), floor),
                          std::max(inertia(2, 2), floor))};
}

}  // namespace

struct Scene::Impl {
  const HandModel& hand_model;
  const PhysicalObject* physical_object;
  double time_step_s = 0;
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btMultiBodyConstraintSolver solver;
  btMultiBodyDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration};
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::unique_ptr<btMultiBody> hand;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders;
  std::vector<std::unique_ptr<btMultiBodyConstraint>> constraints;
  std::unique_ptr<btRigidBody> object;
  std::unique_ptr<SurfaceShape::BodyMesh> body_mesh;  // borrowed from the object's pool
  // The body frame of the object (centre of mass, principal axes) in the object frame.
  Pose body_in_object = Pose::Identity();
  // Per hand joint: its multibody link (-1: none); per multibody link: the hand link.
  std::vector<int> joint_to_multibody;
  std::vector<int> multibody_to_link;
  Eigen::VectorXd fixed_joints;  // the joint vector the scene started with
  std::vector<JointDrive> drives;
  std::vector<btMultiBodyJointMotor*> motors;  // per hand joint: its closing servo, if any
  std::vector<double> joint_inertia;           // per hand joint: the links it moves, about its axis
  std::vector<double> hold_stiffness, hold_damping;  // per hand joint, kHold
  btAlignedObjectArray<btQuaternion> scratch_rotations;
  btAlignedObjectArray<btVector3> scratch_origins;

  Impl(const HandModel& h, const PhysicalObject* o) : hand_model(h), physical_object(o) {}
  ~Impl() {
    if (object) world.removeRigidBody(object.get());
    if (body_mesh) physical_object->surfaceShape().giveBack(std::move(body_mesh));
    for (auto& constraint : constraints) world.removeMultiBodyConstraint(constraint.get());
    for (auto& collider : colliders) world.removeCollisionObject(collider.get());
    if (hand) world.removeMultiBody(hand.get());
  }

  void buildHand(const Pose& hand_pose, const std::vector<JointDrive>& drives,
                 const SceneState& state) {
    const auto& joints = hand_model.joints();
    const auto& links = hand_model.links();
    const auto& order = hand_model.jointOrder();
    joint_to_multibody.assign(joints.size(), -1);
    std::vector<int> link_to_multibody(links.size(), -1);
    multibody_to_link.clear();
    for (int j : order) {
      joint_to_multibody[j] = static_cast<int>(multibody_to_link.size());
      link_to_multibody[joints[j].child_link] = joint_to_multibody[j];
      multibody_to_link.push_back(joints[j].child_link);
    }
    const int n = static_cast<int>(multibody_to_link.size());
    hand = std::make_unique<btMultiBody>(n, kBaseMassKg, btVector3(1, 1, 1), true, false);
    hand->setBaseWorldTransform(toBt(hand_pose));
    for (int j : order) {
      const auto& joint = joints[j];
      const int i = joint_to_multibody[j];
      const bool simulated = isSimulated(j, drives);
      auto [mass, inertia] = linkInertia(links[joint.child_link]);
      const double armature = simulated ? kArmatureS2 * drives[j].torque_limit : 0.0;
      if (joint.type == JointType::kPrismatic) {
        mass += armature;
      } else {
        inertia += btVector3(armature, armature, armature);
      }
      const int parent = link_to_multibody[joint.parent_link];
      const btVector3 zero(0, 0, 0);
      if (!simulated) {
        // Locked where the state has it: the joint's motion is part of the fixed transform.
        const Pose locked = joint.origin * jointMotion(joint, state.joints[j]);
        hand->setupFixed(i, mass, inertia, parent,
                         toBt(Pose(locked.linear().transpose())).getRotation(),
                         toBt(locked.translation()), zero);
        continue;
      }
      const btQuaternion parent_to_this =
          toBt(Pose(joint.origin.linear().transpose())).getRotation();
      const btVector3 pivot = toBt(joint.origin.translation());
      switch (joint.type) {
        case JointType::kRevolute:
          hand->setupRevolute(i, mass, inertia, parent, parent_to_this, toBt(joint.axis), pivot,
                              zero, true);
          break;
        case JointType::kPrismatic:
          hand->setupPrismatic(i, mass, inertia, parent, parent_to_this, toBt(joint.axis), pivot,
                               zero, true);
          break;
        case JointType::kFixed:
          hand->setupFixed(i, mass, inertia, parent, parent_to_this, pivot, zero);
          break;
      }
    }
    hand->finalizeMultiDof();
    hand->setHasSelfCollision(false);
    hand->setCanSleep(false);
    world.addMultiBody(hand.get());
    fixed_joints = state.joints;
    for (int j : order) {
      if (!isSimulated(j, drives)) continue;
      hand->setJointPos(joint_to_multibody[j], state.joints[j]);
      hand->setJointVel(joint_to_multibody[j],
                        state.joint_velocities.size() ? state.joint_velocities[j] : 0.0);
    }
    hand->forwardKinematics(scratch_rotations, scratch_origins);
    addColliders(link_to_multibody);
    hand->updateCollisionObjectWorldTransforms(scratch_rotations, scratch_origins);
    computeJointInertia(state.joints, drives);
    addDrives(drives);
  }

  // Whether hand joint `j` moves in the engine: a movable joint with a drive. The others are
  // locked where the scene's state has them.
  bool isSimulated(std::size_t j, const std::vector<JointDrive>& with) const {
    return hand_model.joints()[j].movable() && with[j].mode != JointDrive::Mode::kFixed;
  }

  // Each joint's inertia about its axis: the links below it as the masses of linkInertia at their
  // link origins, plus their own inertia (its largest axis) and the joint's armature - enough to
  // bound a stable gain.
  void computeJointInertia(const Eigen::VectorXd& q, const std::vector<JointDrive>& drives) {
    const auto& joints = hand_model.joints();
    const auto poses = hand_model.linkPoses(q);
    joint_inertia.assign(joints.size(), 0.0);
    for (std::size_t j = 0; j < joints.size(); ++j) {
      if (!joints[j].movable()) continue;
      const Pose frame = poses[joints[j].parent_link] * joints[j].origin;
      const Eigen::Vector3d axis = (frame.linear() * joints[j].axis).normalized();
      std::vector<int> below = {joints[j].child_link};
      for (std::size_t k = 0; k < below.size(); ++k) {
        for (const auto& other : joints) {
          if (other.parent_link == below[k]) below.push_back(other.child_link);
        }
      }
      double inertia = 0;
      for (int link : below) {
        const auto [mass, own] = linkInertia(hand_model.links()[link]);
        const Eigen::Vector3d r = poses[link].translation() - frame.translation();
        const double lever =
            joints[j].type == JointType::kPrismatic ? 1.0 : (r - r.dot(axis) * axis).squaredNorm();
        inertia += joints[j].type == JointType::kPrismatic
                       ? mass
                       : mass * lever + std::max({own.x(), own.y(), own.z()});
      }
      joint_inertia[j] = inertia + kArmatureS2 * drives[j].torque_limit;
    }
  }

  void addColliders(const std::vector<int>& link_to_multibody) {
    const auto& links = hand_model.links();
    for (std::size_t l = 0; l < links.size(); ++l) {
      if (links[l].shapes.empty()) continue;
      auto made = linkShape(links[l], shapes);
      btCompoundShape* shape = made.get();
      shapes.push_back(std::move(made));
      const int index = static_cast<int>(l) == hand_model.rootLink() ? -1 : link_to_multibody[l];
      auto collider = std::make_unique<btMultiBodyLinkCollider>(hand.get(), index);
      collider->setCollisionShape(shape);
      // A pair's friction is the product of the two bodies': the object's mu (its torsional
      // friction is set on the object, buildObject).
      collider->setFriction(1.0);
      collider->setRestitution(0.0);
      collider->setUserIndex(static_cast<int>(l));
      world.addCollisionObject(collider.get(), kHandGroup, kObjectGroup);
      if (index < 0) {
        hand->setBaseCollider(collider.get());
      } else {
        hand->getLink(index).m_collider = collider.get();
      }
      colliders.push_back(std::move(collider));
    }
  }

  void addDrives(const std::vector<JointDrive>& requested) {
    drives = requested;
    const auto& joints = hand_model.joints();
    hold_stiffness.assign(joints.size(), 0.0);
    hold_damping.assign(joints.size(), 0.0);
    motors.assign(joints.size(), nullptr);
    for (std::size_t j = 0; j < joints.size(); ++j) {
      const JointDrive& drive = drives[j];
      const int i = joint_to_multibody[j];
      if (!isSimulated(j, drives)) continue;
      auto limit = std::make_unique<btMultiBodyJointLimitConstraint>(hand.get(), i, joints[j].lower,
                                                                     joints[j].upper);
      world.addMultiBodyConstraint(limit.get());
      constraints.push_back(std::move(limit));
      if (drive.mode == JointDrive::Mode::kHold) {
        setHold(j, drive);
        continue;
      }
      auto motor = std::make_unique<btMultiBodyJointMotor>(hand.get(), i, 0.0,
                                                           drive.closing_torque * time_step_s);
      motor->setVelocityTarget(drive.velocity, 1.0);
      world.addMultiBodyConstraint(motor.get());
      motors[j] = motor.get();
      constraints.push_back(std::move(motor));
    }
  }

  // A critically damped spring: explicit torques each step (applyHoldTorques).
  void setHold(std::size_t j, const JointDrive& drive) {
    drives[j] = drive;
    hold_stiffness[j] = stableStiffness(j, drive.stiffness);
    hold_damping[j] = 2.0 * std::sqrt(hold_stiffness[j] * joint_inertia[j]);
    if (motors[j]) motors[j]->setMaxAppliedImpulse(0.0);
  }

  double stableStiffness(std::size_t joint, double requested) const {
    const double bound = kStableStiffnessShare * joint_inertia[joint] / (time_step_s * time_step_s);
    return std::min(requested, bound);
  }

  void applyHoldTorques() {
    const auto& joints = hand_model.joints();
    for (std::size_t j = 0; j < joints.size(); ++j) {
      if (drives[j].mode != JointDrive::Mode::kHold) continue;
      const int i = joint_to_multibody[j];
      const double q = hand->getJointPos(i), v = hand->getJointVel(i);
      const double torque = hold_stiffness[j] * (drives[j].target - q) - hold_damping[j] * v;
      hand->addJointTorque(i, std::clamp(torque, -drives[j].torque_limit, drives[j].torque_limit));
    }
  }

  void buildObject(const ObjectState& state, double friction) {
    // The body frame is the centre of mass with the principal axes: the rigid body takes a
    // diagonal inertia there.
    const SurfaceShape& surface = physical_object->surfaceShape();
    body_in_object = surface.bodyInObject();
    const Eigen::Matrix3d axes = body_in_object.linear();
    const Eigen::Vector3d principal =
        (axes.transpose() * physical_object->inertia() * axes).diagonal().cwiseMax(1e-12);
    // A fixed object is a static body (mass 0 to the engine) colliding as the static triangle mesh
    // with its bounding-volume tree, in the object frame; a free one as its GImpact mesh in the
    // body frame.
    btCollisionShape* shape = nullptr;
    Pose body_pose = state.pose * body_in_object;
    if (state.fixed) {
      shape = surface.staticMesh();
      body_in_object = Pose::Identity();
      body_pose = state.pose;
    } else {
      body_mesh = surface.borrowBodyMesh();
      btGImpactCollisionAlgorithm::registerAlgorithm(&dispatcher);
      shape = body_mesh->shape.get();
    }
    const double mass = state.fixed ? 0.0 : physical_object->massKg();
    btRigidBody::btRigidBodyConstructionInfo info(
        mass, nullptr, shape, state.fixed ? btVector3(0, 0, 0) : toBt(principal));
    info.m_startWorldTransform = toBt(body_pose);
    info.m_friction = friction;
    // The engine's torsional friction of a pair is the object's spinning friction times the link's
    // friction (1): a patch resists a twist about its normal up to this length times the normal
    // force, the hand's soft-finger contact model (ClosingDefaults::torsional_friction_m) as the
    // quality measure's.
    info.m_spinningFriction = hand_model.closingDefaults().torsional_friction_m;
    info.m_restitution = 0.0;
    info.m_linearDamping = 0.0;
    info.m_angularDamping = 0.0;
    object = std::make_unique<btRigidBody>(info);
    object->setActivationState(DISABLE_DEACTIVATION);
    object->setLinearVelocity(toBt(state.linear_velocity));
    object->setAngularVelocity(toBt(state.angular_velocity));
    object->setUserIndex(-1);
    world.addRigidBody(object.get(), kObjectGroup, kHandGroup);
    object->setGravity(btVector3(0, 0, 0));
  }
};

Scene::Scene(const HandModel& hand, const Pose& hand_pose, const std::vector<JointDrive>& drives,
             const PhysicalObject* object, const SceneState& state, const JudgeParams& params)
    : impl_(std::make_unique<Impl>(hand, object)) {
  SKELGRASP_DEMAND(drives.size() == hand.joints().size());
  SKELGRASP_DEMAND(state.joints.size() == static_cast<Eigen::Index>(hand.joints().size()));
  impl_->time_step_s = params.time_step_s;
  impl_->world.setGravity(btVector3(0, 0, 0));
  impl_->world.getSolverInfo().m_numIterations = params.solver_iterations;
  impl_->buildHand(hand_pose, drives, state);
  if (object) impl_->buildObject(state.object, params.friction);
}

Scene::~Scene() = default;

void Scene::setObjectForce(const Eigen::Vector3d& force) {
  // A body's own gravity: a constant force at its centre of mass, kept across steps.
  SKELGRASP_DEMAND(impl_->object);
  impl_->object->setGravity(toBt(force / impl_->physical_object->massKg()));
}

void Scene::setDrive(int joint, const JointDrive& drive) {
  const auto j = static_cast<std::size_t>(joint);
  SKELGRASP_DEMAND(j < impl_->drives.size());
  if (impl_->drives[j].mode == JointDrive::Mode::kFixed) return;
  if (drive.mode == JointDrive::Mode::kHold) {
    impl_->setHold(j, drive);
  } else if (drive.mode == JointDrive::Mode::kClose && impl_->motors[j]) {
    impl_->drives[j] = drive;
    impl_->motors[j]->setVelocityTarget(drive.velocity, 1.0);
    impl_->motors[j]->setMaxAppliedImpulse(drive.closing_torque * impl_->time_step_s);
  }
}

double Scene::jointSpeed(int joint) const {
  const auto j = static_cast<std::size_t>(joint);
  if (!impl_->isSimulated(j, impl_->drives)) return 0.0;
  return impl_->hand->getJointVel(impl_->joint_to_multibody[j]);
}

double Scene::holdStiffness(int joint, double requested) const {
  return impl_->stableStiffness(static_cast<std::size_t>(joint), requested);
}

void Scene::step() {
  impl_->applyHoldTorques();
  impl_->world.stepSimulation(impl_->time_step_s, 0, impl_->time_step_s);
}

ObjectState Scene::objectState() const {
  ObjectState state;
  if (!impl_->object) return state;
  state.pose = fromBt(impl_->object->getWorldTransform()) * impl_->body_in_object.inverse();
  state.linear_velocity = fromBt(impl_->object->getLinearVelocity());
  state.angular_velocity = fromBt(impl_->object->getAngularVelocity());
  return state;
}

SceneState Scene::state() const {
  SceneState state;
  const auto& joints = impl_->hand_model.joints();
  state.joints = impl_->fixed_joints;
  state.joint_velocities = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(joints.size()));
  for (std::size_t j = 0; j < joints.size(); ++j) {
    if (!impl_->isSimulated(j, impl_->drives)) continue;
    state.joints[j] = impl_->hand->getJointPos(impl_->joint_to_multibody[j]);
    state.joint_velocities[j] = impl_->hand->getJointVel(impl_->joint_to_multibody[j]);
  }
  state.object = objectState();
  return state;
}

std::vector<Pose> Scene::linkPoses() const {
  const auto& links = impl_->hand_model.links();
  std::vector<Pose> poses(links.size(), fromBt(impl_->hand->getBaseWorldTransform()));
  for (std::size_t i = 0; i < impl_->multibody_to_link.size(); ++i) {
    poses[impl_->multibody_to_link[i]] =
        fromBt(impl_->hand->getLink(static_cast<int>(i)).m_cachedWorldTransform);
  }
  return poses;
}

std::vector<int> Scene::touchingLinks(double distance_m) const {
  std::vector<int> links;
  const int manifolds = impl_->dispatcher.getNumManifolds();
  for (int m = 0; m < manifolds; ++m) {
    const btPersistentManifold* manifold = impl_->dispatcher.getManifoldByIndexInternal(m);
    const int hand_link =
        std::max(manifold->getBody0()->getUserIndex(), manifold->getBody1()->getUserIndex());
    for (int p = 0; p < manifold->getNumContacts(); ++p) {
      if (manifold->getContactPoint(p).getDistance() <= distance_m) {
        links.push_back(hand_link);
        break;
      }
    }
  }
  std::sort(links.begin(), links.end());
  links.erase(std::unique(links.begin(), links.end()), links.end());
  return links;
}

double Scene::maxJointSpeed() const {
  double fastest = 0;
  for (int i = 0; i < impl_->hand->getNumLinks(); ++i) {
    if (impl_->hand->getLink(i).m_jointType == btMultibodyLink::eFixed) continue;
    fastest = std::max(fastest, std::abs(impl_->hand->getJointVel(i)));
  }
  return fastest;
}

}  // namespace skelgrasp::physics::internal
