// skelgrasp export GRASPS.json --format moveit|joint_states: grasps for a robot stack
// (docs/export.md), and the `--export` option plan and run share.
#include "export_options.h"

#include <filesystem>
#include <iostream>

#include "cli.h"
#include "grasps_hand.h"
#include "output_paths.h"
#include "skelgrasp/common/atomic_file.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"

namespace skelgrasp::cli {
namespace {

struct ExportArgs {
  std::string grasps;
  std::string format;
  std::string out;
  std::string hand;  // empty: the built-in hand the file names
  std::string description;
  std::string frame_id;
};

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const auto& n : names) text += (text.empty() ? "" : ", ") + n;
  return text;
}

int runExport(const ExportArgs& args) {
  const auto format = grasping::parseExportFormat(args.format);
  const std::string out = args.out.empty() ? (std::filesystem::path(args.grasps).parent_path() /
                                              grasping::defaultExportFileName(format))
                                                 .string()
                                           : args.out;
  checkOutputFileOption(out);
  checkOutputIsNotInput(out, {args.grasps, args.description});
  const nlohmann::json grasps = readJsonFile(args.grasps);
  const auto hand = handOfGraspsFile(grasps, args.grasps, args.hand, args.description);
  grasping::ExportParams params;
  if (!args.frame_id.empty()) params.frame_id = args.frame_id;
  std::string text;
  try {
    text = grasping::exportGrasps(grasps, hand, format, params);
  } catch (const InvalidArgument& e) {
    throw IoError(args.grasps, e.what());
  }
  writeFileAtomically(out, text);
  std::cout << "exported " << grasps["grasps"].size() << " grasp(s) as " << args.format << " -> "
            << out << std::endl;
  return kExitOk;
}

}  // namespace

void ExportOptions::addTo(CLI::App& cmd) {
  cmd.add_option("--export", formats,
                 "Also write the grasps for a robot stack: " +
                     joined(grasping::exportFormatNames()) + " (docs/export.md)")
      ->delimiter(',')
      ->check(CLI::IsMember(grasping::exportFormatNames()));
}

void ExportOptions::stage(OutputTransaction& outputs, const std::string& grasps_json_path,
                          const nlohmann::json& grasps, const grasping::HandModel& hand) const {
  const auto stem = std::filesystem::path(grasps_json_path).replace_extension("").string();
  for (const auto& name : formats) {
    const auto format = grasping::parseExportFormat(name);
    const std::string suffix =
        grasping::defaultExportFileName(format).substr(std::string("grasps").size());
    writeFileAtomically(outputs.stage(stem + suffix), grasping::exportGrasps(grasps, hand, format));
  }
}

void registerExportCommand(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand(
      "export", "Write planned grasps in a format a robot stack loads (MoveIt, joint states)");
  auto args = std::make_shared<ExportArgs>();
  cmd->add_option("GRASPS", args->grasps, "grasps.json written by plan or run")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--format", args->format, joined(grasping::exportFormatNames()))
      ->required()
      ->check(CLI::IsMember(grasping::exportFormatNames()));
  cmd->add_option("--out", args->out,
                  "Output file (default: grasps.moveit.yaml or grasps.joint_states.json next to "
                  "GRASPS)");
  cmd->add_option("--hand", args->hand,
                  "The hand the grasps were planned with: built-in name or .urdf (default: the "
                  "built-in hand GRASPS names)");
  cmd->add_option("--grasp-description", args->description,
                  "Grasp description JSON for a .urdf hand (docs/hands.md)");
  cmd->add_option("--frame-id", args->frame_id,
                  "Frame of grasp_pose (default: the file's frame, \"scan\" for run, else the "
                  "object's name)");
  cmd->callback([args, &action] { action = [args] { return runExport(*args); }; });
}

}  // namespace skelgrasp::cli
