// skelgrasp skeleton MESH --out DIR: the skeleton stage on one mesh.
// skelgrasp shape NAME --out FILE: writes one of the built-in generated shapes.
#include <filesystem>
#include <iostream>

#include "cli.h"
#include "output_paths.h"
#include "skeleton_options.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/presentation/skeleton_render.h"
#include "skelgrasp/skeleton/output.h"

namespace skelgrasp::cli {

int runSkeletonOnFile(const std::string& mesh_path, const std::string& out_dir,
                      const SkeletonOptions& options) {
  checkOutputDirectoryOption(out_dir);
  checkOutputFileOption(options.render_path);
  MeshLoadInfo info;
  const TriangleMesh input = loadMesh(mesh_path, options.loadOptions(), &info);
  const auto result = skeleton::extractSkeleton(input, options.params());
  const std::string name = std::filesystem::path(mesh_path).filename().string();
  if (!result.status.ok()) return fail(mesh_path + ": " + result.status.message);
  // All files appear together at the end, skeleton.json (the index) last.
  OutputTransaction outputs;
  saveMesh(outputs.stage(out_dir + "/segmentation.ply"),
           skeleton::colourByVertexType(input, result.skeleton));
  if (options.write_regularised) {
    saveMesh(outputs.stage(out_dir + "/regularised.ply"), result.regularised_mesh);
  }
  if (!options.render_path.empty()) {
    presentation::renderSkeletonPng(input, result.skeleton, outputs.stage(options.render_path));
  }
  writeJsonFile(outputs.stage(out_dir + "/skeleton.json"),
                skeleton::skeletonToJson(result, input, info));
  outputs.commit();
  std::cout << skeleton::summaryLine(result, name) << std::endl;
  return kExitOk;
}

void registerSkeletonCommand(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("skeleton", "Mean-curvature skeleton and segmentation of a mesh");
  auto mesh = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>("skeleton_out");
  auto options = std::make_shared<SkeletonOptions>();
  cmd->add_option("MESH", *mesh, "Input mesh (.ply .obj .off .stl)")->required();
  cmd->add_option("--out", *out, "Output directory (skeleton.json, segmentation.ply)")
      ->capture_default_str();
  options->addTo(*cmd);
  cmd->callback(
      [=, &action] { action = [=] { return runSkeletonOnFile(*mesh, *out, *options); }; });
}

void registerShapeCommand(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("shape", "Write a generated test shape as a mesh file");
  auto name = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  std::string names;
  for (const auto& n : geometry::shapes::namedShapes()) names += (names.empty() ? "" : ", ") + n;
  cmd->add_option("NAME", *name, "Shape: " + names)->required();
  cmd->add_option("--out", *out, "Output mesh file (.ply .obj .off .stl)")->required();
  cmd->callback([=, &action] {
    action = [=] {
      checkOutputFileOption(*out);
      saveMesh(*out, geometry::shapes::makeNamedShape(*name));
      std::cout << "wrote " << *name << " to " << *out << std::endl;
      return kExitOk;
    };
  });
}

}  // namespace skelgrasp::cli
