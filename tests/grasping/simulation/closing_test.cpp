// Finger closing and contacts on generated shapes with known geometry.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "skelgrasp/common/pose.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/quality/quality.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"

namespace skelgrasp::grasping {
namespace {

// The parallel gripper over a 5 x 9 x 16 cm box: approach along -y onto the 9 cm face, the jaws
// closing along x across the 5 cm width.
struct GripperOnBox {
  const HandModel gripper = loadBuiltinHand("parallel_gripper");
  const GraspObject box{geometry::shapes::makeBox({0.05, 0.09, 0.16}, 2)};
  GraspSimulator sim{gripper, box};
  const Preshape& preshape = gripper.preshape("precision");
  const Pose hand = sim.handPoseForGcp(poseFromZY({0, 0.035, 0}, {0, -1, 0}, {0, 0, 1}), preshape);
  ClosingResult close(ContactPatch patch) {
    ClosingParams params;
    params.contact_patch = patch;
    return sim.close(hand, preshape, params);
  }
};

TEST(Closing, ParallelGripperStopsAtTheBoxWidthWithOpposedContacts) {
  GripperOnBox setup;
  const HandModel& gripper = setup.gripper;
  const GraspObject& box = setup.box;
  // One contact per jaw, at the centre of its patch.
  const auto r = setup.close(ContactPatch::kCentre);
  ASSERT_TRUE(r.status.ok()) << r.status.message;
  const double opening = 2 * r.joints[gripper.jointIndex("finger_left")];
  EXPECT_NEAR(opening, 0.05, 2 * 0.0005 + 1e-9);  // within one step per jaw
  ASSERT_EQ(r.contacts.size(), 2u);
  EXPECT_NEAR(r.contacts[0].normal.dot(r.contacts[1].normal), -1.0, 1e-9);
  for (const auto& c : r.contacts) {
    EXPECT_NEAR(std::abs(c.point.x()), 0.025, 1e-6);
    EXPECT_NEAR(std::abs(c.normal.x()), 1.0, 1e-9);
    EXPECT_LE(c.distance, 0.0005 + 1e-9);
  }
  // Point contacts cannot hold the torque about the jaw axis; the gripper's soft pads can.
  EXPECT_FALSE(evaluateGrasp(r.contacts, box).force_closure);
  QualityParams soft;
  soft.torsional_friction_m = gripper.closingDefaults().torsional_friction_m;
  EXPECT_TRUE(evaluateGrasp(r.contacts, box, soft).force_closure);
}

TEST(Closing, ParallelGripperJawsPushThroughTheCornersOfTheirPatches) {
  GripperOnBox setup;
  const GraspObject& box = setup.box;
  ASSERT_EQ(ClosingParams{}.contact_patch, ContactPatch::kCorners);  // the default
  const auto one = setup.close(ContactPatch::kCentre);
  const auto r = setup.close(ContactPatch::kCorners);
  ASSERT_TRUE(r.status.ok()) << r.status.message;
  // The same closing; only where the jaws push differs.
  EXPECT_TRUE(r.joints.isApprox(one.joints));
  ASSERT_EQ(one.contacts.size(), 2u);
  ASSERT_GT(r.contacts.size(), 2u);
  ASSERT_LE(r.contacts.size(), 8u);  // at most four corners per jaw
  for (const auto& jaw : one.contacts) {
    std::vector<Eigen::Vector3d> corners;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& c : r.contacts) {
      if (c.link != jaw.link) continue;
      // On the jaw's side of the box, pushing along the same normal as its single contact.
      EXPECT_NEAR(c.point.x(), jaw.point.x(), 1e-6);
      EXPECT_NEAR(c.normal.dot(jaw.normal), 1.0, 1e-9);
      EXPECT_LE(c.distance, 0.0005 + 0.001 + 1e-9);  // within a step, plus the patch band
      corners.push_back(c.point);
      mean += c.point;
    }
    ASSERT_GE(corners.size(), 2u) << jaw.link;
    double span = 0;
    for (const auto& a : corners) {
      for (const auto& b : corners) span = std::max(span, (a - b).norm());
    }
    EXPECT_GE(span, 0.004) << jaw.link;
    // The corners surround the patch centre.
    mean /= static_cast<double>(corners.size());
    EXPECT_LT((mean - jaw.point).norm(), 0.5 * span) << jaw.link;
  }
  // Two jaws pressing along segments hold the torque about the jaw axis that two points cannot:
  // force closure with point contacts, no soft pads needed.
  EXPECT_FALSE(evaluateGrasp(one.contacts, box).force_closure);
  EXPECT_TRUE(evaluateGrasp(r.contacts, box).force_closure);
}

TEST(Closing, RejectsAHandThatStartsInCollision) {
  const HandModel gripper = loadBuiltinHand("parallel_gripper");
  const GraspObject box(geometry::shapes::makeBox({0.05, 0.09, 0.16}, 2));
  GraspSimulator sim(gripper, box);
  const auto& preshape = gripper.preshape("precision");
  const Pose hand = sim.handPoseForGcp(poseFromZY({0, 0, 0}, {0, -1, 0}, {0, 0, 1}), preshape);
  const auto r = sim.close(hand, preshape);
  EXPECT_EQ(r.status.code, StatusCode::kNoResult);
  EXPECT_EQ(r.reason, "start_collision");
  EXPECT_EQ(r.colliding_link, "hand");
}

TEST(Closing, AHandEntirelyInsideAClosedObjectCollides) {
  // No link touches a triangle, but every link is inside: that is a collision, not a free pose.
  const HandModel hand = loadBuiltinHand("armar3");
  const GraspObject block(geometry::shapes::makeBox({1.0, 1.0, 1.0}));
  GraspSimulator sim(hand, block);
  EXPECT_GE(sim.firstLinkInCollision(Pose::Identity(), hand.preshape("power").joints), 0);
  Pose outside = Pose::Identity();
  outside.translation() = Eigen::Vector3d(2, 0, 0);
  EXPECT_EQ(sim.firstLinkInCollision(outside, hand.preshape("power").joints), -1);
}

TEST(Closing, ReportsTooFewContactsWhenClosingOnNothing) {
  const HandModel gripper = loadBuiltinHand("parallel_gripper");
  const GraspObject box(geometry::shapes::makeBox({0.02, 0.02, 0.02}));
  GraspSimulator sim(gripper, box);
  const auto& preshape = gripper.preshape("precision");
  const Pose hand =
      sim.handPoseForGcp(poseFromZY({0.5, 0.5, 0.5}, {0, -1, 0}, {0, 0, 1}), preshape);
  const auto r = sim.close(hand, preshape);
  EXPECT_EQ(r.reason, "too_few_contacts");
  EXPECT_TRUE(r.contacts.empty());
  EXPECT_NEAR(r.joints[gripper.jointIndex("finger_left")], 0.0, 1e-12);  // fully closed
}

// A hand approaching an object about the z axis from +x along -x, its fingers spreading along z:
// backed off in 1 mm steps until the open hand is free of the object, as the planners place a
// hand, and closed there. `closed` stays default (not ok) when no pose up to 15 cm was free.
struct PlacedClosing {
  Pose placed = Pose::Identity();
  ClosingResult closed;
};
PlacedClosing closeBackedOffAlongX(GraspSimulator& sim, const Preshape& preshape) {
  PlacedClosing out;
  for (double x = 0.0; x < 0.15; x += 0.001) {
    out.placed = sim.handPoseForGcp(poseFromZY({x, 0, 0}, {-1, 0, 0}, {0, 0, 1}), preshape);
    if (sim.inCollision(out.placed, preshape.joints)) continue;
    out.closed = sim.close(out.placed, preshape);
    break;
  }
  return out;
}

TEST(Closing, HandsWrapACylinderWithinTheirJointLimits) {
  const GraspObject cylinder(geometry::shapes::makeCylinder(0.03, 0.2, 48, 10));
  for (const std::string name : {"armar3", "sdh", "shadow"}) {
    const HandModel hand = loadBuiltinHand(name);
    GraspSimulator sim(hand, cylinder);
    const auto [placed, r] = closeBackedOffAlongX(sim, hand.preshape("power"));
    ASSERT_TRUE(r.status.ok()) << name << ": " << r.reason;
    EXPECT_GE(r.contacts.size(), 3u) << name;
    for (std::size_t j = 0; j < hand.joints().size(); ++j) {
      EXPECT_GE(r.joints[j], hand.joints()[j].lower - 1e-9) << name;
      EXPECT_LE(r.joints[j], hand.joints()[j].upper + 1e-9) << name;
    }
    // The closed hand does not penetrate the object.
    EXPECT_FALSE(sim.inCollision(placed, r.joints)) << name;
    // Contacts lie on the cylinder surface with outward normals.
    for (const auto& c : r.contacts) {
      if (std::abs(c.point.z()) < 0.099) {
        EXPECT_NEAR(c.point.head<2>().norm(), 0.03, 1e-3) << name << " " << c.link;
        EXPECT_GT(c.normal.head<2>().dot(c.point.head<2>().normalized()), 0.9) << name;
      }
    }
  }
}

// The SDH's claw starts with its distal joints at their limit, so closing turns the proximal
// joints only and the bent fingers hook a handle from three sides with their distal links
// (docs/hands.md). A 25 mm rod, approached across its axis.
TEST(Closing, SdhClawHooksARodWithItsDistalLinksAndProximalJointsOnly) {
  const GraspObject rod(geometry::shapes::makeCylinder(0.0125, 0.2, 48, 10));
  const HandModel sdh = loadBuiltinHand("sdh");
  GraspSimulator sim(sdh, rod);
  const Preshape& claw = sdh.preshape("claw");
  const ClosingResult r = closeBackedOffAlongX(sim, claw).closed;
  ASSERT_TRUE(r.status.ok()) << r.reason;
  std::set<std::string> fingers_touching;
  for (const char* finger : {"finger1", "finger2", "thumb"}) {
    const int distal = sdh.jointIndex(std::string(finger) + "_distal_joint");
    const int proximal = sdh.jointIndex(std::string(finger) + "_proximal_joint");
    EXPECT_DOUBLE_EQ(r.joints[distal], sdh.joints()[distal].upper) << finger;
    EXPECT_GT(r.joints[proximal], claw.joints[proximal]) << finger;
  }
  for (const auto& c : r.contacts) {
    if (c.palm) continue;
    EXPECT_NE(c.link.find("_distal"), std::string::npos) << c.link;
    fingers_touching.insert(c.link.substr(0, c.link.find('_')));
  }
  EXPECT_EQ(fingers_touching, (std::set<std::string>{"finger1", "finger2", "thumb"}));
  QualityParams quality;
  quality.friction = 0.35;
  EXPECT_TRUE(evaluateGrasp(r.contacts, rod, quality).force_closure);
}

TEST(Closing, ShadowTendonMovesTheDistalPhalanxWithTheMiddleOne) {
  // J1 has no drive of its own: it follows J2 on the same tendon, and keeps going alone when the
  // middle phalanx is blocked (here by the palm, closing on nothing).
  const HandModel shadow = loadBuiltinHand("shadow");
  const GraspObject far_away(geometry::shapes::makeBox({0.01, 0.01, 0.01}));
  GraspSimulator sim(shadow, far_away);
  Pose pose = Pose::Identity();
  pose.translation() = Eigen::Vector3d(1, 1, 1);
  const auto r = sim.close(pose, shadow.preshape("power"));
  for (const std::string f : {"FF", "MF", "RF", "LF"}) {
    const double j1 = r.joints[shadow.jointIndex(f + "J1")],
                 j2 = r.joints[shadow.jointIndex(f + "J2")];
    EXPECT_GT(j2, 0.5) << f;
    EXPECT_GT(j1, 0.5) << f;                 // moved by J2's tendon
    EXPECT_LT(std::abs(j1 - j2), 0.2) << f;  // mostly together
    EXPECT_LE(j1, 1.571 + 1e-9) << f;
  }
}

TEST(Closing, UnsetStepsAreTheHandsDefaultsAndSetStepsAreUsed) {
  const HandModel gripper = loadBuiltinHand("parallel_gripper");
  const GraspObject box(geometry::shapes::makeBox({0.05, 0.09, 0.16}, 2));
  GraspSimulator sim(gripper, box);
  const auto& preshape = gripper.preshape("precision");
  const Pose hand = sim.handPoseForGcp(poseFromZY({0, 0.035, 0}, {0, -1, 0}, {0, 0, 1}), preshape);
  const int jaw = gripper.jointIndex("finger_left");
  ClosingParams explicit_defaults;
  explicit_defaults.step_m = gripper.closingDefaults().step_m;
  explicit_defaults.step_rad = gripper.closingDefaults().step_rad;
  explicit_defaults.palm_contact_distance_m = gripper.closingDefaults().palm_contact_distance_m;
  EXPECT_EQ(sim.close(hand, preshape).joints, sim.close(hand, preshape, explicit_defaults).joints);
  // A coarser step than the hand's stops the jaws up to that step from the 5 cm faces (too far
  // to count as touching, so the status may be too few contacts: the reached joints tell).
  ClosingParams coarse;
  coarse.step_m = 0.004;
  const auto r = sim.close(hand, preshape, coarse);
  EXPECT_NEAR(2 * r.joints[jaw], 0.05, 2 * 0.004 + 1e-9);
  EXPECT_GT(2 * r.joints[jaw], 0.05 + 2 * 0.0005);  // farther than the hand's step would stop
  // Zero is a step that never arrives, not "the default" any more.
  ClosingParams zero;
  zero.step_m = 0.0;
  EXPECT_THROW(sim.close(hand, preshape, zero), InvalidArgument);
}

TEST(Closing, IsDeterministic) {
  const HandModel hand = loadBuiltinHand("armar3");
  const GraspObject capsule(geometry::shapes::makeCapsule(0.025, 0.12));
  GraspSimulator a(hand, capsule), b(hand, capsule);
  const auto& preshape = hand.preshape("power");
  const Pose pose = a.handPoseForGcp(poseFromZY({0.02, 0, 0}, {-1, 0, 0}, {0, 0, 1}), preshape);
  const auto ra = a.close(pose, preshape), rb = b.close(pose, preshape);
  EXPECT_EQ(ra.joints, rb.joints);
  ASSERT_EQ(ra.contacts.size(), rb.contacts.size());
  for (std::size_t i = 0; i < ra.contacts.size(); ++i)
    EXPECT_EQ(ra.contacts[i].point, rb.contacts[i].point);
}

}  // namespace
}  // namespace skelgrasp::grasping
