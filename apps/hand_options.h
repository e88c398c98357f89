#pragma once
// Command-line options selecting a hand, shared by the commands that use one.
#include <CLI/CLI.hpp>

#include "skelgrasp/grasping/hand/hand_model.h"

namespace skelgrasp::cli {

struct HandOptions {
  std::string hand = "armar3";
  std::string description;

  void addTo(CLI::App& cmd) {
    cmd.add_option("--hand", hand,
                   "Built-in hand (armar3, sdh, shadow, parallel_gripper) or a .urdf file")
        ->capture_default_str();
    cmd.add_option("--grasp-description", description,
                   "Grasp description JSON for a .urdf hand (docs/hands.md)");
  }
  grasping::HandModel load() const { return grasping::resolveHand(hand, description); }
};

}  // namespace skelgrasp::cli
