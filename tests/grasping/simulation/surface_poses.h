#pragma once
// Hand poses sampled on an object's surface, as the surface planner makes them: shared by the
// tests that compare two ways of closing or judging the same real closings.
#include <cmath>
#include <optional>
#include <random>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/pose.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"

namespace skelgrasp::test {

// The preshape's approach against the normal of a random face (at its centroid) with a random
// roll, backed off in 4 mm steps up to 15 cm until the open hand is free of the object. Draws the
// face and the roll from `rng` (in that order, whatever comes of them); nullopt for a degenerate
// face or when no free pose was found.
inline std::optional<Pose> freeSurfaceHandPose(grasping::GraspSimulator& sim,
                                               const grasping::GraspObject& object,
                                               const grasping::Preshape& preshape,
                                               std::mt19937_64& rng) {
  constexpr double kRetreatStepM = 0.004, kMaxRetreatM = 0.15;
  const auto& mesh = object.mesh();
  const std::size_t face = std::uniform_int_distribution<std::size_t>(0, mesh.numFaces() - 1)(rng);
  const Eigen::Vector3d normal = object.faceNormal(face);
  const double roll = 2 * kPi * std::uniform_real_distribution<double>(0, 1)(rng);
  if (normal.isZero()) return std::nullopt;
  const auto& t = mesh.faces[face];
  const Eigen::Vector3d point =
      (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3;
  const Eigen::Vector3d u = anyPerpendicular(normal), w = normal.cross(u);
  Pose gcp = Pose::Identity();
  gcp.linear() = frameFromZY(-normal, std::cos(roll) * u + std::sin(roll) * w);
  for (double retreat = 0; retreat < kMaxRetreatM; retreat += kRetreatStepM) {
    gcp.translation() = point + retreat * normal;
    const Pose hand_pose = sim.handPoseForGcp(gcp, preshape);
    if (!sim.inCollision(hand_pose, preshape.joints)) return hand_pose;
  }
  return std::nullopt;
}

}  // namespace skelgrasp::test
