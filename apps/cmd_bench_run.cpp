// skelgrasp bench run [INPUT...]: per-stage and total times of the main job, scan -> ranked grasps.
// With no input (or the word "demo") it times every object of the generated demo scene; with
// --object all, every object of each scan at once (runScene), on one thread and on --jobs.
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <limits>

#include "cli.h"
#include "option_checks.h"
#include "output_paths.h"
#include "run_command.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/datasets/input.h"
#include "skelgrasp/perception/demo_scene.h"
#include "skelgrasp/pipeline/run_scene.h"

namespace skelgrasp::cli {
namespace {

struct BenchRunArgs {
  std::vector<std::string> inputs;
  int repeat = 3;
  std::string json_out;
  RunOptions run;
};

struct Case {
  std::string name;
  perception::Scan scan;
  std::string object;  // --object value
};

std::vector<Case> loadCases(const BenchRunArgs& args) {
  std::vector<Case> cases;
  const auto inputs = args.inputs.empty() ? std::vector<std::string>{"demo"} : args.inputs;
  for (const auto& input : inputs) {
    if (input == "demo") {
      const auto scene = perception::makeDemoScene();
      perception::Scan scan;
      scan.cloud = scene.cloud;
      scan.per_view_normals = true;
      scan.views = scene.cameras.size();
      scan.source = "demo scene";
      for (std::size_t k = 1; k < scene.meshes.size(); ++k) {
        cases.push_back({"demo " + scene.names[k], scan, nearestObjectOption(scene.centres[k])});
      }
    } else {
      cases.push_back({std::filesystem::path(input).filename().string(),
                       datasets::loadInput(input, args.run.reconstruction.inputOptions()),
                       args.run.reconstruction.object});
    }
  }
  return cases;
}

// Stage times of a scene run: the shared stages, then each per-object stage summed over objects.
std::vector<pipeline::StageTime> sceneStages(const pipeline::SceneRunResult& run) {
  std::vector<pipeline::StageTime> stages = run.stages;
  std::vector<pipeline::StageTime> objects;
  for (const auto& o : run.objects) {
    for (const auto& s : o.stages) {
      auto it = std::find_if(objects.begin(), objects.end(),
                             [&](const auto& t) { return t.stage == "objects " + s.stage; });
      if (it == objects.end()) it = objects.insert(objects.end(), {"objects " + s.stage, 0.0});
      it->seconds += s.seconds;
    }
  }
  stages.insert(stages.end(), objects.begin(), objects.end());
  return stages;
}

// --object all: each scan's every object planned on one thread and on args.run's --jobs (all
// cores by default), best of --repeat each, in this process; the ratio is the parallel speed-up.
int runBenchScenes(const BenchRunArgs& args, const grasping::HandModel& hand) {
  nlohmann::json rows = nlohmann::json::array();
  const int jobs = args.run.object_jobs == 0 ? hardwareThreads() : args.run.object_jobs;
  std::cout << fmt::format("{:<28} {:>7} {:>9} {:>11} {:>11} {:>6}  per-stage (one thread, s)\n",
                           "scene (best of " + std::to_string(args.repeat) + ")", "objects",
                           "w/ grasp", "1 thread s", std::to_string(jobs) + " threads s", "ratio");
  for (const auto& input : args.inputs) {
    const auto scan = datasets::loadInput(input, args.run.reconstruction.inputOptions());
    auto params = args.run.params();
    const auto best = [&](int threads) {
      params.object_jobs = threads;
      pipeline::SceneRunResult fastest;
      fastest.total_s = std::numeric_limits<double>::infinity();
      for (int r = 0; r < args.repeat; ++r) {
        auto result = pipeline::runScene(scan, hand, params);
        if (result.total_s < fastest.total_s) fastest = std::move(result);
      }
      return fastest;
    };
    const auto one = best(1);
    const auto many = best(jobs);
    std::string stages_text;
    nlohmann::json stages = nlohmann::json::object();
    for (const auto& s : sceneStages(one)) {
      stages_text += fmt::format(" {} {:.2f}", s.stage, s.seconds);
      stages[s.stage] = s.seconds;
    }
    const double ratio = many.total_s / one.total_s;
    std::cout << fmt::format("{:<28} {:>7} {:>9} {:>11.2f} {:>11.2f} {:>6.2f} {}\n",
                             std::filesystem::path(input).filename().string(), one.objects.size(),
                             one.objectsWithGrasps(), one.total_s, many.total_s, ratio,
                             stages_text);
    rows.push_back({{"input", input},
                    {"status", toString(one.status.code)},
                    {"objects", one.objects.size()},
                    {"objects_with_grasps", one.objectsWithGrasps()},
                    {"one_thread_s", one.total_s},
                    {"threads", jobs},
                    {"threads_s", many.total_s},
                    {"ratio", ratio},
                    {"stages_s", stages}});
  }
  if (!args.json_out.empty()) {
    writeJsonFile(args.json_out, {{"rows", rows},
                                  {"hand", hand.name()},
                                  {"schema", "skelgrasp.bench_run_scenes/1"},
                                  {"repeat", args.repeat}});
  }
  return kExitOk;
}

int runBenchRun(const BenchRunArgs& args) {
  checkOutputFileOption(args.json_out);
  if (args.run.params().reconstruction.ingest.scene.target.mode == perception::TargetMode::kAll) {
    if (args.inputs.empty() || std::count(args.inputs.begin(), args.inputs.end(), "demo") > 0)
      throw InvalidArgument("bench run --object all times scans: give their paths, not 'demo'");
    return runBenchScenes(args, args.run.hand.load());
  }
  const auto hand = args.run.hand.load();
  const auto cases = loadCases(args);
  nlohmann::json rows = nlohmann::json::array();
  std::vector<std::string> stage_names;
  std::size_t width = 24;
  for (const auto& c : cases) width = std::max(width, c.name.size());
  ProgressReporter progress("bench run", cases.size(), 10.0);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    progress.step(i);
    const auto& c = cases[i];
    RunOptions options = args.run;
    options.reconstruction.object = c.object;
    const auto params = options.params();
    pipeline::RunResult best;
    best.total_s = std::numeric_limits<double>::infinity();
    for (int r = 0; r < args.repeat; ++r) {
      auto result = pipeline::runPipeline(c.scan, hand, params);
      if (result.total_s < best.total_s) best = std::move(result);
    }
    if (stage_names.empty()) {
      for (const auto& s : best.stages) stage_names.push_back(s.stage);
      std::string header =
          fmt::format("{:<{}}", "input (best of " + std::to_string(args.repeat) + ", s)", width);
      for (const auto& s : stage_names) header += fmt::format(" {:>11}", s);
      std::cout << header << fmt::format(" {:>7} {:>6}\n", "total", "grasps");
    }
    std::string line = fmt::format("{:<{}}", c.name, width);
    nlohmann::json stages = nlohmann::json::object();
    for (const auto& name : stage_names) {
      double seconds = 0;
      for (const auto& s : best.stages)
        if (s.stage == name) seconds = s.seconds;
      line += fmt::format(" {:>11.3f}", seconds);
      stages[name] = seconds;
    }
    std::cout << line << fmt::format(" {:>7.3f} {:>6}", best.total_s, best.ranked.size())
              << (best.status.ok() ? "" : "  (" + best.status.message + ")") << "\n";
    rows.push_back({{"input", c.name},
                    {"object", c.object},
                    {"status", toString(best.status.code)},
                    {"stages_s", stages},
                    {"total_s", best.total_s},
                    {"grasps", best.ranked.size()}});
  }
  progress.finish();
  if (!args.json_out.empty()) {
    writeJsonFile(args.json_out, {{"rows", rows},
                                  {"hand", hand.name()},
                                  {"threads", args.run.reconstruction.threads},
                                  {"repeat", args.repeat}});
  }
  return kExitOk;
}

}  // namespace

void registerBenchRunCommand(CLI::App& app, Action& action) {
  CLI::App* bench = app.get_subcommand("bench");  // created by registerBenchCommand
  auto* cmd = bench->add_subcommand(
      "run", "Per-stage times of the main job (scan -> ranked grasps), one core unless --threads");
  auto args = std::make_shared<BenchRunArgs>();
  cmd->add_option("INPUT", args->inputs,
                  "Scans or captures (their --object target; all: every object at once, on one "
                  "thread and on --jobs), or 'demo' for every object of the generated scene (the "
                  "default)");
  cmd->add_option("--repeat", args->repeat, "Runs per input; the fastest is reported")
      ->transform(countIn(1, kMaxRepeat))
      ->capture_default_str();
  cmd->add_option("--json", args->json_out, "Also write the rows as JSON");
  args->run.addTo(*cmd);
  cmd->callback([=, &action] { action = [=] { return runBenchRun(*args); }; });
}

}  // namespace skelgrasp::cli
