#pragma once
// The hand a grasps-file command (score, simulate, export) works with: --hand when given, else
// the built-in hand the file names.
#include <nlohmann/json.hpp>

#include <string>

#include "skelgrasp/common/error.h"
#include "skelgrasp/grasping/hand/hand_model.h"

namespace skelgrasp::cli {

// Throws IoError naming `grasps_path` when neither --hand (`hand_option`) nor the file says.
inline grasping::HandModel handOfGraspsFile(const nlohmann::json& file,
                                            const std::string& grasps_path,
                                            const std::string& hand_option,
                                            const std::string& description) {
  std::string hand_name = hand_option;
  if (hand_name.empty()) {
    if (!file.is_object() || !file.contains("hand") || !file["hand"].is_string())
      throw IoError(grasps_path, "names no hand; give --hand");
    hand_name = file["hand"].get<std::string>();
  }
  return grasping::resolveHand(hand_name, description);
}

}  // namespace skelgrasp::cli
