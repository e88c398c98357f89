// skelgrasp demo: the embedded default. A table scene made in code, scanned by the simulated depth
// camera from three viewpoints (written as a real PCD), then `run` for every object on it.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli.h"
#include "output_paths.h"
#include "option_checks.h"
#include "run_command.h"
#include "skelgrasp/common/html_report.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/datasets/input.h"
#include "skelgrasp/perception/cloud_io.h"
#include "skelgrasp/perception/demo_scene.h"

namespace skelgrasp::cli {
namespace {

struct DemoArgs {
  std::string out = "demo_output";
  std::uint64_t seed = 1;
  int views = 3;
  RunOptions run;
};

int runDemo(const DemoArgs& args) {
  namespace fs = std::filesystem;
  checkOutputDirectoryOption(args.out);
  fs::create_directories(args.out);
  const auto scene = perception::makeDemoScene(args.seed, args.views);
  const std::string scan_path = args.out + "/scene.pcd";
  perception::savePointCloud(scan_path, scene.cloud);
  for (std::size_t k = 0; k < scene.meshes.size(); ++k) {
    saveMesh(args.out + "/truth_" + scene.names[k] + ".ply", scene.meshes[k]);
  }
  std::cout << fmt::format("demo scene: {} objects, {} points from {} simulated views -> {}",
                           scene.meshes.size() - 1, scene.cloud.size(), args.views, scan_path)
            << std::endl;
  // The pipeline reads the scan back from the PCD, as it would a recorded one.
  const auto scan = datasets::loadInput(scan_path, args.run.reconstruction.inputOptions());
  HtmlReport index("skelgrasp demo");
  index.paragraph(fmt::format(
      "A table scene made in code, scanned from {} viewpoints by a simulated Primesense-like "
      "camera (scene.pcd), and `skelgrasp run` with hand {} for each object.",
      args.views, args.run.hand.hand));
  std::vector<std::vector<std::string>> rows;
  int failures = 0;
  for (std::size_t k = 1; k < scene.meshes.size(); ++k) {
    RunOptions options = args.run;
    options.reconstruction.object = nearestObjectOption(scene.centres[k]);
    const std::string dir = args.out + "/" + scene.names[k];
    std::cout << "== " << scene.names[k] << std::endl;
    const int code = runOnScan(scan, scene.names[k], dir, options);
    if (code != kExitOk) ++failures;
    rows.push_back(
        {scene.names[k], code == kExitOk ? "done" : "failed", scene.names[k] + "/report.html"});
  }
  index.table({"object", "run", "report"}, rows);
  index.write(args.out + "/index.html");
  std::cout << "demo reports: " << fs::absolute(args.out).string()
            << "/<object>/report.html (index: " << fs::absolute(args.out).string() << "/index.html)"
            << std::endl;
  return failures == 0 ? kExitOk : kExitBadInput;
}

}  // namespace

void registerDemoCommand(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand(
      "demo", "Scan a table scene made in code and run the pipeline on every object");
  auto args = std::make_shared<DemoArgs>();
  cmd->add_option("--out", args->out, "Output directory")->capture_default_str();
  cmd->add_option("--scene-seed", args->seed, "Seed of the simulated sensor noise")
      ->transform(countIn(0, UINT64_MAX))
      ->capture_default_str();
  cmd->add_option("--views", args->views, "Simulated camera views")
      ->transform(countIn(1, 8))
      ->capture_default_str();
  args->run.addTo(*cmd);
  cmd->callback([args, &action] { action = [args] { return runDemo(*args); }; });
}

}  // namespace skelgrasp::cli
