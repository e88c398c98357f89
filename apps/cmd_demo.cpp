// skelgrasp demo: the embedded default. A table scene made in code, scanned by the simulated depth
// camera from three viewpoints (written as a real PCD), then `run --object all` on it: every object
// in one process, one report, and an index naming the objects the scene was made of.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <limits>

#include "cli.h"
#include "option_checks.h"
#include "output_paths.h"
#include "run_command.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/datasets/input.h"
#include "skelgrasp/perception/cloud_io.h"
#include "skelgrasp/perception/demo_scene.h"
#include "skelgrasp/presentation/html_report.h"

namespace skelgrasp::cli {
namespace {

struct DemoArgs {
  std::string out = "demo_output";
  std::uint64_t seed = 1;
  int views = 3;
  RunOptions run;
};

// The object of the run nearest to each object the scene was made of (centroid to bounding-box
// centre), so the index can name what the segmentation found; -1 when the run found no object.
int nearestRunObject(const nlohmann::json& objects, const Eigen::Vector3d& centre) {
  int best = -1;
  double best_distance = std::numeric_limits<double>::infinity();
  for (const auto& o : objects) {
    const Eigen::Vector3d c(o["centroid"][0].get<double>(), o["centroid"][1].get<double>(),
                            o["centroid"][2].get<double>());
    if ((c - centre).norm() < best_distance) {
      best_distance = (c - centre).norm();
      best = o["id"].get<int>();
    }
  }
  return best;
}

// index.html: the scene's objects by name with the run object each became, its grasp count and a
// link to its section of report.html. Read back from the run's grasps.json, the file users get.
void writeDemoIndex(const std::string& out, const perception::DemoScene& scene,
                    const std::string& hand, int views) {
  const auto run = readJsonFile(out + "/grasps.json");
  const auto& objects = run["objects"];
  presentation::HtmlReport index("skelgrasp demo");
  index.paragraph(fmt::format(
      "A table scene made in code, scanned from {} viewpoints by a simulated Primesense-like "
      "camera (scene.pcd), and `skelgrasp run --object all` with hand {}: {} objects found, "
      "every one planned against the table and the others in one run.",
      views, hand, objects.size()));
  std::string rows =
      "<table>\n<tr><th>object made</th><th>run object</th><th>points</th>"
      "<th>grasps</th><th>status</th></tr>\n";
  for (std::size_t k = 1; k < scene.meshes.size(); ++k) {
    const int id = nearestRunObject(objects, scene.centres[k]);
    if (id < 0) {
      rows += "<tr><td>" + presentation::escapeHtml(scene.names[k]) +
              "</td><td>-</td><td></td><td></td><td>not found</td></tr>\n";
      continue;
    }
    const auto& o = objects[static_cast<std::size_t>(id)];
    rows += fmt::format(
        "<tr><td>{}</td><td><a href=\"report.html#object-{}\">object {}</a></td><td>{}</td>"
        "<td>{}</td><td>{}</td></tr>\n",
        presentation::escapeHtml(scene.names[k]), id, id, o["points"].get<std::size_t>(),
        o["grasps"].get<std::size_t>(),
        o["reason"].is_null() ? "ok" : presentation::escapeHtml(o["reason"].get<std::string>()));
  }
  index.rawHtml(rows + "</table>\n");
  index.rawHtml(
      "<p><a href=\"report.html\">The run's report</a>: the scene in 3D, every object "
      "and its grasps.</p>\n");
  index.write(out + "/index.html");
}

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
  RunOptions options = args.run;
  options.reconstruction.object = "all";  // `run --object all`: one process, one occupancy map
  const int code = runOnScan(scan, "scene.pcd", args.out, options);
  if (code != kExitOk) return code;
  writeDemoIndex(args.out, scene, args.run.hand.hand, args.views);
  std::cout << "demo report: " << fs::absolute(args.out).string()
            << "/report.html (index: " << fs::absolute(args.out).string() << "/index.html)"
            << std::endl;
  return kExitOk;
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
