#pragma once
// Shared plumbing of the skelgrasp subcommands. Each command file registers its subcommand and
// returns the process exit code from its run function: 0 success, 2 bad input or failure to
// process it (one error line on stderr naming the file and the problem).
#include <CLI/CLI.hpp>

#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace skelgrasp::cli {

constexpr int kExitOk = 0;
constexpr int kExitBadInput = 2;

// The items of a comma-separated option value such as "armar3,sdh"; empty items are dropped.
inline std::vector<std::string> splitList(const std::string& text, char separator = ',') {
  std::vector<std::string> items;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, separator);) {
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

// A registered subcommand's action, run after parsing.
using Action = std::function<int()>;

void registerSkeletonCommand(CLI::App& app, Action& action);
void registerShapeCommand(CLI::App& app, Action& action);
void registerBenchCommand(CLI::App& app, Action& action);
void registerDemoCommand(CLI::App& app, Action& action);
void registerHandCommands(CLI::App& app, Action& action);
void registerPlanCommand(CLI::App& app, Action& action);
void registerBenchPlanCommand(CLI::App& bench, Action& action);
void registerEvaluateCommands(CLI::App& app, Action& action);
void registerRunCommand(CLI::App& app, Action& action);
void registerReconstructCommand(CLI::App& app, Action& action);
void registerIngestCommand(CLI::App& app, Action& action);
void registerDatasetsCommand(CLI::App& app, Action& action);
void registerExportCommand(CLI::App& app, Action& action);
void registerScoreCommand(CLI::App& app, Action& action);
void registerSimulateCommand(CLI::App& app, Action& action);
// Adds `bench reconstruct`; call after registerBenchCommand.
void registerBenchReconstructCommand(CLI::App& app, Action& action);
// Adds `bench run`; call after registerBenchCommand.
void registerBenchRunCommand(CLI::App& app, Action& action);
// Adds `bench judge`; call after registerBenchCommand.
void registerBenchJudgeCommand(CLI::App& app, Action& action);
// Adds `bench segment`; call after registerBenchCommand.
void registerBenchSegmentCommand(CLI::App& app, Action& action);
// Adds `bench ranking`; call after registerBenchCommand.
void registerBenchRankingCommand(CLI::App& app, Action& action);
// Adds `bench physics`; call after registerBenchCommand.
void registerBenchPhysicsCommand(CLI::App& app, Action& action);
// Adds `bench scan2grasp`; call after registerBenchCommand.
void registerBenchScanToGraspCommand(CLI::App& app, Action& action);

// Prints "skelgrasp: error: <message>" to stderr and returns kExitBadInput.
int fail(const std::string& message);

}  // namespace skelgrasp::cli
