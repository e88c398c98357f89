// fuzz_replay TARGET FILE...: runs files through a fuzz target without libFuzzer or sanitizers, so
// a memory checker that needs an ordinary build (valgrind) can watch third-party readers that the
// sanitizers do not instrument (PCL, CGAL, urdfdom). Exit 0 when every file was handled.
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz_targets.h"
#include "skelgrasp/common/logging.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: fuzz_replay TARGET FILE...\n");
    return 2;
  }
  skelgrasp::setLogLevel(spdlog::level::off);
  skelgrasp::fuzz::Target target = nullptr;
  for (const auto& t : skelgrasp::fuzz::allTargets()) {
    if (std::strcmp(t.name, argv[1]) == 0) target = t.run;
  }
  if (!target) {
    std::fprintf(stderr, "fuzz_replay: no target named %s\n", argv[1]);
    return 2;
  }
  for (int i = 2; i < argc; ++i) {
    std::ifstream in(argv[i], std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
    std::fprintf(stderr, "fuzz_replay: %s\n", argv[i]);
    target(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  }
  return 0;
}
