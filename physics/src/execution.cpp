#include "skelgrasp/physics/execution.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <limits>

#include "bullet_scene.h"
#include "bullet_shapes.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/grasping/hand/hand_strength.h"

namespace skelgrasp::physics {
namespace {

using grasping::HandModel;
using grasping::JointType;
using internal::JointDrive;

// A prismatic joint closes at this speed per unit of the revolute closing speed (m per rad): a
// jaw of 4 cm closes in the time a finger turns 0.8 rad.
constexpr double kPrismaticSpeedPerRadian = 0.05;
// The fingers have settled when every joint turns slower than this (rad/s) for still_time_s.
// A link touches the object when a contact point lies within this distance (m).
constexpr double kTouchDistanceM = 0.001;
// Once closed, each finger joint holds its grip as a spring towards a point beyond where it
// stopped: it presses with grasping::kGripTorqueShare of its torque limit and can press harder by
// the rest before it gives way.
constexpr double kGripShare = grasping::kGripTorqueShare;
// The springs' requested stiffness: the full torque limit at this angle (rad) or, for prismatic
// joints, at this distance (m) from the target.
constexpr double kGripAngleRad = 0.1;
constexpr double kGripDistanceM = 0.005;
// The closing's end (fingers switched to their grips, the object free) settles for at most this
// long (s) before the disturbances.
constexpr double kReleaseTimeS = 0.5;
// While closing, each servo pushes with at most this share of its torque limit: the fingers stop
// at the object instead of shoving it (a guarded closing), then all grip at once.
constexpr double kClosingTorqueShare = 0.2;
// A closing joint is blocked (its servo saturated by a contact or its limit) once it has turned
// slower than this share of its closing speed for kBlockedTimeS.
constexpr double kBlockedSpeedShare = 0.2;
constexpr double kBlockedTimeS = 0.02;
// ... counted from this long after the closing starts (s): a servo takes a few steps to bring its
// joint (and the drive's inertia) up to speed.
constexpr double kServoStartupTimeS = 0.1;

double threadCpuSeconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

void validate(const JudgeParams& p) {
  const auto positive = [](double value, const char* name) {
    if (!(value > 0) || !std::isfinite(value)) {
      throw InvalidArgument(fmt::format("physics: {} = {}: must be finite and > 0", name, value));
    }
  };
  if (!(p.friction >= 0) || !std::isfinite(p.friction)) {
    throw InvalidArgument(
        fmt::format("physics: friction = {}: must be finite and >= 0", p.friction));
  }
  if (p.disturbance_force_n) positive(*p.disturbance_force_n, "disturbance_force_n");
  positive(p.closing_time_s, "closing_time_s");
  positive(p.disturbance_time_s, "disturbance_time_s");
  positive(p.still_time_s, "still_time_s");
  positive(p.still_speed_m_s, "still_speed_m_s");
  positive(p.max_displacement_m, "max_displacement_m");
  positive(p.max_rotation_rad, "max_rotation_rad");
  positive(p.max_start_penetration_m, "max_start_penetration_m");
  if (p.fingertip_force_n) positive(*p.fingertip_force_n, "fingertip_force_n");
  positive(p.closing_speed_rad_s, "closing_speed_rad_s");
  positive(p.time_step_s, "time_step_s");
  if (p.time_step_s > 0.01) throw InvalidArgument("physics: time_step_s must be <= 0.01 s");
  if (p.solver_iterations < 1 || p.solver_iterations > 1000) {
    throw InvalidArgument("physics: solver_iterations must be in [1, 1000]");
  }
  const double longest = std::max(p.closing_time_s, p.disturbance_time_s);
  if (longest / p.time_step_s > 1e6) {
    throw InvalidArgument("physics: more than 1e6 steps per phase; raise time_step_s");
  }
}

double rotationAngle(const Eigen::Matrix3d& rotation) {
  return Eigen::AngleAxisd(rotation).angle();
}

// How far the object moved from `from` to `to`: its centre of mass, and the turn.
std::pair<double, double> motionBetween(const Pose& from, const Pose& to,
                                        const Eigen::Vector3d& centre_of_mass) {
  const double displacement = (to * centre_of_mass - from * centre_of_mass).norm();
  const double rotation = rotationAngle(from.linear().transpose() * to.linear());
  return {displacement, rotation};
}

// Joints that close while the fingers close, with their signed speeds; every other movable joint
// holds its preshape value by a torque-limited spring.
std::vector<JointDrive> closingDrives(const HandModel& hand, const grasping::Preshape& preshape,
                                      const std::vector<double>& torque_limits,
                                      const JudgeParams& params) {
  const auto& joints = hand.joints();
  std::vector<JointDrive> drives(joints.size());
  const auto speed = [&](int joint, double direction) {
    const double unit =
        joints[joint].type == JointType::kPrismatic ? kPrismaticSpeedPerRadian : 1.0;
    return direction * params.closing_speed_rad_s * unit;
  };
  for (std::size_t j = 0; j < joints.size(); ++j) drives[j].torque_limit = torque_limits[j];
  for (const auto& finger : hand.fingers()) {
    for (const auto& drive : finger.drives) {
      drives[drive.joint].mode = JointDrive::Mode::kClose;
      drives[drive.joint].velocity = speed(drive.joint, drive.direction);
      drives[drive.joint].closing_torque = kClosingTorqueShare * torque_limits[drive.joint];
      for (const auto& [follower, ratio] : drive.followers) {
        drives[follower].mode = JointDrive::Mode::kClose;
        drives[follower].velocity = speed(follower, drive.direction * ratio);
        drives[follower].closing_torque = kClosingTorqueShare * torque_limits[follower];
      }
    }
  }
  // A mimic joint moves with its leader (the URDF's coupling), scaled by the multiplier.
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const int leader = joints[j].mimic_of;
    if (leader < 0 || drives[leader].mode != JointDrive::Mode::kClose) continue;
    drives[j].mode = JointDrive::Mode::kClose;
    drives[j].velocity = drives[leader].velocity * joints[j].mimic_multiplier;
    drives[j].closing_torque = kClosingTorqueShare * torque_limits[j];
  }
  // Every other movable joint is a servo too: it holds its preshape value with a PD spring that
  // reaches its torque limit at kGripAngleRad (kGripDistanceM) off, and no more. A joint locked
  // rigid would make the judge stronger than the hand.
  Eigen::VectorXd open = preshape.joints;
  hand.normalise(open);
  for (std::size_t j = 0; j < joints.size(); ++j) {
    if (drives[j].mode != JointDrive::Mode::kFixed || !joints[j].movable()) continue;
    if (!(torque_limits[j] > 0)) continue;
    const double span = joints[j].type == JointType::kPrismatic ? kGripDistanceM : kGripAngleRad;
    drives[j].mode = JointDrive::Mode::kHold;
    drives[j].target = open[static_cast<Eigen::Index>(j)];
    drives[j].stiffness = torque_limits[j] / span;
  }
  return drives;
}

// The grip of a closing joint that stopped at `position`: a spring pressing towards closing with
// kGripShare of its torque limit there.
JointDrive gripDrive(const grasping::Joint& joint, const JointDrive& closing, double position,
                     const internal::Scene& scene, int index) {
  const double span = joint.type == JointType::kPrismatic ? kGripDistanceM : kGripAngleRad;
  JointDrive grip = closing;
  grip.mode = JointDrive::Mode::kHold;
  grip.stiffness = scene.holdStiffness(index, closing.torque_limit / span);
  const double direction = closing.velocity > 0 ? 1.0 : -1.0;
  grip.target = position + direction * kGripShare * closing.torque_limit /
                               std::max(grip.stiffness, std::numeric_limits<double>::min());
  return grip;
}

int stepsFor(double seconds, const JudgeParams& params) {
  return std::max(1, static_cast<int>(std::ceil(seconds / params.time_step_s)));
}

// Whether the object stays put: over each window of still_time_s, its centre of mass, and a point
// at its largest radius by the turn, moved less than still_speed x still_time. Positions, not
// speeds: a contact's jitter does not keep a held object "moving".
class StillWatch {
 public:
  StillWatch(const JudgeParams& params, const PhysicalObject& object, const Pose& start)
      : window_(stepsFor(params.still_time_s, params)),
        bound_m_(params.still_speed_m_s * params.still_time_s),
        object_(object),
        anchor_(start) {}
  // Call after every step; true at the end of a window over which the object stayed put.
  bool stillAfterStep(const Pose& pose) {
    if (++steps_ < window_) return false;
    const auto [moved, turned] = motionBetween(anchor_, pose, object_.centerOfMass());
    anchor_ = pose;
    steps_ = 0;
    return moved + turned * object_.maxRadiusM() < bound_m_;
  }

 private:
  int window_;
  double bound_m_;
  const PhysicalObject& object_;
  Pose anchor_;
  int steps_ = 0;
};

const Eigen::Vector3d kDirections[6] = {Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitX(),
                                        Eigen::Vector3d::UnitY(), -Eigen::Vector3d::UnitY(),
                                        Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitZ()};

}  // namespace

const char* toString(ExecutionPhase phase) {
  switch (phase) {
    case ExecutionPhase::kNone:
      return "none";
    case ExecutionPhase::kStart:
      return "start";
    case ExecutionPhase::kClosing:
      return "closing";
    case ExecutionPhase::kDisturbance:
      return "disturbance";
  }
  return "?";
}

std::vector<double> jointTorqueLimits(const HandModel& hand, const JudgeParams& params) {
  return grasping::jointTorqueLimits(hand, params.fingertip_force_n);
}

ExecutionResult executeGrasp(const HandModel& hand, const PhysicalObject& object,
                             const Pose& hand_pose, const grasping::Preshape& preshape,
                             const JudgeParams& params) {
  validate(params);
  const double cpu_start = threadCpuSeconds();
  ExecutionResult result;
  const auto torque_limits = jointTorqueLimits(hand, params);
  const auto drives = closingDrives(hand, preshape, torque_limits, params);
  internal::SceneState start;
  start.joints = preshape.joints;
  hand.normalise(start.joints);
  start.joint_velocities = Eigen::VectorXd::Zero(start.joints.size());
  // Charges the CPU time and steps since the last mark to `phase`.
  double mark_cpu = cpu_start;
  int mark_steps = 0;
  const auto charge = [&](ExecutionResult::PhaseCost& phase) {
    const double now = threadCpuSeconds();
    phase.cpu_s += now - mark_cpu;
    phase.steps += result.steps - mark_steps;
    mark_cpu = now;
    mark_steps = result.steps;
  };
  ExecutionResult::PhaseCost* current_phase = &result.start_cost;
  const auto finish = [&]() {
    charge(*current_phase);
    result.cpu_s = threadCpuSeconds() - cpu_start;
    return result;
  };

  // The open hand at the grasp pose.
  std::vector<Pose> link_poses = hand.linkPoses(start.joints);
  for (auto& pose : link_poses) pose = hand_pose * pose;
  const auto [depth, link] = internal::startPenetration(hand, link_poses, object);
  result.start_penetration_m = depth;
  if (link >= 0) result.penetrating_link = hand.links()[link].name;
  if (depth > params.max_start_penetration_m) {
    result.failed_phase = ExecutionPhase::kStart;
    result.reason = fmt::format("the open hand's link {} penetrates the object {:.1f} mm",
                                result.penetrating_link, 1e3 * depth);
    return finish();
  }
  charge(result.start_cost);
  current_phase = &result.closing_cost;
  start.object.fixed = true;
  internal::Scene closing(hand, hand_pose, drives, &object, start, params);

  // Closing: each closing joint turns at the closing speed until it is blocked (its servo
  // saturates: it has slowed below kBlockedSpeedShare of its speed for kBlockedTimeS), then holds
  // its grip there. The object is held where it is meanwhile, as the planners assume (on a support,
  // or in a fixture): which finger happens to touch first does not shove it.
  const int blocked_steps = stepsFor(kBlockedTimeS, params);
  const int startup_steps = stepsFor(kServoStartupTimeS, params);
  auto current = drives;
  std::vector<int> slow(current.size(), 0);
  const auto grip = [&](std::size_t j) {
    current[j] = gripDrive(hand.joints()[j], current[j], closing.state().joints[j], closing,
                           static_cast<int>(j));
    closing.setDrive(static_cast<int>(j), current[j]);
  };
  const int closing_steps = stepsFor(params.closing_time_s, params);
  bool settled_closing = false;
  for (int s = 0; s < closing_steps && !settled_closing; ++s) {
    closing.step();
    ++result.steps;
    bool closing_joints = false;
    for (std::size_t j = 0; j < current.size(); ++j) {
      if (current[j].mode != JointDrive::Mode::kClose) continue;
      // Speed towards closing: a joint pushed back counts as blocked too.
      const double speed =
          closing.jointSpeed(static_cast<int>(j)) * (current[j].velocity > 0 ? 1 : -1);
      const bool starting = s < startup_steps;
      slow[j] =
          !starting && speed < kBlockedSpeedShare * std::abs(current[j].velocity) ? slow[j] + 1 : 0;
      if (slow[j] >= blocked_steps) {
        grip(j);
      } else {
        closing_joints = true;
      }
    }
    settled_closing = !closing_joints;
  }
  for (std::size_t j = 0; j < current.size(); ++j) {
    if (current[j].mode == JointDrive::Mode::kClose) grip(j);
  }
  bool finger_touches = false;
  for (int touching : closing.touchingLinks(kTouchDistanceM)) {
    finger_touches = finger_touches || hand.fingerOfLink(touching) >= 0;
  }
  if (!finger_touches) {
    result.joints = closing.state().joints;
    result.failed_phase = ExecutionPhase::kClosing;
    result.reason = "no finger touches the object after closing";
    return finish();
  }

  // The object is let go: it settles in the gripping hand.
  charge(result.closing_cost);
  current_phase = &result.release_cost;
  internal::SceneState closed = closing.state();
  closed.joint_velocities.setZero();
  closed.object = internal::ObjectState{};
  internal::Scene release(hand, hand_pose, current, &object, closed, params);
  StillWatch release_watch(params, object, Pose::Identity());
  for (int s = 0; s < stepsFor(kReleaseTimeS, params); ++s) {
    release.step();
    ++result.steps;
    if (release_watch.stillAfterStep(release.objectState().pose)) break;
  }
  internal::SceneState settled = release.state();
  result.joints = settled.joints;
  for (int touching : release.touchingLinks(kTouchDistanceM)) {
    result.touching_links.push_back(hand.links()[touching].name);
  }
  std::tie(result.closing_displacement_m, result.closing_rotation_rad) =
      motionBetween(Pose::Identity(), settled.object.pose, object.centerOfMass());
  const double released_by = result.closing_displacement_m;
  const double released_turn = result.closing_rotation_rad;
  if (released_by >= params.max_displacement_m || released_turn >= params.max_rotation_rad) {
    result.failed_phase = ExecutionPhase::kClosing;
    result.reason = fmt::format(
        "the object slipped {:.1f} mm and turned {:.1f} deg when the closed hand let it go",
        1e3 * released_by, released_turn * 180.0 / kPi);
    return finish();
  }
  const auto& grips = current;
  charge(result.release_cost);
  current_phase = &result.disturbance_cost;

  // The disturbances, each from the settled state.
  const double force = params.disturbance_force_n.value_or(object.massKg() * kStandardGravity);
  const int disturbance_steps =
      static_cast<int>(std::ceil(params.disturbance_time_s / params.time_step_s));
  result.holds = true;
  for (const Eigen::Vector3d& direction : kDirections) {
    DisturbanceResult outcome;
    outcome.direction = direction;
    internal::Scene scene(hand, hand_pose, grips, &object, settled, params);
    scene.setObjectForce(force * direction);
    StillWatch watch(params, object, settled.object.pose);
    bool quiet = false;
    int s = 0;
    bool moved_out = false;
    for (; s < disturbance_steps && !quiet && !moved_out; ++s) {
      scene.step();
      ++result.steps;
      const auto state = scene.objectState();
      std::tie(outcome.displacement_m, outcome.rotation_rad) =
          motionBetween(settled.object.pose, state.pose, object.centerOfMass());
      moved_out = outcome.displacement_m >= params.max_displacement_m ||
                  outcome.rotation_rad >= params.max_rotation_rad;
      quiet = watch.stillAfterStep(state.pose);
    }
    outcome.simulated_s = s * params.time_step_s;
    outcome.held = !moved_out;
    if (!outcome.held && result.holds) {
      result.holds = false;
      result.failed_phase = ExecutionPhase::kDisturbance;
      result.reason = fmt::format(
          "the object moved {:.1f} mm and turned {:.1f} deg under a {:.2f} N pull along "
          "({:g}, {:g}, {:g})",
          1e3 * outcome.displacement_m, outcome.rotation_rad * 180.0 / kPi, force, direction.x(),
          direction.y(), direction.z());
    }
    result.disturbances.push_back(outcome);
  }
  return finish();
}

std::vector<Pose> engineLinkPoses(const HandModel& hand, const Pose& hand_pose,
                                  const Eigen::VectorXd& joints) {
  if (joints.size() != static_cast<Eigen::Index>(hand.joints().size())) {
    throw InvalidArgument(fmt::format("physics: {} joint values for a hand of {} joints",
                                      joints.size(), hand.joints().size()));
  }
  internal::SceneState state;
  state.joints = joints;
  state.joint_velocities = Eigen::VectorXd::Zero(joints.size());
  const std::vector<JointDrive> drives(hand.joints().size());
  const internal::Scene scene(hand, hand_pose, drives, nullptr, state, JudgeParams{});
  return scene.linkPoses();
}

}  // namespace skelgrasp::physics
