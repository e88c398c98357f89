// skelgrasp: the command-line entry point. It loads no stage library. Each command runs in one of
// two programs installed beside it, chosen by the command word: commands on meshes run in
// skelgrasp-mesh, which never loads PCL, VTK or OpenCV, the rest in skelgrasp-full. Loading the
// ~210 shared libraries of the full program costs 0.2-0.5 s before main; `skelgrasp --help` is
// answered here from text the full program rendered at build time.
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <iostream>
#include <string>
#include <string_view>

#include "command_programs.h"
#include "skelgrasp/common/resources.h"

namespace {

using namespace skelgrasp::cli;

constexpr int kExitBadInput = 2;

// The full program's `--help` with placeholders (command_programs.h), rendered by the build.
constexpr const char kTopLevelHelpTemplate[] =
#include "top_level_help.inc"
    ;

std::string replaceAll(std::string text, std::string_view from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos;
       at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
  return text;
}

// The command programs live beside this executable, wherever it was built or installed.
std::string executableDirectory() {
  std::string path(4096, '\0');
  const ssize_t length = readlink("/proc/self/exe", path.data(), path.size() - 1);
  if (length <= 0) return ".";
  path.resize(static_cast<std::size_t>(length));
  const std::size_t slash = path.rfind('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

bool isHelpFlag(std::string_view word) {
  return word == "-h" || word == "--help";
}

// The first argument that is neither an option nor the value of the one global option that takes
// a value: the command. Empty when there is none.
std::string_view commandWord(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view word = argv[i];
    if (word == "--memory-limit") {
      ++i;  // its value may look like a word ("4G")
    } else if (!word.empty() && word[0] != '-') {
      return word;
    }
  }
  return {};
}

bool asksTopLevelHelp(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (isHelpFlag(argv[i])) return true;
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string_view command = commandWord(argc, argv);
  if (command.empty() && asksTopLevelHelp(argc, argv)) {
    std::string help = replaceAll(kTopLevelHelpTemplate, kProgramPlaceholder, argv[0]);
    help = replaceAll(
        help, kMemoryDefaultPlaceholder,
        skelgrasp::formatBytes(static_cast<double>(skelgrasp::defaultMemoryLimitBytes())));
    std::cout << help << std::flush;
    return std::cout ? 0 : kExitBadInput;
  }
  // Everything else, errors included, is the command programs' business: same argv, same name.
  const std::string program =
      executableDirectory() + "/" + (isMeshCommand(command) ? kMeshProgram : kFullProgram);
  execv(program.c_str(), argv);
  std::cerr << "skelgrasp: error: cannot start " << program << ": " << std::strerror(errno)
            << std::endl;
  return kExitBadInput;
}
