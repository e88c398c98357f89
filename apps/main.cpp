// skelgrasp's command programs: skeleton-based grasp planning from raw 3D scans. Built twice:
// skelgrasp-full with every command, and with SKELGRASP_MESH_COMMANDS_ONLY skelgrasp-mesh with the
// commands of command_programs.h, which link no perception stack. The `skelgrasp` launcher
// (launcher.cpp) starts the right one.
#include <algorithm>
#include <cstdlib>
#include <iostream>

#include "cli.h"
#include "command_programs.h"
#include "help_format.h"
#include "option_checks.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/resources.h"
#include "skelgrasp/common/signal_cleanup.h"

namespace skelgrasp::cli {

int fail(const std::string& message) {
  std::cerr << "skelgrasp: error: " << message << std::endl;
  return kExitBadInput;
}

// The launcher routes kMeshCommands to skelgrasp-mesh: every one of them must exist in both
// programs, and skelgrasp-mesh must have no other (it would be unreachable). A bug otherwise.
void checkMeshCommandList(CLI::App& app) {
  std::vector<std::string> registered;
  for (const auto* sub : app.get_subcommands([](CLI::App*) { return true; })) {
    registered.push_back(sub->get_name());
  }
  for (const auto& command : kMeshCommands) {
    if (std::find(registered.begin(), registered.end(), command) == registered.end()) {
      throw std::logic_error("command '" + std::string(command) + "' of kMeshCommands is missing");
    }
  }
#ifdef SKELGRASP_MESH_COMMANDS_ONLY
  for (const auto& name : registered) {
    if (!isMeshCommand(name)) {
      throw std::logic_error("command '" + name + "' is not in kMeshCommands");
    }
  }
#endif
}

}  // namespace skelgrasp::cli

int main(int argc, char** argv) {
  using namespace skelgrasp;
  CLI::App app{"skelgrasp: skeleton-based grasp planning for multi-fingered hands"};
  // The build renders the top-level help with placeholders for the launcher to fill in.
  const bool help_template = std::getenv(cli::kHelpTemplateVariable) != nullptr;
  cli::setUpHelp(app);  // before the commands, which inherit --help-all and the layout
  app.require_subcommand(1);
  app.fallthrough();  // global flags (-q, -v) may follow the subcommand
  bool quiet = false, verbose = false;
  app.add_flag("-q,--quiet", quiet, "Only warnings and errors on stderr");
  app.add_flag("-v,--verbose", verbose, "Debug logging on stderr");
  std::string memory_limit;
  app.add_option("--memory-limit", memory_limit,
                 "Refuse work estimated to need more memory: 4G, 512M or a fraction of RAM "
                 "(default " +
                     (help_template ? std::string(cli::kMemoryDefaultPlaceholder)
                                    : formatBytes(static_cast<double>(defaultMemoryLimitBytes()))) +
                     ", half of this machine's; docs/limits.md)");

  cli::Action action;
  // The mesh commands are in both programs, the rest only in skelgrasp-full; this order is the
  // top-level help's.
  cli::registerSkeletonCommand(app, action);
  cli::registerShapeCommand(app, action);
#ifndef SKELGRASP_MESH_COMMANDS_ONLY
  cli::registerBenchCommand(app, action);
  cli::registerDemoCommand(app, action);
#endif
  cli::registerHandCommands(app, action);
  cli::registerPlanCommand(app, action);
  cli::registerEvaluateCommands(app, action);
#ifndef SKELGRASP_MESH_COMMANDS_ONLY
  cli::registerRunCommand(app, action);
  cli::registerReconstructCommand(app, action);
  cli::registerIngestCommand(app, action);
  cli::registerDatasetsCommand(app, action);
#endif
  cli::registerExportCommand(app, action);
  cli::registerScoreCommand(app, action);
  cli::registerSimulateCommand(app, action);
#ifndef SKELGRASP_MESH_COMMANDS_ONLY
  cli::registerBenchReconstructCommand(app, action);
  cli::registerBenchRunCommand(app, action);
  cli::registerBenchJudgeCommand(app, action);
  cli::registerBenchSegmentCommand(app, action);
  cli::registerBenchRankingCommand(app, action);
  cli::registerBenchPhysicsCommand(app, action);
  cli::registerBenchScanToGraspCommand(app, action);
#endif

  try {
    cli::checkDefaults(app);
    cli::checkMeshCommandList(app);
  } catch (const std::logic_error& e) {
    return cli::fail(std::string("internal error: ") + e.what());  // a bug, seen by every run
  }

  try {
    app.parse(argc, argv);
    cli::checkParsedNumbers(app);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help: usage on stdout, exit 0
  } catch (const CLI::ParseError& e) {
    // CLI11 says only "A subcommand is required" for a mistyped command: name the word.
    if (app.get_subcommands().empty()) {
      for (int i = 1; i < argc; ++i) {
        if (argv[i][0] != '-') {
          return cli::fail(std::string("unknown command '") + argv[i] + "' (see skelgrasp --help)");
        }
      }
    }
    // House format instead of CLI11's two lines: the message names the option and its range.
    return cli::fail(cli::oneLine(e.what()));
  }
  setLogLevel(verbose ? spdlog::level::debug : quiet ? spdlog::level::warn : spdlog::level::info);
  // Ctrl-C or `kill` removes the hidden temporaries and the empty output directories of the
  // command (signal_cleanup.h) before ending it.
  installSignalCleanup();
  try {
    if (!memory_limit.empty()) setMemoryLimitBytes(parseMemoryLimit(memory_limit));
    return action ? action() : cli::kExitOk;
  } catch (const IoError& e) {
    return cli::fail(e.what());
  } catch (const InvalidArgument& e) {
    return cli::fail(e.what());
  } catch (const std::exception& e) {
    return cli::fail(e.what());
  }
}
