// The real hand models (Simox / ROS facts with their collision meshes, ../shared/data/hands) load
// through the same URDF + grasp-description path as the built-in hands, and closing with the real
// meshes and with our primitive approximations gives similar results.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "real_hand_urdf.h"
#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/quality/quality.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"
#include "test_support.h"

namespace skelgrasp::grasping {
namespace {

struct RealHand {
  const char* folder;
  const char* builtin;
};
const RealHand kHands[] = {{"armar3_right_hand", "armar3"},
                           {"schunk_sdh", "sdh"},
                           {"shadow_hand", "shadow"},
                           {"franka_hand", "parallel_gripper"}};

std::string descriptionPath(const std::string& builtin) {
  return std::string(SKELGRASP_SOURCE_DIR) + "/grasping/hands/" + builtin + "/" + builtin +
         ".grasp.json";
}

HandModel loadRealHand(const RealHand& h) {
  const std::string dir = test::tempDir(std::string("real_") + h.builtin);
  const std::string urdf =
      test::writeRealHandUrdf(test::sharedDataDir() + "/hands/" + h.folder, h.builtin, dir);
  return loadHand(urdf, descriptionPath(h.builtin));
}

class RealHands : public ::testing::TestWithParam<RealHand> {};

TEST_P(RealHands, LoadWithMeshesAndMatchTheBuiltInKinematics) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  const HandModel real = loadRealHand(GetParam());
  const HandModel ours = loadBuiltinHand(GetParam().builtin);
  EXPECT_EQ(real.fingers().size(), ours.fingers().size());
  EXPECT_EQ(real.numDrives(), ours.numDrives());
  std::size_t mesh_shapes = 0;
  for (const auto& link : real.links()) {
    for (const auto& shape : link.shapes) mesh_shapes += shape.type == ShapeType::kMesh;
  }
  EXPECT_GT(mesh_shapes, 2u);
  for (const auto& [name, preshape] : ours.preshapes()) {
    const Pose a = ours.gcpInRoot(preshape), b = real.gcpInRoot(real.preshape(name));
    EXPECT_LT((a.translation() - b.translation()).norm(), 1e-4) << name;
    EXPECT_TRUE(a.rotation().isApprox(b.rotation(), 1e-4)) << name;
  }
}

// Closes both models from the same poses around a few objects and compares the outcome.
TEST_P(RealHands, ClosingWithRealMeshesIsCloseToThePrimitiveApproximation) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  const HandModel real = loadRealHand(GetParam());
  const HandModel ours = loadBuiltinHand(GetParam().builtin);
  std::vector<std::pair<std::string, TriangleMesh>> objects = {
      {"cylinder", geometry::shapes::makeCylinder(0.03, 0.2, 48, 10)},
      {"box", geometry::shapes::makeBox({0.05, 0.07, 0.15}, 3)}};
  objects.emplace_back("mustard",
                       loadMesh(test::sharedDataDir() + "/objects/ycb/006_mustard_bottle.ply"));
  double joint_error_sum = 0;
  int joints_compared = 0, grasps = 0, same_contact_count = 0, same_closure = 0;
  for (const auto& [object_name, mesh] : objects) {
    const GraspObject object(mesh);
    GraspSimulator sim_real(real, object), sim_ours(ours, object);
    const Eigen::Vector3d centre = object.bounds().center();
    for (const std::string preshape_name : {"power", "precision"}) {
      for (int k = 0; k < 6; ++k) {
        const double a = 2 * kPi * k / 6;
        const Eigen::Vector3d approach(-std::cos(a), -std::sin(a), 0);
        Pose gcp = Pose::Identity();
        gcp.linear() = frameFromZY(approach, Eigen::Vector3d::UnitZ());
        // Back off along the approach until neither model starts in collision.
        Pose pose_real, pose_ours;
        bool free = false;
        for (double d = 0; d < 0.2 && !free; d += 0.002) {
          gcp.translation() = centre - d * approach;
          pose_real = sim_real.handPoseForGcp(gcp, real.preshape(preshape_name));
          pose_ours = sim_ours.handPoseForGcp(gcp, ours.preshape(preshape_name));
          free = !sim_real.inCollision(pose_real, real.preshape(preshape_name).joints) &&
                 !sim_ours.inCollision(pose_ours, ours.preshape(preshape_name).joints);
        }
        if (!free) continue;
        // One contact per link: the meshes' and the primitives' patches have different corners,
        // and the floors below compare the geometry of the closings.
        ClosingParams centre;
        centre.contact_patch = ContactPatch::kCentre;
        const auto r = sim_real.close(pose_real, real.preshape(preshape_name), centre);
        const auto o = sim_ours.close(pose_ours, ours.preshape(preshape_name), centre);
        ++grasps;
        for (const auto& finger : ours.fingers()) {
          for (const auto& drive : finger.drives) {
            const std::string& joint = ours.joints()[drive.joint].name;
            joint_error_sum += std::abs(r.joints[real.jointIndex(joint)] - o.joints[drive.joint]);
            ++joints_compared;
          }
        }
        same_contact_count += std::abs(static_cast<int>(r.contacts.size()) -
                                       static_cast<int>(o.contacts.size())) <= 1;
        QualityParams q;
        q.torsional_friction_m = ours.closingDefaults().torsional_friction_m;
        same_closure += evaluateGrasp(r.contacts, object, q).force_closure ==
                        evaluateGrasp(o.contacts, object, q).force_closure;
      }
    }
  }
  ASSERT_GT(grasps, 20);
  const double mean_joint_error = joint_error_sum / joints_compared;
  const double contact_agreement = static_cast<double>(same_contact_count) / grasps;
  const double closure_agreement = static_cast<double>(same_closure) / grasps;
  std::printf(
      "%s: %d grasps, mean |dq| %.3f (rad or m), contact count within 1: %.0f%%, same "
      "force-closure verdict: %.0f%%\n",
      GetParam().builtin, grasps, mean_joint_error, 100 * contact_agreement,
      100 * closure_agreement);
  RecordProperty("mean_joint_error", std::to_string(mean_joint_error));
  RecordProperty("closure_agreement", std::to_string(closure_agreement));
  // Floors measured on this data (docs/hands.md); they guard against a drift of the models.
  EXPECT_LT(mean_joint_error, 0.25);
  EXPECT_GT(closure_agreement, 0.6);
}

INSTANTIATE_TEST_SUITE_P(Hands, RealHands, ::testing::ValuesIn(kHands),
                         [](const auto& info) { return std::string(info.param.builtin); });

}  // namespace
}  // namespace skelgrasp::grasping
