// Settling (grasping/quality/settling.h): the squeeze LP on analytic contact sets, and the
// object settling in closing hands on analytic shapes where the physics is known (a cylinder pulled
// into a power grasp, a cone squeezed out of parallel jaws when it is steeper than the friction
// cone).
#include "skelgrasp/grasping/quality/settling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/pose.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/quality/quality.h"

#include <nlohmann/json.hpp>

namespace skelgrasp::grasping {
namespace {

// A contact's cone-edge wrenches with its pushing group, and the wrench of its unit inward normal
// force, as settling builds them (about the origin, torque scale 1).
struct SqueezeInput {
  std::vector<Wrench> wrenches;
  std::vector<int> group;
  std::vector<double> normal;
  std::vector<Wrench> pressing;

  void add(const Eigen::Vector3d& point, const Eigen::Vector3d& outward, int finger,
           const QualityParams& quality = {}) {
    Contact c;
    c.point = point;
    c.normal = outward.normalized();
    for (const auto& w : contactWrenches({c}, Eigen::Vector3d::Zero(), 1.0, quality)) {
      wrenches.push_back(w);
      group.push_back(finger);
      normal.push_back(w.head<3>().dot(-c.normal));
    }
    Wrench press;
    press << -c.normal, point.cross(-c.normal);
    pressing.push_back(press);
  }
  SqueezeLpResult solve() const { return solveSqueezeLp(wrenches, group, normal, pressing); }
};

TEST(SqueezeLp, OneFingerPushesTheObjectAlongItsInwardNormal) {
  SqueezeInput in;
  in.add({0, 0, 0.05}, {0, 0, 1}, 0);
  const auto squeeze = in.solve();
  ASSERT_TRUE(squeeze.error.empty()) << squeeze.error;
  EXPECT_FALSE(squeeze.balanced);
  // The least unbalanced push is the normal force itself (a cone edge has a larger L1 norm), and
  // it acts through the origin: no torque.
  EXPECT_NEAR(squeeze.residual.head<3>().normalized().dot(Eigen::Vector3d(0, 0, -1)), 1.0, 1e-9);
  EXPECT_NEAR(squeeze.residual.tail<3>().norm(), 0.0, 1e-9);
}

TEST(SqueezeLp, OpposedFingersBalanceAndAPalmHoldsAFingerPushingAtIt) {
  SqueezeInput pinch;
  pinch.add({0.03, 0, 0}, {1, 0, 0}, 0);
  pinch.add({-0.03, 0, 0}, {-1, 0, 0}, 1);
  EXPECT_TRUE(pinch.solve().balanced);
  // Within the friction cone (10 degrees off opposed at mu = 0.35, a 19.3 degree cone): balanced.
  SqueezeInput tilted;
  tilted.add({0.03, 0, 0}, {1, 0, 0}, 0);
  const double tilt = radiansFromDegrees(10.0);
  tilted.add({-0.03, 0, 0}, {-std::cos(tilt), std::sin(tilt), 0}, 1);
  EXPECT_TRUE(tilted.solve().balanced);
  SqueezeInput palm;
  palm.add({0, 0, 0.03}, {0, 0, 1}, 0);
  palm.add({0, 0, -0.03}, {0, 0, -1}, -1);  // passive
  EXPECT_TRUE(palm.solve().balanced);
  // Nothing pushes: nothing moves.
  SqueezeInput palm_only;
  palm_only.add({0, 0, -0.03}, {0, 0, -1}, -1);
  EXPECT_TRUE(palm_only.solve().balanced);
}

TEST(SqueezeLp, AWedgeSteeperThanTheFrictionConeSquirtsOutAlongItsAxis) {
  // Two fingers squeeze across x on faces tilted by the half-angle about z, opening towards +y:
  // beyond the friction angle (19.3 degrees at mu = 0.35) the object is pushed towards +y.
  for (const double half_angle_deg : {10.0, 30.0}) {
    const double a = radiansFromDegrees(half_angle_deg);
    SqueezeInput in;
    in.add({0.02, 0, 0}, {std::cos(a), -std::sin(a), 0}, 0);
    in.add({-0.02, 0, 0}, {-std::cos(a), -std::sin(a), 0}, 1);
    const auto squeeze = in.solve();
    ASSERT_TRUE(squeeze.error.empty());
    if (half_angle_deg < 19.0) {
      EXPECT_TRUE(squeeze.balanced) << half_angle_deg;
    } else {
      ASSERT_FALSE(squeeze.balanced) << half_angle_deg;
      EXPECT_GT(squeeze.residual.head<3>().normalized().y(), 0.99) << half_angle_deg;
    }
  }
}

TEST(SqueezeLp, TheResidualDrivesTheObjectIntoNoContact) {
  // Random contact sets, some fingers and some palm contacts: moving along the residual never
  // closes in on a contact (first order), and a balanced squeeze leaves no residual.
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_int_distribution<int> contacts_of(1, 6), group_of(-1, 3);
  int balanced = 0, pushed = 0;
  for (int set = 0; set < 300; ++set) {
    SqueezeInput in;
    const int n = contacts_of(rng);
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector3d p(gauss(rng), gauss(rng), gauss(rng));
      in.add(0.05 * p.normalized(), p + 0.5 * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)),
             group_of(rng));
    }
    const auto squeeze = in.solve();
    ASSERT_TRUE(squeeze.error.empty()) << set;
    for (const auto& press : in.pressing) EXPECT_GE(squeeze.residual.dot(press), -1e-9) << set;
    if (squeeze.balanced) {
      ++balanced;
      EXPECT_LT(squeeze.residual.lpNorm<1>(), 1e-6) << set;
    } else {
      ++pushed;
    }
  }
  EXPECT_GT(balanced, 10);
  EXPECT_GT(pushed, 10);
}

TEST(SqueezeLp, RejectsInputOfMismatchedSizes) {
  EXPECT_THROW(solveSqueezeLp({}, {}, {}), InvalidArgument);
  EXPECT_THROW(solveSqueezeLp({Wrench::Ones()}, {0, 1}, {1.0}), InvalidArgument);
  EXPECT_THROW(solveSqueezeLp({Wrench::Ones()}, {0}, {std::nan("")}), InvalidArgument);
}

// The first collision-free hand pose coming in along -x towards the cylinder's axis, with the
// grasp centre point `offset_m` off the axis along y (across the closing fingers of a power grasp).
Pose powerPoseBeside(GraspSimulator& sim, const Preshape& preshape, double offset_m) {
  for (double x = 0.0; x < 0.15; x += 0.001) {
    const Pose placed =
        sim.handPoseForGcp(poseFromZY({x, offset_m, 0}, {-1, 0, 0}, {0, 0, 1}), preshape);
    if (!sim.inCollision(placed, preshape.joints)) return placed;
  }
  ADD_FAILURE() << "no free pose";
  return Pose::Identity();
}

bool holdsStill(GraspSimulator& sim, const Pose& pose, const Preshape& preshape,
                const QualityParams& quality) {
  const auto still = sim.close(pose, preshape);
  return still.status.ok() && evaluateGrasp(still.contacts, sim.object(), quality).force_closure;
}

TEST(Settling, TheSdhPullsACylinderIntoItsPowerGraspAndHoldingHandsStayPut) {
  const GraspObject cylinder(geometry::shapes::makeCylinder(0.03, 0.2, 48, 10));
  for (const std::string name : {"armar3", "sdh", "shadow"}) {
    const HandModel hand = loadBuiltinHand(name);
    GraspSimulator sim(hand, cylinder);
    const auto& preshape = hand.preshape("power");
    const QualityParams quality = withHandContactModel({}, hand);
    for (const double offset : {0.0, 0.008, 0.015}) {
      SCOPED_TRACE(name + " offset " + std::to_string(offset));
      const Pose start = powerPoseBeside(sim, preshape, offset);
      const SettlingResult settled = settleGrasp(sim, start, preshape, {}, quality);
      // The settled hand never ends inside the object, and the travel stays within its bound.
      EXPECT_FALSE(sim.inCollision(settled.hand_pose, settled.closing.joints));
      EXPECT_LE(settled.travel_m, SettlingParams{}.max_travel_m + SettlingParams{}.step_m);
      if (holdsStill(sim, start, preshape, quality)) {
        // A grasp that holds the object still needs no settling: nothing moves.
        EXPECT_EQ(settled.outcome, SettlingOutcome::kForceClosure);
        EXPECT_EQ(settled.steps, 0);
        EXPECT_TRUE(settled.hand_pose.isApprox(start));
      }
    }
  }
  // ARMAR-III's power grasp wraps the cylinder wherever it lands within 15 mm of the axis.
  const HandModel armar = loadBuiltinHand("armar3");
  GraspSimulator armar_sim(armar, cylinder);
  const QualityParams armar_quality = withHandContactModel({}, armar);
  for (const double offset : {0.0, 0.008, 0.015}) {
    EXPECT_TRUE(holdsStill(armar_sim, powerPoseBeside(armar_sim, armar.preshape("power"), offset),
                           armar.preshape("power"), armar_quality))
        << offset;
  }
  // The SDH's three fingertips first touch the centred cylinder behind its axis: held still, that
  // is no closure; free, the fingertips pull it into the palm, where it is held.
  const HandModel sdh = loadBuiltinHand("sdh");
  GraspSimulator sim(sdh, cylinder);
  const auto& power = sdh.preshape("power");
  const QualityParams quality = withHandContactModel({}, sdh);
  const Pose start = powerPoseBeside(sim, power, 0.0);
  ASSERT_FALSE(holdsStill(sim, start, power, quality));
  const SettlingResult settled = settleGrasp(sim, start, power, {}, quality);
  EXPECT_EQ(settled.outcome, SettlingOutcome::kForceClosure);
  EXPECT_GT(settled.steps, 0);
  // The approach is -x: the object moving into the palm is the hand moving along -x relative to
  // the object, by more than 2 cm.
  const Eigen::Vector3d approach(-1, 0, 0);
  EXPECT_GT((settled.hand_pose.translation() - start.translation()).dot(approach), 0.02);
}

TEST(Settling, SkippingTheClosureTestWhileUnbalancedChangesNoOutcome) {
  // Force closure implies a balanced squeeze, so the shortcut (squeeze first, no closure LP while
  // it is unbalanced) must end every settling where the plain order does: same outcome, same
  // steps, same final pose. Power and precision closings of the three paper hands on a cylinder
  // and a sphere, the start poses perturbed as robustness samples are (10 mm, 5 degrees).
  std::mt19937_64 rng(16);
  std::normal_distribution<double> position(0.0, 0.01), angle(0.0, 5.0 * kPi / 180.0);
  SettlingParams plain;
  plain.skip_closure_test_when_unbalanced = false;
  const SettlingParams shortcut;
  int settled_with_steps = 0, compared = 0;
  for (const auto& mesh : {geometry::shapes::makeCylinder(0.03, 0.2, 48, 10),
                           geometry::shapes::makeSphere(0.035, 48, 24)}) {
    const GraspObject object(mesh);
    for (const std::string name : {"armar3", "sdh", "shadow"}) {
      const HandModel hand = loadBuiltinHand(name);
      GraspSimulator sim(hand, object);
      const QualityParams quality = withHandContactModel({}, hand);
      for (const std::string preshape_name : {"power", "precision"}) {
        const auto& preshape = hand.preshape(preshape_name);
        const Pose start = powerPoseBeside(sim, preshape, 0.0);
        for (int i = 0; i < 12; ++i) {
          SCOPED_TRACE(name + " " + preshape_name + " sample " + std::to_string(i));
          Pose perturbed = Pose::Identity();
          perturbed.linear() = (Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitY()) *
                                Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitZ()))
                                   .toRotationMatrix();
          perturbed.translation() = Eigen::Vector3d(position(rng), position(rng), position(rng));
          const Pose pose = perturbed * start;
          const SettlingResult a = settleGrasp(sim, pose, preshape, {}, quality, plain);
          const SettlingResult b = settleGrasp(sim, pose, preshape, {}, quality, shortcut);
          ++compared;
          settled_with_steps += a.steps > 0;
          EXPECT_EQ(a.outcome, b.outcome);
          EXPECT_EQ(a.steps, b.steps);
          EXPECT_TRUE(a.hand_pose.isApprox(b.hand_pose, 0.0));
          EXPECT_EQ(a.closing.contacts.size(), b.closing.contacts.size());
        }
      }
    }
  }
  // The comparison covers settlings that moved the object, where the shortcut applies (33 of the
  // 144 when written).
  EXPECT_EQ(compared, 144);
  EXPECT_GE(settled_with_steps, 20);
}

TEST(Settling, AConeSteeperThanTheFrictionConeSquirtsOutOfParallelJaws) {
  // The gripper's jaws squeeze a frustum (axis z) across its middle. A 9.5 degree side is inside
  // the 19.3 degree friction cone at mu = 0.35: held. A 31 degree side is not: the squeeze pushes
  // the frustum towards its wide end (-z) until the jaws close past its narrow top.
  const HandModel gripper = loadBuiltinHand("parallel_gripper");
  const QualityParams quality = withHandContactModel({}, gripper);
  const auto& preshape = gripper.preshape("precision");
  constexpr double kHeightM = 0.05, kBottomRadiusM = 0.03;
  for (const double top_radius : {0.0216, 0.005}) {
    const bool steep = top_radius < 0.01;
    SCOPED_TRACE(steep ? "steep" : "shallow");
    const GraspObject frustum(
        geometry::shapes::makeFrustum(kBottomRadiusM, top_radius, kHeightM, 64));
    GraspSimulator sim(gripper, frustum);
    Pose start = Pose::Identity();
    for (double y = 0.0; y < 0.15; y += 0.001) {
      start = sim.handPoseForGcp(poseFromZY({0, y, kHeightM / 2}, {0, -1, 0}, {0, 0, 1}), preshape);
      if (!sim.inCollision(start, preshape.joints)) break;
    }
    const SettlingResult settled = settleGrasp(sim, start, preshape, {}, quality);
    if (!steep) {
      EXPECT_EQ(settled.outcome, SettlingOutcome::kForceClosure);
      EXPECT_EQ(settled.steps, 0);
      continue;
    }
    EXPECT_FALSE(holdsStill(sim, start, preshape, quality));
    EXPECT_EQ(settled.outcome, SettlingOutcome::kTooFewContacts);
    // The frustum moved down, i.e. the hand up relative to it, along the axis only.
    const Eigen::Vector3d moved = settled.hand_pose.translation() - start.translation();
    EXPECT_GT(moved.z(), 0.02);
    EXPECT_LT(moved.head<2>().norm(), 0.002);
  }
}

TEST(Settling, RejectsBadParameters) {
  const HandModel gripper = loadBuiltinHand("parallel_gripper");
  const GraspObject box(geometry::shapes::makeBox({0.05, 0.09, 0.16}, 2));
  GraspSimulator sim(gripper, box);
  const auto& preshape = gripper.preshape("precision");
  const Pose pose = sim.handPoseForGcp(poseFromZY({0, 0.035, 0}, {0, -1, 0}, {0, 0, 1}), preshape);
  const auto settle = [&](SettlingParams params) {
    return settleGrasp(sim, pose, preshape, {}, {}, params);
  };
  SettlingParams p;
  p.step_m = 0;
  EXPECT_THROW(settle(p), InvalidArgument);
  p = {};
  p.min_step_m = 2 * p.step_m;
  EXPECT_THROW(settle(p), InvalidArgument);
  p = {};
  p.max_travel_m = -1;
  EXPECT_THROW(settle(p), InvalidArgument);
  p = {};
  p.max_steps = -1;
  EXPECT_THROW(settle(p), InvalidArgument);
  p = {};
  p.pushing_distance_m = std::nan("");
  EXPECT_THROW(settle(p), InvalidArgument);
  EXPECT_NO_THROW(settle({}));
}

// The built-in gripper with its real coupling: the right jaw mimics the left (one finger, one
// drive), as the Franka hand's fingers do.
HandModel coupledGripper() {
  HandFiles files = builtinHandFiles("parallel_gripper");
  const std::string right_axis = "<axis xyz=\"0 -1 0\"/>";
  const auto at = files.urdf.find(right_axis);
  EXPECT_NE(at, std::string::npos);
  files.urdf.insert(at + right_axis.size(), "<mimic joint=\"finger_left\"/>");
  auto description = nlohmann::json::parse(files.description);
  auto& fingers = description["fingers"];
  fingers[0]["links"]["right_finger"] = "all";
  fingers.erase(1);
  for (auto& [name, preshape] : description["preshapes"].items())
    preshape["joints"].erase("finger_right");
  return loadHandFromText(files.urdf, description.dump(), "", "coupled gripper");
}

TEST(Settling, ACoupledGripperSettlesToTheContactsOfIndependentJaws) {
  // The built-in gripper's jaws close independently with the object held still, standing for a
  // coupled gripper whose first jaw to touch pushes the object until the other touches
  // (docs/hands.md). Settling lets the object slide in the gripper with its real coupling:
  //  * jaws shifted off the middle of a box or a cylinder (across and along the jaws): the two
  //    models reach the same contacts, so they agree on whether the grasp holds;
  //  * jaws also rolled about the approach, so that they meet the box's faces at points far apart
  //    along the jaw: held still that is no closure, but the squeeze turns the free box until the
  //    contacts face each other. Settled, the coupled gripper holds wherever the independent jaws
  //    hold, and more often.
  const HandModel independent = loadBuiltinHand("parallel_gripper");
  const HandModel coupled = coupledGripper();
  ASSERT_EQ(coupled.fingers().size(), 1u);
  const auto& open_jaws = independent.preshape("precision");
  const auto& coupled_open = coupled.preshape("precision");
  const QualityParams quality = withHandContactModel({}, independent);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> offset(-0.012, 0.012), tilt(-0.15, 0.15);
  int shifted = 0, shifted_agree = 0, rolled = 0, rolled_lost = 0;
  int rolled_still_holds = 0, rolled_settled_holds = 0, coupled_still = 0, independent_holds = 0;
  for (const auto& mesh : {geometry::shapes::makeBox({0.05, 0.09, 0.16}, 2),
                           geometry::shapes::makeCylinder(0.025, 0.16, 48, 6)}) {
    const GraspObject object(mesh);
    GraspSimulator free_jaws(independent, object), coupled_jaws(coupled, object);
    for (int i = 0; i < 40; ++i) {
      // Approach along -y, jaws across x, shifted across (x) and along (z) the jaws; half the
      // poses rolled about the approach.
      const bool roll_it = i % 2 == 1;
      const double dx = offset(rng), dz = offset(rng), roll = roll_it ? tilt(rng) : 0.0;
      const Eigen::Vector3d z(0, -1, 0);
      const Eigen::Vector3d y = Eigen::AngleAxisd(roll, z) * Eigen::Vector3d(0, 0, 1);
      Pose start = Pose::Identity();
      bool found = false;
      for (double standoff = 0.0; standoff < 0.15 && !found; standoff += 0.001) {
        start = free_jaws.handPoseForGcp(poseFromZY({dx, 0.03 + standoff, dz}, z, y), open_jaws);
        found = !free_jaws.inCollision(start, open_jaws.joints);
      }
      ASSERT_TRUE(found);
      const bool held = holdsStill(free_jaws, start, open_jaws, quality);
      const bool settled_holds =
          settleGrasp(coupled_jaws, start, coupled_open, {}, quality).force_closure();
      coupled_still += holdsStill(coupled_jaws, start, coupled_open, quality);
      independent_holds += held;
      if (roll_it) {
        ++rolled;
        rolled_lost += held && !settled_holds;
        rolled_still_holds += held;
        rolled_settled_holds += settled_holds;
      } else {
        ++shifted;
        shifted_agree += held == settled_holds;
      }
    }
  }
  std::cout << "[ coupled  ] shifted jaws: the models agree on " << shifted_agree << " of "
            << shifted << "; rolled: independent jaws hold " << rolled_still_holds
            << ", settled coupled jaws " << rolled_settled_holds << " of " << rolled << std::endl;
  // Held still, the coupled gripper touches with one jaw whenever the object is off its middle.
  EXPECT_LT(coupled_still, independent_holds / 4);
  EXPECT_GE(shifted_agree, shifted * 19 / 20);
  EXPECT_EQ(rolled_lost, 0);
  EXPECT_GT(rolled_settled_holds, rolled_still_holds + rolled / 4);
}

}  // namespace
}  // namespace skelgrasp::grasping
