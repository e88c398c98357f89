// Grasp-wrench-space quality on contact sets with known answers.
#include "skelgrasp/grasping/quality.h"

#include <gtest/gtest.h>

#include <cmath>

#include "skelgrasp/common/pose.h"

namespace skelgrasp::grasping {
namespace {

constexpr double kPi = 3.14159265358979323846;

Contact contact(const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
  Contact c;
  c.point = p;
  c.normal = n.normalized();
  return c;
}

// Three contacts at 120 degrees around a cylinder's mid-plane (radius 3 cm).
std::vector<Contact> threeAroundCylinder(double radius = 0.03) {
  std::vector<Contact> contacts;
  for (int i = 0; i < 3; ++i) {
    const double a = 2 * kPi * i / 3;
    contacts.push_back(contact(radius * Eigen::Vector3d(std::cos(a), std::sin(a), 0),
                               {std::cos(a), std::sin(a), 0}));
  }
  return contacts;
}

TEST(Quality, ConeEdgesHaveTheFrictionHalfAngle) {
  QualityParams params;
  params.friction = 0.35;
  const Eigen::Vector3d n(0, 0, 1);
  const auto edges = frictionConeEdges(n, params);
  ASSERT_EQ(edges.size(), 8u);
  for (const auto& e : edges) {
    EXPECT_NEAR(e.norm(), 1.0, 1e-12);
    EXPECT_NEAR(std::acos(e.dot(-n)), std::atan(0.35), 1e-12);  // pushes into the object
  }
  params.reference_compat = true;  // the reference's 45 degree edges
  for (const auto& e : frictionConeEdges(n, params))
    EXPECT_NEAR(std::acos(e.dot(-n)), kPi / 4, 1e-12);
}

TEST(Quality, TwoAntipodalPointContactsAreNotForceClosureIn6D) {
  const std::vector<Contact> contacts = {contact({0.03, 0, 0}, {1, 0, 0}),
                                         contact({-0.03, 0, 0}, {-1, 0, 0})};
  const auto r = evaluateWrenchSpace(contacts, Eigen::Vector3d::Zero(), 1 / 0.03);
  EXPECT_FALSE(r.force_closure);
  EXPECT_EQ(r.rank, 5);  // no torque about the contact line
  EXPECT_EQ(r.epsilon, 0.0);
  // Soft fingers resist that torque.
  QualityParams soft;
  soft.torsional_friction_m = 0.003;
  EXPECT_TRUE(evaluateWrenchSpace(contacts, Eigen::Vector3d::Zero(), 1 / 0.03, soft).force_closure);
}

TEST(Quality, ThreeFrictionalContactsAroundACylinderAreForceClosure) {
  const auto r = evaluateWrenchSpace(threeAroundCylinder(), Eigen::Vector3d::Zero(), 1 / 0.03);
  EXPECT_TRUE(r.force_closure);
  EXPECT_GT(r.epsilon, 0.05);
  EXPECT_GT(r.volume, 0);
  EXPECT_EQ(r.wrenches, 24);
}

TEST(Quality, ContactsOnOneFaceAreNotForceClosure) {
  std::vector<Contact> contacts;
  for (double x : {-0.02, 0.0, 0.02}) {
    for (double y : {-0.02, 0.02}) contacts.push_back(contact({x, y, 0.05}, {0, 0, 1}));
  }
  const auto r = evaluateWrenchSpace(contacts, Eigen::Vector3d::Zero(), 1 / 0.05);
  EXPECT_FALSE(r.force_closure);
  EXPECT_EQ(r.epsilon, 0.0);
}

TEST(Quality, EpsilonGrowsWithFriction) {
  double previous = 0;
  for (double mu : {0.2, 0.35, 0.5, 0.8}) {
    QualityParams params;
    params.friction = mu;
    const auto r =
        evaluateWrenchSpace(threeAroundCylinder(), Eigen::Vector3d::Zero(), 1 / 0.03, params);
    ASSERT_TRUE(r.force_closure) << mu;
    EXPECT_GT(r.epsilon, previous) << mu;
    previous = r.epsilon;
  }
}

TEST(Quality, EpsilonIsInvariantToRigidMotionOfTheGrasp) {
  const auto contacts = threeAroundCylinder();
  const auto base = evaluateWrenchSpace(contacts, Eigen::Vector3d::Zero(), 1 / 0.03);
  Pose motion = Pose::Identity();
  motion.linear() =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  motion.translation() = Eigen::Vector3d(0.4, -1.2, 0.3);
  std::vector<Contact> moved;
  for (const auto& c : contacts)
    moved.push_back(contact(motion * c.point, motion.rotation() * c.normal));
  const auto r = evaluateWrenchSpace(moved, motion * Eigen::Vector3d::Zero(), 1 / 0.03);
  EXPECT_TRUE(r.force_closure);
  EXPECT_NEAR(r.epsilon, base.epsilon, 1e-9);
  EXPECT_NEAR(r.volume, base.volume, 1e-9);
}

TEST(Quality, ReferenceCompatMeasuresFromTheHullCentre) {
  QualityParams compat;
  compat.reference_compat = true;
  const auto r =
      evaluateWrenchSpace(threeAroundCylinder(), Eigen::Vector3d::Zero(), 1 / 0.03, compat);
  EXPECT_TRUE(r.force_closure);
  EXPECT_GT(r.epsilon, 0);
  // The 45 degree cones accept a wedge: two pairs of contacts whose normals lean 30 degrees
  // towards +y, so every force pushes towards -y unless friction beyond atan(0.35) = 19.3 degrees
  // tilts it back. Force closure for the reference, not for mu = 0.35.
  const double lean = 30 * kPi / 180;
  std::vector<Contact> wedge;
  for (double z : {-0.02, 0.02}) {
    wedge.push_back(contact({0.03, 0, z}, {std::cos(lean), std::sin(lean), 0}));
    wedge.push_back(contact({-0.03, 0, z}, {-std::cos(lean), std::sin(lean), 0}));
  }
  EXPECT_TRUE(evaluateWrenchSpace(wedge, Eigen::Vector3d::Zero(), 1 / 0.036, compat).force_closure);
  EXPECT_FALSE(evaluateWrenchSpace(wedge, Eigen::Vector3d::Zero(), 1 / 0.036).force_closure);
  QualityParams grippy;
  grippy.friction = 0.7;  // 35 degrees > 30: the wedge holds
  EXPECT_TRUE(evaluateWrenchSpace(wedge, Eigen::Vector3d::Zero(), 1 / 0.036, grippy).force_closure);
}

TEST(Quality, RejectsBadParameters) {
  QualityParams bad;
  bad.cone_edges = 2;
  EXPECT_THROW(evaluateWrenchSpace(threeAroundCylinder(), Eigen::Vector3d::Zero(), 1, bad),
               InvalidArgument);
  EXPECT_THROW(evaluateWrenchSpace(threeAroundCylinder(), Eigen::Vector3d::Zero(), 0),
               InvalidArgument);
}

}  // namespace
}  // namespace skelgrasp::grasping
