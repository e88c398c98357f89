// skelgrasp bench reconstruct INPUT...: per-stage times of scan -> closed object mesh.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli.h"
#include "option_checks.h"
#include "output_paths.h"
#include "reconstruct_options.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/logging.h"

namespace skelgrasp::cli {
namespace {

struct BenchReconstructArgs {
  std::vector<std::string> inputs;
  int repeat = 3;
  std::string json_out;
  ReconstructOptions options;
};

struct StageTimes {
  double load = 0, filters = 0, scene = 0, normals = 0, completion = 0, poisson = 0, trim = 0,
         regularise = 0, observed = 0, total = 0;
};

int runBenchReconstruct(const BenchReconstructArgs& args) {
  checkOutputFileOption(args.json_out);
  const auto params = args.options.params();
  std::cout << fmt::format(
      "{:<44} {:>7} {:>6} {:>6} {:>6} {:>6} {:>6} {:>6} {:>6} {:>6} {:>6} {:>6}\n",
      "input (best of " + std::to_string(args.repeat) + ", s)", "points", "load", "filter", "scene",
      "normal", "compl", "poisson", "trim", "wrap", "obs", "total");
  nlohmann::json rows = nlohmann::json::array();
  ProgressReporter progress("bench reconstruct", args.inputs.size(), 10.0);
  for (const auto& input : args.inputs) {
    progress.step(static_cast<std::size_t>(rows.size()));
    StageTimes best;
    best.total = std::numeric_limits<double>::infinity();
    std::size_t points = 0;
    std::string failure;
    for (int r = 0; r < args.repeat; ++r) {
      Stopwatch watch;
      const auto scan = datasets::loadInput(input, args.options.inputOptions());
      StageTimes t;
      t.load = watch.seconds();
      const auto result = pipeline::reconstructScan(scan, params);
      if (!result.status.ok()) {
        failure = result.status.message;
        break;
      }
      points = scan.cloud.size();
      t.filters = result.ingest.filter_time_s;
      t.scene = result.ingest.scene_time_s;
      t.normals = result.ingest.normals_time_s;
      for (const auto& o : result.objects) {
        const auto& m = o.meshing.report;
        t.completion += m.completion_s;
        t.poisson += m.poisson_s;
        t.trim += m.trim_s;
        t.regularise += m.regularise_s;
        t.observed += m.observed_s;
      }
      t.total = watch.seconds();
      if (t.total < best.total) best = t;
    }
    const std::string name = std::filesystem::path(input).filename().string();
    if (!failure.empty()) {
      std::cout << fmt::format("{:<44} failed: {}\n", name, failure);
      rows.push_back({{"input", input}, {"status", "failed"}, {"message", failure}});
      continue;
    }
    std::cout << fmt::format(
        "{:<44} {:>7} {:>6.3f} {:>6.3f} {:>6.3f} {:>6.3f} {:>6.3f} {:>6.3f} {:>6.3f} {:>6.3f} "
        "{:>6.3f} {:>6.3f}\n",
        name, points, best.load, best.filters, best.scene, best.normals, best.completion,
        best.poisson, best.trim, best.regularise, best.observed, best.total);
    rows.push_back({{"input", input},
                    {"status", "ok"},
                    {"points", points},
                    {"load_s", best.load},
                    {"filters_s", best.filters},
                    {"scene_s", best.scene},
                    {"normals_s", best.normals},
                    {"completion_s", best.completion},
                    {"poisson_s", best.poisson},
                    {"trim_s", best.trim},
                    {"regularise_s", best.regularise},
                    {"observed_s", best.observed},
                    {"total_s", best.total}});
  }
  progress.finish();
  if (!args.json_out.empty()) {
    writeJsonFile(args.json_out, {{"rows", rows}, {"threads", args.options.threads}});
  }
  return kExitOk;
}

}  // namespace

void registerBenchReconstructCommand(CLI::App& app, Action& action) {
  CLI::App* bench = app.get_subcommand("bench");  // created by registerBenchCommand
  auto* cmd = bench->add_subcommand(
      "reconstruct", "Per-stage times of scan -> closed mesh (one core unless --threads)");
  auto args = std::make_shared<BenchReconstructArgs>();
  args->options.threads = 1;
  cmd->add_option("INPUT", args->inputs, "Clouds, capture descriptions or YCB raw folders")
      ->required();
  cmd->add_option("--repeat", args->repeat, "Runs per input; the fastest is reported")
      ->transform(countIn(1, kMaxRepeat))
      ->capture_default_str();
  cmd->add_option("--json", args->json_out, "Also write the rows as JSON");
  args->options.addInputOptions(*cmd);
  args->options.addIngestOptions(*cmd);
  args->options.addMeshingOptions(*cmd);
  cmd->callback([=, &action] { action = [=] { return runBenchReconstruct(*args); }; });
}

}  // namespace skelgrasp::cli
