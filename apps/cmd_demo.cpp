// skelgrasp demo: runs the main job on shapes the program generates itself (no data needed).
#include <filesystem>
#include <iostream>

#include "cli.h"
#include "skeleton_options.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/common/primitives.h"

namespace skelgrasp::cli {

void registerDemoCommand(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("demo", "Run the skeleton stage on generated shapes");
  auto out = std::make_shared<std::string>("demo_output");
  cmd->add_option("--out", *out, "Output directory")->capture_default_str();
  cmd->callback([=, &action] {
    action = [=] {
      const SkeletonOptions options;
      for (const std::string name : {"mug", "hammer", "bottle", "y_shape"}) {
        const std::string dir = *out + "/" + name;
        std::filesystem::create_directories(dir);
        const std::string mesh_path = dir + "/" + name + ".ply";
        saveMesh(mesh_path, primitives::makeNamedShape(name));
        const int code = runSkeletonOnFile(mesh_path, dir, options);
        if (code != kExitOk) return code;
      }
      std::cout << "demo outputs in " << std::filesystem::absolute(*out).string()
                << " (skeleton.json, segmentation.ply per shape)" << std::endl;
      return kExitOk;
    };
  });
}

}  // namespace skelgrasp::cli
