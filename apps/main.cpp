// skelgrasp: skeleton-based grasp planning from raw 3D scans.
#include <iostream>

#include "cli.h"
#include "option_checks.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/resources.h"

namespace skelgrasp::cli {

int fail(const std::string& message) {
  std::cerr << "skelgrasp: error: " << message << std::endl;
  return kExitBadInput;
}

}  // namespace skelgrasp::cli

int main(int argc, char** argv) {
  using namespace skelgrasp;
  CLI::App app{"skelgrasp: skeleton-based grasp planning for multi-fingered hands"};
  app.require_subcommand(1);
  app.fallthrough();  // global flags (-q, -v) may follow the subcommand
  bool quiet = false, verbose = false;
  app.add_flag("-q,--quiet", quiet, "Only warnings and errors on stderr");
  app.add_flag("-v,--verbose", verbose, "Debug logging on stderr");
  std::string memory_limit;
  app.add_option("--memory-limit", memory_limit,
                 "Refuse work estimated to need more memory: 4G, 512M or a fraction of RAM "
                 "(default " +
                     formatBytes(static_cast<double>(defaultMemoryLimitBytes())) +
                     ", half of this machine's; docs/limits.md)");

  cli::Action action;
  cli::registerSkeletonCommand(app, action);
  cli::registerShapeCommand(app, action);
  cli::registerBenchCommand(app, action);
  cli::registerDemoCommand(app, action);
  cli::registerHandCommands(app, action);
  cli::registerPlanCommand(app, action);
  cli::registerEvaluateCommands(app, action);
  cli::registerRunCommand(app, action);
  cli::registerReconstructCommand(app, action);
  cli::registerIngestCommand(app, action);
  cli::registerDatasetsCommand(app, action);
  cli::registerExportCommand(app, action);
  cli::registerBenchReconstructCommand(app, action);
  cli::registerBenchRunCommand(app, action);
  cli::registerBenchJudgeCommand(app, action);
  cli::registerBenchSegmentCommand(app, action);

  try {
    cli::checkDefaults(app);
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
