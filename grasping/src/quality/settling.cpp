#include "skelgrasp/grasping/quality/settling.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "skelgrasp/common/logging.h"
#include "skelgrasp/grasping/grasp.h"

namespace skelgrasp::grasping {

const char* toString(SettlingOutcome outcome) {
  switch (outcome) {
    case SettlingOutcome::kForceClosure:
      return "force_closure";
    case SettlingOutcome::kBalanced:
      return "balanced";
    case SettlingOutcome::kWedged:
      return "wedged";
    case SettlingOutcome::kPushedOut:
      return "pushed_out";
    case SettlingOutcome::kStepLimit:
      return "step_limit";
    case SettlingOutcome::kTooFewContacts:
      return "too_few_contacts";
    case SettlingOutcome::kStartCollision:
      return "start_collision";
  }
  return "?";
}

namespace {

// A step halved down to exactly min_step_m is still tried, whatever the rounding of the halvings.
constexpr double kHalvingSlack = 1e-9;

// The object moved by the twist (v, w) about its centre of mass c: x -> c + R(w) (x - c) + v.
Pose objectMotion(const Eigen::Vector3d& centre, const Eigen::Vector3d& v,
                  const Eigen::Vector3d& w) {
  Pose motion = Pose::Identity();
  const double angle = w.norm();
  if (angle > 0) motion.linear() = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
  motion.translation() = centre + v - motion.linear() * centre;
  return motion;
}

// The squeeze of the closing's contacts: each finger's contacts push together with a normal force
// of at least 1, palm contacts push back as needed (solveSqueezeLp). Wrenches about the centre of
// mass with the max-radius torque scale, so a unit of torque is a unit force at the max radius.
SqueezeLpResult squeezeOf(const HandModel& hand, const GraspObject& object,
                          const std::vector<Contact>& contacts, const QualityParams& quality,
                          double pushing_distance_m) {
  const double torque_scale = 1.0 / object.maxRadius();
  std::vector<Wrench> wrenches;
  std::vector<int> group;
  std::vector<double> normal;
  std::vector<Wrench> pressing;
  for (const auto& contact : contacts) {
    if (contact.distance > pushing_distance_m) continue;
    const auto own = contactWrenches({contact}, object.centerOfMass(), torque_scale, quality);
    const int link = hand.linkIndex(contact.link);
    const int finger = contact.palm || link < 0 ? -1 : hand.fingerOfLink(link);
    const Eigen::Vector3d inward = -contact.normal.normalized();
    Wrench press;
    press << inward, torque_scale * (contact.point - object.centerOfMass()).cross(inward);
    pressing.push_back(press);
    for (const auto& w : own) {
      wrenches.push_back(w);
      group.push_back(finger);
      normal.push_back(w.head<3>().dot(inward));
    }
  }
  return solveSqueezeLp(wrenches, group, normal, pressing);
}

bool anyFingerPushes(const std::vector<Contact>& contacts, double pushing_distance_m) {
  for (const auto& c : contacts) {
    if (!c.palm && c.distance <= pushing_distance_m) return true;
  }
  return false;
}

// The squeeze leaves out contacts beyond the pushing distance, and force closure implies balance
// only when both see the same contacts.
bool allContactsPush(const std::vector<Contact>& contacts, double pushing_distance_m) {
  for (const auto& c : contacts) {
    if (c.distance > pushing_distance_m) return false;
  }
  return true;
}

// The object is moved along the residual: the squeeze is unbalanced and the LP did not fail.
bool pushesObject(const SqueezeLpResult& squeeze) {
  return !squeeze.balanced && squeeze.error.empty() && squeeze.residual.norm() > 0;
}

}  // namespace

SettlingResult settleGrasp(GraspSimulator& simulator, const Pose& hand_pose,
                           const Preshape& preshape, const ClosingParams& closing,
                           const QualityParams& quality, const SettlingParams& params) {
  if (!(params.step_m > 0) || !(params.min_step_m > 0) || params.min_step_m > params.step_m ||
      !(params.max_travel_m > 0) || params.max_steps < 0 || !(params.pushing_distance_m >= 0)) {
    throw InvalidArgument(
        "settling: steps and travel must be > 0, min_step_m <= step_m, max_steps >= 0 and the "
        "pushing distance >= 0");
  }
  const HandModel& hand = simulator.hand();
  const GraspObject& object = simulator.object();
  SettlingResult result;
  result.hand_pose = hand_pose;
  result.closing = simulator.close(hand_pose, preshape, closing);
  if (result.closing.reason == reason::kStartCollision) {
    result.outcome = SettlingOutcome::kStartCollision;
    return result;
  }
  // A push that keeps its direction speeds up (twice the last step), one that reverses slows down.
  double step = params.step_m;
  Wrench last_direction = Wrench::Zero();
  // Force closure implies a balanced squeeze only for a strict-interior test on the same wrenches;
  // the reference's hull test also accepts the origin on the hull's boundary.
  const bool shortcut = params.skip_closure_test_when_unbalanced && !quality.reference_compat;
  for (;;) {
    const auto& contacts = result.closing.contacts;
    const bool pushes = anyFingerPushes(contacts, params.pushing_distance_m);
    const bool may_step = pushes && result.steps < params.max_steps;
    std::optional<SqueezeLpResult> squeeze;
    // Only once the object has moved: a first closing is mostly force closure (a returned grasp's
    // samples mostly hold as they close), where the squeeze first would be an LP more, while a
    // squeeze that just moved the object mostly moves it again.
    if (shortcut && result.steps > 0 && may_step && result.closing.status.ok() &&
        allContactsPush(contacts, params.pushing_distance_m)) {
      squeeze = squeezeOf(hand, object, contacts, quality, params.pushing_distance_m);
    }
    const bool proven_open = squeeze && pushesObject(*squeeze);
    if (result.closing.status.ok() && !proven_open &&
        evaluateGrasp(contacts, object, quality).force_closure) {
      result.outcome = SettlingOutcome::kForceClosure;
      return result;
    }
    if (!pushes) {
      result.outcome = SettlingOutcome::kTooFewContacts;
      return result;
    }
    if (!may_step) {
      result.outcome = SettlingOutcome::kStepLimit;
      return result;
    }
    if (!squeeze) squeeze = squeezeOf(hand, object, contacts, quality, params.pushing_distance_m);
    // A failed LP (never seen) is read as balance: the object is not moved on a guess.
    if (!pushesObject(*squeeze)) {
      result.outcome = SettlingOutcome::kBalanced;
      return result;
    }
    const Wrench direction = squeeze->residual.normalized();
    if (log().should_log(spdlog::level::trace)) {
      log().trace("settling step {}: {} contacts, unbalanced wrench [{:.3f}]", result.steps,
                  contacts.size(), fmt::join(squeeze->residual, " "));
      for (const auto& c : contacts) {
        log().trace("  {} at [{:.4f}] normal [{:.2f}] gap {:.4f}", c.link, fmt::join(c.point, " "),
                    fmt::join(c.normal, " "), c.distance);
      }
    }
    // The hand relative to the object moved by `length` along the unbalanced wrench: the inverse
    // motion applied to the hand.
    const auto handAfter = [&](double length) {
      const Eigen::Vector3d v = length * direction.head<3>();
      const Eigen::Vector3d w = length * direction.tail<3>() / object.maxRadius();
      return Pose(objectMotion(object.centerOfMass(), v, w).inverse() * result.hand_pose);
    };
    // The step: twice the last one (at most step_m), or half of it when the push reverses (the
    // object overshot: a coupled gripper's jaws would otherwise bounce it between them, the
    // pushing jaw left behind), then halved until the moved start is free of the hand. The
    // fingers close on from where they were (closeFrom tests the moved start first).
    step = last_direction.dot(direction) < 0 ? step / 2 : std::min(2 * step, params.step_m);
    ClosingResult closed;
    bool moved = false;
    for (; step >= params.min_step_m * (1 - kHalvingSlack); step /= 2) {
      closed = simulator.closeFrom(handAfter(step), preshape, result.closing.joints, closing);
      if (closed.reason != reason::kStartCollision) {
        moved = true;
        break;
      }
    }
    if (!moved) {
      result.outcome = SettlingOutcome::kWedged;
      return result;
    }
    last_direction = direction;
    result.hand_pose = handAfter(step);
    result.closing = std::move(closed);
    result.travel_m += step * direction.head<3>().norm();
    result.turn_rad += step * direction.tail<3>().norm() / object.maxRadius();
    ++result.steps;
    if (result.travel_m > params.max_travel_m) {
      result.outcome = SettlingOutcome::kPushedOut;
      return result;
    }
  }
}

}  // namespace skelgrasp::grasping
