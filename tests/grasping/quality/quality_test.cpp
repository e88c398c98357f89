// Grasp-wrench-space quality on contact sets with known answers.
#include "skelgrasp/grasping/quality/quality.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/pose.h"
#include "skelgrasp/grasping/io/contacts_io.h"
#include "test_support.h"

namespace skelgrasp::grasping {
namespace {

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
  EXPECT_FALSE(r.volume.has_value());  // only on request
  EXPECT_EQ(r.wrenches, 24);
  QualityParams with_volume;
  with_volume.compute_volume = true;
  const auto v =
      evaluateWrenchSpace(threeAroundCylinder(), Eigen::Vector3d::Zero(), 1 / 0.03, with_volume);
  ASSERT_TRUE(v.volume.has_value());
  EXPECT_GT(*v.volume, 0);
  EXPECT_NEAR(v.epsilon, r.epsilon, 1e-9);
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
  QualityParams params;
  params.compute_volume = true;
  const auto base = evaluateWrenchSpace(contacts, Eigen::Vector3d::Zero(), 1 / 0.03, params);
  Pose motion = Pose::Identity();
  motion.linear() =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  motion.translation() = Eigen::Vector3d(0.4, -1.2, 0.3);
  std::vector<Contact> moved;
  for (const auto& c : contacts)
    moved.push_back(contact(motion * c.point, motion.rotation() * c.normal));
  const auto r = evaluateWrenchSpace(moved, motion * Eigen::Vector3d::Zero(), 1 / 0.03, params);
  EXPECT_TRUE(r.force_closure);
  EXPECT_NEAR(r.epsilon, base.epsilon, 1e-9);
  EXPECT_NEAR(r.volume.value(), base.volume.value(), 1e-9);
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
  const double lean = radiansFromDegrees(30);
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

// Contact files (input of `skelgrasp quality`) are validated on reading: every problem is an
// IoError naming the file, and the contact for per-contact problems.
TEST(ContactsFile, ReadsContactsCenterAndTorqueScale) {
  const std::string path = test::tempDir("contacts_ok") + "/three.json";
  std::ofstream(path) << R"({"contacts": [{"point": [0.03, 0, 0], "normal": [2, 0, 0]},
                          {"point": [-0.015, 0.02598, 0], "normal": [-0.5, 0.866, 0]},
                          {"point": [-0.015, -0.02598, 0], "normal": [-0.5, -0.866, 0]}],
            "center": [0, 0, 0.01], "torque_scale": 40})";
  const ContactSet set = readContactsFile(path);
  ASSERT_EQ(set.contacts.size(), 3u);
  EXPECT_NEAR(set.contacts[0].normal.norm(), 1.0, 1e-12);  // normalised
  EXPECT_NEAR(set.center.z(), 0.01, 1e-12);
  EXPECT_DOUBLE_EQ(set.torque_scale, 40);
}

TEST(ContactsFile, BadFilesNameTheFileAndTheProblem) {
  const std::string dir = test::tempDir("contacts_bad");
  std::string many = R"({"contacts": [)";
  for (int i = 0; i < 101; ++i) {
    many += std::string(i ? "," : "") + R"({"point": [0.01, 0, 0], "normal": [1, 0, 0]})";
  }
  many += "]}";
  struct Case {
    std::string name, content, expected;
  };
  for (
      const Case& c : {
          Case{"empty", "  \n", "file is empty"},
          Case{"not_json", "{\"contacts\": [\n  {\"point\": [0, 0, 0],,}\n]}",
               "not valid JSON at line 2"},
          Case{"huge_coordinate",
               R"({"contacts": [{"point": [0, 0, 0], "normal": [1, 0, 0]},
                                 {"point": [1e308, 0, 0], "normal": [1, 0, 0]}]})",
               "contact 1 point is 1e+308 m from the origin, beyond the limit of 1e+03 m"},
          Case{"overflowing_coordinate",
               R"({"contacts": [{"point": [0, 0, 1e999], "normal": [1, 0, 0]}]})",
               "not valid JSON"},
          Case{"zero_normal", R"({"contacts": [{"point": [0, 0, 0], "normal": [0, 0, 0]}]})",
               "contact 0 normal has zero length"},
          Case{"string_coordinate",
               R"({"contacts": [{"point": [0, "a", 0], "normal": [1, 0, 0]}]})",
               "contact 0 point must be an array of 3 numbers"},
          Case{
              "far_center",
              R"({"contacts": [{"point": [0, 0, 0], "normal": [1, 0, 0]}], "center": [0, 5e3, 0]})",
              "center is 5e+03 m from the origin"},
          Case{"bad_torque_scale",
               R"({"contacts": [{"point": [0, 0, 0], "normal": [1, 0, 0]}], "torque_scale": -1})",
               "torque_scale must be a positive finite number"},
          Case{"no_contacts", R"({"contacts": []})", "no contacts"},
          Case{"too_many", many, "101 contacts, more than the limit of 100"},
      }) {
    const std::string path = dir + "/" + c.name + ".json";
    std::ofstream(path) << c.content;
    try {
      readContactsFile(path);
      ADD_FAILURE() << c.name << ": expected IoError";
    } catch (const IoError& e) {
      EXPECT_EQ(e.path(), path);
      EXPECT_NE(e.problem().find(c.expected), std::string::npos) << c.name << ": " << e.problem();
    }
  }
  try {
    readContactsFile(dir);
    ADD_FAILURE() << "expected IoError for a directory";
  } catch (const IoError& e) {
    EXPECT_NE(e.problem().find("is a directory"), std::string::npos) << e.problem();
  }
}

}  // namespace
}  // namespace skelgrasp::grasping
