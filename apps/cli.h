#pragma once
// Shared plumbing of the skelgrasp subcommands. Each command file registers its subcommand and
// returns the process exit code from its run function: 0 success, 2 bad input or failure to
// process it (one error line on stderr naming the file and the problem).
#include <CLI/CLI.hpp>

#include <functional>
#include <string>

namespace skelgrasp::cli {

constexpr int kExitOk = 0;
constexpr int kExitBadInput = 2;

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
// Adds `bench reconstruct`; call after registerBenchCommand.
void registerBenchReconstructCommand(CLI::App& app, Action& action);
// Adds `bench run`; call after registerBenchCommand.
void registerBenchRunCommand(CLI::App& app, Action& action);
// Adds `bench judge`; call after registerBenchCommand.
void registerBenchJudgeCommand(CLI::App& app, Action& action);
// Adds `bench segment`; call after registerBenchCommand.
void registerBenchSegmentCommand(CLI::App& app, Action& action);

// Prints "skelgrasp: error: <message>" to stderr and returns kExitBadInput.
int fail(const std::string& message);

}  // namespace skelgrasp::cli
