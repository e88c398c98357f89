#pragma once
// `--export FORMAT[,FORMAT]` on plan and run: the grasps also in formats robot stacks load,
// written next to grasps.json (grasps.moveit.yaml, grasps.joint_states.json; docs/export.md).
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "skelgrasp/common/atomic_file.h"

#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/grasping/io/grasp_export.h"

namespace skelgrasp::cli {

struct ExportOptions {
  std::vector<std::string> formats;

  void addTo(CLI::App& cmd);
  // Stages each requested export of `grasps` (the document written to `grasps_json_path`) in
  // `outputs`, beside that file and named after it (x.json -> x.moveit.yaml): the exports appear
  // with grasps.json or not at all. Throws IoError / InvalidArgument.
  void stage(OutputTransaction& outputs, const std::string& grasps_json_path,
             const nlohmann::json& grasps, const grasping::HandModel& hand) const;
};

}  // namespace skelgrasp::cli
