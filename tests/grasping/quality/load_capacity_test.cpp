// The load capacity (load_capacity.h) and its LP (solveLoadLp, quality.h) on cases with a known
// answer.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/pose.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/hand/hand_strength.h"
#include "skelgrasp/grasping/quality/load_capacity.h"
#include "skelgrasp/grasping/quality/quality.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"

namespace skelgrasp::grasping {
namespace {

constexpr double kPi = 3.14159265358979323846;

// One force along +x as a wrench on the object, and a joint row that loads it by `torque`.
std::vector<Wrench> pushAlongX() {
  Wrench w;
  w << 1, 0, 0, 0, 0, 0;
  return {w};
}

Wrench pullAlongMinusX(double newtons) {
  Wrench load;
  load << -newtons, 0, 0, 0, 0, 0;
  return load;
}

TEST(LoadLp, AJointThatOnlyPushesCannotHoldALoadItWouldHaveToPull) {
  // The contact force x balances the load: x = scale. Its joint supplies -x of torque.
  const auto columns = pushAlongX();
  const Eigen::MatrixXd row = Eigen::MatrixXd::Constant(1, 1, -1.0);
  const auto bounds = [](double lo, double hi) {
    Eigen::VectorXd lower(1), upper(1);
    lower << lo;
    upper << hi;
    return std::pair{lower, upper};
  };
  const auto [both_lo, both_hi] = bounds(-10, 10);
  const LoadLpResult either_way =
      solveLoadLp(columns, pullAlongMinusX(1.0), row, both_lo, both_hi, 100);
  ASSERT_TRUE(either_way.error.empty()) << either_way.error;
  EXPECT_NEAR(either_way.scale, 10.0, 1e-9);  // the joint's limit, 10 N m per unit force
  const auto [push_lo, push_hi] = bounds(0, 10);
  const LoadLpResult pushing =
      solveLoadLp(columns, pullAlongMinusX(1.0), row, push_lo, push_hi, 100);
  ASSERT_TRUE(pushing.error.empty()) << pushing.error;
  EXPECT_TRUE(pushing.feasible);
  EXPECT_NEAR(pushing.scale, 0.0, 1e-12);
  // A lower bound the force can only meet by pulling: no balance at all.
  const auto [pressing_lo, pressing_hi] = bounds(1, 10);
  const LoadLpResult pressing =
      solveLoadLp(columns, pullAlongMinusX(1.0), row, pressing_lo, pressing_hi, 100);
  ASSERT_TRUE(pressing.error.empty()) << pressing.error;
  EXPECT_FALSE(pressing.feasible);
  EXPECT_EQ(pressing.scale, 0.0);
  // A caller's mistake: a lower bound above the upper.
  EXPECT_THROW(solveLoadLp(columns, pullAlongMinusX(1.0), row, push_hi, push_lo, 100),
               InvalidArgument);
}

// The parallel gripper across a 5 cm box, one contact at the centre of each jaw (x = +-2.5 cm),
// level with the centre of mass: the jaws' centres lie 8.7 mm beyond the grasp centre point, which
// sits 1 cm inside the box's 3.74 cm side.
constexpr double kBoxDepthM = 0.0374;
struct GripperAcrossBox {
  const HandModel gripper = loadBuiltinHand("parallel_gripper");
  const GraspObject box{geometry::shapes::makeBox({0.05, kBoxDepthM, 0.16}, 2)};
  GraspSimulator sim{gripper, box};
  const Preshape& preshape = gripper.preshape("precision");
  const Pose hand = sim.handPoseForGcp(
      poseFromZY({0, kBoxDepthM / 2 - 0.01, 0}, {0, -1, 0}, {0, 0, 1}), preshape);
  ClosingResult closed() {
    ClosingParams params;
    params.contact_patch = ContactPatch::kCentre;
    return sim.close(hand, preshape, params);
  }
};

TEST(LoadCapacity, GripperAcrossABoxCarriesWhatItsJawsAndFrictionAllow) {
  GripperAcrossBox setup;
  const ClosingResult r = setup.closed();
  ASSERT_TRUE(r.status.ok()) << r.status.message;
  ASSERT_EQ(r.contacts.size(), 2u);
  for (const auto& c : r.contacts) ASSERT_NEAR((c.point - setup.box.centerOfMass()).y(), 0.0, 5e-4);
  const QualityParams quality = withHandContactModel({}, setup.gripper);
  LoadCapacityParams params;
  params.mass_kg = 10;  // heavy enough that no direction reaches max_capacity
  params.torque_share = kGripTorqueShare;
  const LoadCapacity capacity = loadCapacity(setup.gripper, setup.hand, r.joints, r.contacts,
                                             setup.box.centerOfMass(), quality, params);
  ASSERT_TRUE(capacity.error.empty()) << capacity.error;
  // Along the jaws (x) one jaw pushes the whole weight: its force limit x the share.
  const double jaw_n = kGripTorqueShare * fingertipForceN(setup.gripper);
  const double weight_n = params.mass_kg * kStandardGravityMS2;
  // (Within 2 %: the contacts' half a millimetre off the centre of mass costs friction.)
  EXPECT_NEAR(capacity.per_direction[0], jaw_n / weight_n, 0.02 * jaw_n / weight_n);
  EXPECT_NEAR(capacity.per_direction[1], jaw_n / weight_n, 0.02 * jaw_n / weight_n);
  // Across them (y, z) both jaws press their limit and friction carries mu of it, less the
  // linearised cone's inscribed share.
  const int edges = quality.cone_edges;
  const double most = 2 * jaw_n * quality.friction / weight_n;
  for (int d = 2; d < 6; ++d) {
    EXPECT_LE(capacity.per_direction[static_cast<std::size_t>(d)], most * 1.001) << d;
    EXPECT_GE(capacity.per_direction[static_cast<std::size_t>(d)],
              0.98 * most * std::cos(kPi / edges))
        << d;
  }
  double least = capacity.per_direction[0];
  for (double c : capacity.per_direction) least = std::min(least, c);
  EXPECT_DOUBLE_EQ(capacity.min, least);
  // Twice the mass, half the capacity (no direction is capped).
  params.mass_kg *= 2;
  const LoadCapacity heavier = loadCapacity(setup.gripper, setup.hand, r.joints, r.contacts,
                                            setup.box.centerOfMass(), quality, params);
  for (std::size_t d = 0; d < 6; ++d)
    EXPECT_NEAR(heavier.per_direction[d], capacity.per_direction[d] / 2, 1e-6) << d;
}

TEST(LoadCapacity, RejectsCallersMistakes) {
  GripperAcrossBox setup;
  const ClosingResult r = setup.closed();
  ASSERT_TRUE(r.status.ok()) << r.status.message;
  const auto capacityWith = [&](LoadCapacityParams params) {
    return loadCapacity(setup.gripper, setup.hand, r.joints, r.contacts, setup.box.centerOfMass(),
                        QualityParams{}, params);
  };
  LoadCapacityParams p;
  p.mass_kg = 0;
  EXPECT_THROW(capacityWith(p), InvalidArgument);
  p = {};
  p.torque_share = 1.5;
  EXPECT_THROW(capacityWith(p), InvalidArgument);
  p = {};
  p.max_capacity = std::nan("");
  EXPECT_THROW(capacityWith(p), InvalidArgument);
}

}  // namespace
}  // namespace skelgrasp::grasping
