#pragma once
// Files the hostile-input tests of the command line share: plain text and a grasps file of the
// SDH hand that export, score and simulate accept.
#include <nlohmann/json.hpp>

#include <fstream>
#include <string>

#include "skelgrasp/grasping/hand/hand_model.h"

namespace skelgrasp::test {

inline void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// A grasps file of the SDH hand with one grasp: every movable joint at the middle of its limits.
inline nlohmann::json validGrasps() {
  const auto hand = grasping::loadBuiltinHand("sdh");
  nlohmann::json joints = nlohmann::json::object();
  for (const auto& joint : hand.joints())
    if (joint.movable()) joints[joint.name] = 0.5 * (joint.lower + joint.upper);
  nlohmann::json grasp = {
      {"id", 0},
      {"hand_pose", {{"position", {0, 0, 0.2}}, {"quaternion_wxyz", {1, 0, 0, 0}}}},
      {"preshape", hand.preshapes().begin()->first},
      {"retreat_m", 0.01},
      {"epsilon", 0.1},
      {"joints", joints}};
  return {{"schema", "skelgrasp.grasps/3"},
          {"hand", "sdh"},
          {"object", "capsule.ply"},
          {"grasps", {grasp}}};
}

}  // namespace skelgrasp::test
