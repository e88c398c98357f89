#pragma once
// `--export FORMAT[,FORMAT]` on plan and run: the grasps also in formats robot stacks load,
// written next to grasps.json (grasps.moveit.yaml, grasps.joint_states.json; docs/export.md).
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/grasping/io/grasp_export.h"

namespace skelgrasp::cli {

struct ExportOptions {
  std::vector<std::string> formats;

  void addTo(CLI::App& cmd);
  // Reads the grasps.json just written and writes each requested export beside it, named after
  // it (x.json -> x.moveit.yaml). Throws IoError / InvalidArgument.
  void write(const std::string& grasps_json_path, const grasping::HandModel& hand) const;
};

}  // namespace skelgrasp::cli
