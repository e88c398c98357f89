#pragma once
// Shared fixtures of the grasping and evaluation benchmarks.
#include <filesystem>
#include <string>

#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"

namespace skelgrasp::bench {

// The YCB google_16k mustard bottle, or a generated bottle without ../shared/data.
inline const grasping::GraspObject& benchObject() {
  static const grasping::GraspObject object = [] {
    const std::string path =
        std::string(SKELGRASP_SHARED_DATA_DIR) + "/objects/ycb/006_mustard_bottle.ply";
    return grasping::GraspObject(std::filesystem::exists(path)
                                     ? loadMesh(path)
                                     : geometry::shapes::makeNamedShape("bottle"));
  }();
  return object;
}

// A hand pose for a grasp from the side (-x) at mid-height, backed off until the open hand is
// clear of benchObject().
inline Pose sideGraspPose(grasping::GraspSimulator& sim, const grasping::Preshape& preshape) {
  const auto& box = benchObject().bounds();
  Pose gcp = Pose::Identity();
  gcp.linear() = frameFromZY({-1, 0, 0}, {0, 0, 1});
  for (double d = 0; d < 0.2; d += 0.001) {
    gcp.translation() = box.center() + Eigen::Vector3d(d, 0, 0);
    const Pose hand = sim.handPoseForGcp(gcp, preshape);
    if (!sim.inCollision(hand, preshape.joints)) return hand;
  }
  return sim.handPoseForGcp(gcp, preshape);
}

}  // namespace skelgrasp::bench
