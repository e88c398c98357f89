#include "skelgrasp/grasping/quality/load_capacity.h"

#include <fmt/format.h>

#include <cmath>

#include "skelgrasp/grasping/hand/hand_strength.h"

namespace skelgrasp::grasping {
namespace {

// The joints between the root and `link` (their indices), root first.
std::vector<int> jointsAbove(const HandModel& hand, int link) {
  std::vector<int> chain;
  for (int at = link; hand.links()[at].parent_joint >= 0;) {
    const int j = hand.links()[at].parent_joint;
    chain.push_back(j);
    at = hand.joints()[j].parent_link;
  }
  return chain;
}

// Each joint's closing direction along its axis (+1 or -1), 0 for joints that do not close: a
// finger's drives, their followers and the mimics of either (as the hand closes them).
std::vector<double> closingDirections(const HandModel& hand) {
  std::vector<double> direction(hand.joints().size(), 0.0);
  const auto sign = [](double v) { return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0); };
  for (const auto& finger : hand.fingers()) {
    for (const auto& drive : finger.drives) {
      direction[static_cast<std::size_t>(drive.joint)] = sign(drive.direction);
      for (const auto& [follower, ratio] : drive.followers)
        direction[static_cast<std::size_t>(follower)] = sign(drive.direction * ratio);
    }
  }
  for (std::size_t j = 0; j < hand.joints().size(); ++j) {
    const int leader = hand.joints()[j].mimic_of;
    if (leader >= 0 && direction[j] == 0)
      direction[j] =
          direction[static_cast<std::size_t>(leader)] * sign(hand.joints()[j].mimic_multiplier);
  }
  return direction;
}

}  // namespace

LoadCapacity loadCapacity(const HandModel& hand, const Pose& hand_pose,
                          const Eigen::VectorXd& joints, const std::vector<Contact>& contacts,
                          const Eigen::Vector3d& center_of_mass, const QualityParams& quality,
                          const LoadCapacityParams& params) {
  if (!(params.mass_kg > 0) || !std::isfinite(params.mass_kg))
    throw InvalidArgument(fmt::format("load capacity: mass {} kg must be > 0", params.mass_kg));
  if (!(params.max_capacity > 0) || !std::isfinite(params.max_capacity))
    throw InvalidArgument("load capacity: max_capacity must be > 0");
  if (!(params.torque_share > 0 && params.torque_share <= 1))
    throw InvalidArgument("load capacity: torque_share must be in (0, 1]");
  if (joints.size() != static_cast<Eigen::Index>(hand.joints().size()))
    throw InvalidArgument("load capacity: one joint value per joint of the hand");
  LoadCapacity capacity;
  if (contacts.empty()) return capacity;
  const std::vector<double> limits = jointTorqueLimits(hand, params.fingertip_force_n);
  std::vector<Pose> poses = hand.linkPoses(joints);
  for (auto& pose : poses) pose = hand_pose * pose;
  // Each contact's force edges as wrenches on the object about its centre of mass (N, N m), the
  // soft-finger torsion as two variants of each edge (as contactWrenches builds them), and the
  // torque each puts on the joints above its link.
  std::vector<Wrench> columns;
  std::vector<std::vector<std::pair<int, double>>> joint_torques;  // per column: (joint, torque)
  const double torsion_m = quality.torsional_friction_m.value_or(0.0);
  for (const auto& c : contacts) {
    const int link = hand.linkIndex(c.link);
    if (link < 0) throw InvalidArgument("load capacity: the hand has no link '" + c.link + "'");
    const Eigen::Vector3d inward = -c.normal.normalized();
    const Eigen::Vector3d r = c.point - center_of_mass;
    const std::vector<int> chain = c.palm ? std::vector<int>{} : jointsAbove(hand, link);
    for (const auto& f : frictionConeEdges(c.normal, quality)) {
      for (int variant = 0; variant < (torsion_m > 0 ? 2 : 1); ++variant) {
        const Eigen::Vector3d torsion =
            (variant == 0 ? 1.0 : -1.0) * torsion_m * f.dot(inward) * inward;
        Wrench w;
        w << f, r.cross(f) + (torsion_m > 0 ? torsion : Eigen::Vector3d::Zero());
        columns.push_back(w);
        // The finger holds the reaction -f at the contact: joint j supplies a . ((p - o) x f)
        // (plus the torsion's component along its axis).
        std::vector<std::pair<int, double>> torques;
        for (int j : chain) {
          const auto& joint = hand.joints()[j];
          if (!joint.movable()) continue;
          const Pose frame = poses[joint.parent_link] * joint.origin;
          const Eigen::Vector3d axis = frame.linear() * joint.axis.normalized();
          double torque = 0;
          if (joint.type == JointType::kPrismatic) {
            torque = axis.dot(f);
          } else {
            torque = axis.dot((c.point - frame.translation()).cross(f));
            if (torsion_m > 0) torque += axis.dot(torsion);
          }
          torques.emplace_back(j, torque);
        }
        joint_torques.push_back(std::move(torques));
      }
    }
  }
  // One limit row per joint some contact loads.
  std::vector<int> row_of_joint(hand.joints().size(), -1);
  int rows = 0;
  for (const auto& torques : joint_torques) {
    for (const auto& [j, torque] : torques) {
      if (row_of_joint[j] < 0) row_of_joint[j] = rows++;
    }
  }
  Eigen::MatrixXd limit_rows =
      Eigen::MatrixXd::Zero(rows, static_cast<Eigen::Index>(columns.size()));
  // A closing joint supplies torque towards closing only, up to its share of the limit; another
  // joint either way within its share.
  const std::vector<double> closing = closingDirections(hand);
  Eigen::VectorXd lower(rows), upper(rows);
  for (std::size_t j = 0; j < row_of_joint.size(); ++j) {
    const int row = row_of_joint[j];
    if (row < 0) continue;
    const double most = params.torque_share * limits[j];
    if (closing[j] > 0) {
      lower[row] = 0.0;
      upper[row] = most;
    } else if (closing[j] < 0) {
      lower[row] = -most;
      upper[row] = 0.0;
    } else {
      lower[row] = -most;
      upper[row] = most;
    }
  }
  for (std::size_t col = 0; col < joint_torques.size(); ++col) {
    for (const auto& [j, torque] : joint_torques[col]) {
      limit_rows(row_of_joint[j], static_cast<Eigen::Index>(col)) += torque;
    }
  }
  const double weight = params.mass_kg * kStandardGravityMS2;
  const Eigen::Vector3d directions[6] = {Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitX(),
                                         Eigen::Vector3d::UnitY(), -Eigen::Vector3d::UnitY(),
                                         Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitZ()};
  capacity.min = params.max_capacity;
  for (int d = 0; d < 6; ++d) {
    Wrench load;
    load << weight * directions[d], Eigen::Vector3d::Zero();
    const LoadLpResult lp =
        solveLoadLp(columns, load, limit_rows, lower, upper, params.max_capacity);
    // The bounds admit no force at all (scale 0), so the LP is always feasible.
    if (!lp.error.empty()) {
      capacity.error = lp.error;
      capacity.min = 0;
      return capacity;
    }
    capacity.per_direction[static_cast<std::size_t>(d)] = lp.scale;
    capacity.min = std::min(capacity.min, lp.scale);
  }
  return capacity;
}

}  // namespace skelgrasp::grasping
