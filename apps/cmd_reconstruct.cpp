// skelgrasp reconstruct INPUT --out mesh.ply: scan -> closed object mesh(es) with observed flags.
// skelgrasp ingest INPUT --out cloud.pcd: scan -> filtered object cloud(s) with normals.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli.h"
#include "output_paths.h"
#include "reconstruct_options.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/perception/cloud_io.h"
#include "skelgrasp/pipeline/reconstruction_report.h"

namespace skelgrasp::cli {
namespace {

struct ReconstructArgs {
  std::string input;
  std::string out;
  std::string report;
  ReconstructOptions options;
};

// "mesh.ply" for one object; "mesh_0.ply", "mesh_1.ply", ... for several.
std::string numbered(const std::string& path, std::size_t index, std::size_t count) {
  if (count <= 1) return path;
  const std::filesystem::path p(path);
  return (p.parent_path() /
          (p.stem().string() + "_" + std::to_string(index) + p.extension().string()))
      .string();
}

std::string sizeText(const AxisAlignedBox& box) {
  const Eigen::Vector3d e = box.extent();
  return fmt::format("{:.3f} x {:.3f} x {:.3f} m", e.x(), e.y(), e.z());
}

int runReconstruct(const ReconstructArgs& args) {
  if (fileExtension(args.out) != "ply") return fail(args.out + ": --out must be a .ply file");
  checkOutputFileOption(args.out);
  checkOutputFileOption(args.report);
  const auto params = args.options.params();
  datasets::InputKind kind;
  const perception::Scan scan = datasets::loadInput(args.input, args.options.inputOptions(), &kind);
  const auto result = pipeline::reconstructScan(scan, params);
  std::vector<std::string> files;
  OutputTransaction outputs;  // meshes and report appear together, the report last
  for (std::size_t k = 0; k < result.objects.size(); ++k) {
    const auto& o = result.objects[k];
    if (!o.meshing.status.ok()) {
      files.emplace_back();
      continue;
    }
    files.push_back(numbered(args.out, k, result.objects.size()));
    reconstruction::saveObservedMesh(outputs.stage(files.back()), o.meshing.mesh,
                                     o.meshing.observed);
  }
  if (!args.report.empty()) {
    writeJsonFile(outputs.stage(args.report),
                  pipeline::reconstructionReport(scan, params, result, files));
  }
  outputs.commit();
  if (!result.status.ok()) return fail(args.input + ": " + result.status.message);
  for (std::size_t k = 0; k < result.objects.size(); ++k) {
    const auto& r = result.objects[k].meshing.report;
    std::cout << fmt::format("{}: object {} -> {} ({} vertices, {}, {:.0f}% observed), {:.2f} s",
                             args.input, result.objects[k].cluster, files[k], r.vertices,
                             sizeText(result.objects[k].meshing.mesh.bounds()),
                             100 * r.observed_fraction, result.total_s)
              << std::endl;
  }
  return kExitOk;
}

int runIngest(const ReconstructArgs& args) {
  if (fileExtension(args.out) != "pcd") return fail(args.out + ": --out must be a .pcd file");
  checkOutputFileOption(args.out);
  checkOutputFileOption(args.report);
  const auto params = args.options.params();
  const perception::Scan scan = datasets::loadInput(args.input, args.options.inputOptions());
  pipeline::ReconstructionResult result;
  result.ingest = perception::ingestScan(scan, params.ingest);
  result.status = result.ingest.status;
  result.total_s = result.ingest.total_time_s;
  std::vector<std::string> files;
  OutputTransaction outputs;  // clouds and report appear together, the report last
  for (std::size_t k = 0; k < result.ingest.objects.size(); ++k) {
    files.push_back(numbered(args.out, k, result.ingest.objects.size()));
    perception::savePointCloud(outputs.stage(files.back()), result.ingest.objects[k]);
  }
  if (!args.report.empty()) {
    writeJsonFile(outputs.stage(args.report), pipeline::reconstructionReport(scan, params, result));
  }
  outputs.commit();
  if (!result.status.ok()) return fail(args.input + ": " + result.status.message);
  for (std::size_t k = 0; k < files.size(); ++k) {
    const auto& cloud = result.ingest.objects[k];
    std::cout << fmt::format("{}: object {} -> {} ({} points, {}), {:.2f} s", args.input,
                             result.ingest.scene.selected[k], files[k], cloud.size(),
                             sizeText(cloud.bounds()), result.total_s)
              << std::endl;
  }
  return kExitOk;
}

}  // namespace

void registerReconstructCommand(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand(
      "reconstruct", "Scan (PCD/PLY, capture .json, YCB raw folder) -> closed object mesh(es)");
  auto args = std::make_shared<ReconstructArgs>();
  cmd->add_option("INPUT", args->input, "Cloud, capture description or YCB raw capture folder")
      ->required();
  cmd->add_option("--out", args->out, "Output mesh (.ply, with a uchar 'observed' per vertex)")
      ->required();
  cmd->add_option("--report", args->report, "Also write the JSON report here");
  args->options.addInputOptions(*cmd);
  args->options.addIngestOptions(*cmd);
  args->options.addMeshingOptions(*cmd);
  cmd->callback([=, &action] { action = [=] { return runReconstruct(*args); }; });
}

void registerIngestCommand(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("ingest",
                                 "Scan -> filtered, segmented object cloud(s) with normals (.pcd)");
  auto args = std::make_shared<ReconstructArgs>();
  cmd->add_option("INPUT", args->input, "Cloud, capture description or YCB raw capture folder")
      ->required();
  cmd->add_option("--out", args->out, "Output cloud (.pcd)")->required();
  cmd->add_option("--report", args->report, "Also write the JSON report here");
  args->options.addInputOptions(*cmd);
  args->options.addIngestOptions(*cmd);
  cmd->callback([=, &action] { action = [=] { return runIngest(*args); }; });
}

}  // namespace skelgrasp::cli
