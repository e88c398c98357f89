// The physics judge: mass properties against closed forms, the engine's hand against the hand
// model's kinematics, and executions whose outcome is known (a parallel gripper across a box holds;
// on a corner or 10 cm away it does not; an open hand inside the object is flagged; the same
// inputs give the same result).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"
#include "skelgrasp/physics/execution.h"
#include "skelgrasp/physics/physical_object.h"

namespace skelgrasp::physics {
namespace {

TEST(MassProperties, BoxMatchesTheClosedForm) {
  const Eigen::Vector3d size(0.04, 0.06, 0.1);
  TriangleMesh box = geometry::shapes::makeBox(size, 3);
  const Eigen::Vector3d offset(0.3, -0.2, 0.5);
  for (auto& v : box.vertices) v += offset;
  const MassProperties mass = massProperties(box);
  EXPECT_NEAR(mass.volume_m3, size.prod(), 1e-12);
  EXPECT_LT((mass.center_of_mass - offset).norm(), 1e-12);
  const double v = size.prod();
  const Eigen::Vector3d s = size.cwiseProduct(size);
  const Eigen::Vector3d expected(v * (s.y() + s.z()) / 12, v * (s.x() + s.z()) / 12,
                                 v * (s.x() + s.y()) / 12);
  EXPECT_LT((mass.inertia_per_density.diagonal() - expected).norm(), 1e-12);
  EXPECT_LT(std::abs(mass.inertia_per_density(0, 1)), 1e-15);
}

TEST(MassProperties, CylinderApproachesTheClosedFormAndInwardIsNegative) {
  const double r = 0.03, h = 0.12;
  TriangleMesh cylinder = geometry::shapes::makeCylinder(r, h, 256, 4);
  const MassProperties mass = massProperties(cylinder);
  const double v = kPi * r * r * h;
  EXPECT_NEAR(mass.volume_m3, v, 2e-3 * v);
  EXPECT_NEAR(mass.inertia_per_density(2, 2), v * r * r / 2, 5e-3 * v * r * r / 2);
  EXPECT_NEAR(mass.inertia_per_density(0, 0), v * (3 * r * r + h * h) / 12,
              5e-3 * v * (3 * r * r + h * h) / 12);
  cylinder.flipOrientation();
  EXPECT_LT(massProperties(cylinder).volume_m3, 0);
}

TEST(EngineHand, LinkPosesAgreeWithTheHandModel) {
  std::mt19937 rng(7);
  for (const auto& name : grasping::builtinHandNames()) {
    SCOPED_TRACE(name);
    const auto hand = grasping::loadBuiltinHand(name);
    const Pose root =
        makePose({0.1, -0.2, 0.3}, Eigen::Quaterniond(0.8, 0.1, -0.5, 0.3).normalized());
    for (int trial = 0; trial < 5; ++trial) {
      Eigen::VectorXd q = hand.zeroConfiguration();
      for (std::size_t j = 0; j < hand.joints().size(); ++j) {
        const auto& joint = hand.joints()[j];
        if (!joint.movable()) continue;
        std::uniform_real_distribution<double> in(joint.lower, joint.upper);
        q[static_cast<Eigen::Index>(j)] = in(rng);
      }
      hand.normalise(q);
      const auto expected = hand.linkPoses(q);
      const auto engine = engineLinkPoses(hand, root, q);
      ASSERT_EQ(engine.size(), expected.size());
      for (std::size_t l = 0; l < expected.size(); ++l) {
        const Pose want = root * expected[l];
        EXPECT_LT((engine[l].translation() - want.translation()).norm(), 1e-9)
            << hand.links()[l].name;
        EXPECT_LT((engine[l].linear() - want.linear()).norm(), 1e-9) << hand.links()[l].name;
      }
    }
  }
}

// A 5 x 5 x 8 cm box and the parallel gripper from above (70 N at the jaws, its datasheet's).
struct GripperCase {
  grasping::HandModel hand = grasping::loadBuiltinHand("parallel_gripper");
  TriangleMesh box = geometry::shapes::makeBox(Eigen::Vector3d(0.05, 0.05, 0.08), 2);
  std::unique_ptr<PhysicalObject> object = std::make_unique<PhysicalObject>(box);
  grasping::GraspObject grasp_object{box};

  // The gripper's grasp centre point at `gcp_position` (object frame), approaching along -z, its
  // jaws closing along (y_hint x -z).
  Pose handPose(const Eigen::Vector3d& gcp_position, const Eigen::Vector3d& y_hint) {
    grasping::GraspSimulator simulator(hand, grasp_object);
    const Pose gcp = poseFromZY(gcp_position, {0, 0, -1}, y_hint);
    return simulator.handPoseForGcp(gcp, hand.preshape("power"));
  }
  ExecutionResult execute(const Eigen::Vector3d& gcp_position,
                          const Eigen::Vector3d& y_hint = {1, 0, 0}) {
    return executeGrasp(hand, *object, handPose(gcp_position, y_hint), hand.preshape("power"));
  }
};

TEST(PhysicsJudge, ParallelGripperAcrossABoxHolds) {
  GripperCase c;
  // Jaws along y, 1 cm above the centre: the palm clears the box's top by 7 mm.
  const ExecutionResult run = c.execute({0, 0, 0.01});
  EXPECT_TRUE(run.holds) << run.reason;
  EXPECT_EQ(run.failed_phase, ExecutionPhase::kNone);
  EXPECT_LT(run.start_penetration_m, 1e-4);
  ASSERT_EQ(run.disturbances.size(), 6u);
  for (const auto& d : run.disturbances) {
    EXPECT_TRUE(d.held);
    EXPECT_LT(d.displacement_m, 0.005);
    EXPECT_LT(d.rotation_rad, radiansFromDegrees(5.0));
  }
  EXPECT_EQ(run.touching_links, (std::vector<std::string>{"left_finger", "right_finger"}));
  EXPECT_LT(run.closing_displacement_m, 0.005);
}

TEST(PhysicsJudge, ParallelGripperOnACornerDoesNotHold) {
  GripperCase c;
  // Jaws closing across the box's vertical edge at (0.025, 0.025): each meets a face at 45
  // degrees, beyond the friction cone of mu = 0.35 (19 degrees), and squeezes the box out.
  const ExecutionResult run = c.execute({0.025, 0.025, 0.01}, {-1, -1, 0});
  EXPECT_FALSE(run.holds);
  EXPECT_NE(run.failed_phase, ExecutionPhase::kStart) << run.reason;
}

TEST(PhysicsJudge, ParallelGripperTenCentimetresAwayDoesNotHold) {
  GripperCase c;
  const ExecutionResult run = c.execute({0.1, 0, 0});
  EXPECT_FALSE(run.holds);
  EXPECT_EQ(run.failed_phase, ExecutionPhase::kClosing) << run.reason;
  EXPECT_TRUE(run.touching_links.empty());
  EXPECT_TRUE(run.disturbances.empty());
}

TEST(PhysicsJudge, AnOpenHandInsideTheObjectIsFlagged) {
  const auto hand = grasping::loadBuiltinHand("parallel_gripper");
  const TriangleMesh block = geometry::shapes::makeBox(Eigen::Vector3d(0.4, 0.4, 0.4), 2);
  const PhysicalObject object(block);
  // The whole hand (about 20 x 6 x 16 cm) at the block's centre: no link crosses the surface.
  const ExecutionResult run = executeGrasp(hand, object, Pose::Identity(), hand.preshape("power"));
  EXPECT_FALSE(run.holds);
  EXPECT_EQ(run.failed_phase, ExecutionPhase::kStart);
  EXPECT_GT(run.start_penetration_m, 0.05);
  EXPECT_FALSE(run.penetrating_link.empty());
  // A hand around the box starts.
  GripperCase c;
  const ExecutionResult touching = c.execute({0, 0, 0.01});
  EXPECT_NE(touching.failed_phase, ExecutionPhase::kStart);
}

TEST(PhysicsJudge, TheSameInputsGiveTheSameExecution) {
  GripperCase c;
  const Eigen::Vector3d gcp(0.004, -0.003, 0.012);
  const ExecutionResult a = c.execute(gcp);
  const ExecutionResult b = c.execute(gcp);
  EXPECT_EQ(a.holds, b.holds);
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.joints, b.joints);
  ASSERT_EQ(a.disturbances.size(), b.disturbances.size());
  for (std::size_t i = 0; i < a.disturbances.size(); ++i) {
    EXPECT_EQ(a.disturbances[i].displacement_m, b.disturbances[i].displacement_m);
    EXPECT_EQ(a.disturbances[i].rotation_rad, b.disturbances[i].rotation_rad);
  }
}

TEST(PhysicsJudge, TorqueLimitsFollowTheFingertipForce) {
  const auto hand = grasping::loadBuiltinHand("sdh");
  JudgeParams params;
  params.fingertip_force_n = 4.0;
  const auto four = jointTorqueLimits(hand, params);
  params.fingertip_force_n = 8.0;
  const auto eight = jointTorqueLimits(hand, params);
  for (std::size_t j = 0; j < hand.joints().size(); ++j) {
    if (!hand.joints()[j].movable()) {
      EXPECT_EQ(four[j], 0.0);
      continue;
    }
    EXPECT_GT(four[j], 0.0) << hand.joints()[j].name;
    EXPECT_NEAR(eight[j], 2 * four[j], 1e-12);
    // A finger joint's lever is a few centimetres, not metres.
    EXPECT_LT(four[j], 4.0 * 0.3);
  }
  const auto gripper = grasping::loadBuiltinHand("parallel_gripper");
  ASSERT_TRUE(gripper.strength().fingertip_force_n);
  for (double limit : jointTorqueLimits(gripper, JudgeParams{})) {
    EXPECT_EQ(limit, *gripper.strength().fingertip_force_n);
  }
}

}  // namespace
}  // namespace skelgrasp::physics
