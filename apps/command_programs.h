#pragma once
// How the `skelgrasp` launcher (launcher.cpp) and the two command programs it starts (main.cpp,
// built twice) agree: which commands run in the light program, and the placeholders of the
// top-level help text that the launcher serves without starting either.
#include <array>
#include <string_view>

namespace skelgrasp::cli {

// Commands on meshes, hands and grasp files: they need skeleton, grasping and evaluation only,
// so the program that runs them loads no PCL, VTK or OpenCV (about 190 fewer shared libraries).
// Every other command runs in the full program.
constexpr std::array<std::string_view, 11> kMeshCommands = {
    "skeleton", "shape", "hands",  "close", "quality", "plan",
    "evaluate", "merge", "export", "score", "simulate"};

constexpr const char* kMeshProgram = "skelgrasp-mesh";
constexpr const char* kFullProgram = "skelgrasp-full";

// Set in the environment when the build renders the top-level help: the machine-dependent memory
// default is then written as kMemoryDefaultPlaceholder, and the program name (argv[0]) as
// kProgramPlaceholder, both filled in by the launcher at run time.
constexpr const char* kHelpTemplateVariable = "SKELGRASP_HELP_TEMPLATE";
constexpr std::string_view kMemoryDefaultPlaceholder = "@SKELGRASP_MEMORY_DEFAULT@";
constexpr std::string_view kProgramPlaceholder = "@SKELGRASP_PROGRAM@";

inline bool isMeshCommand(std::string_view word) {
  for (const auto& command : kMeshCommands) {
    if (command == word) return true;
  }
  return false;
}

}  // namespace skelgrasp::cli
