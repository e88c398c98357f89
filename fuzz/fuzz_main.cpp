// libFuzzer entry point of one target; SKELGRASP_FUZZ_TARGET names it (see fuzz_targets.h).
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "fuzz_targets.h"
#include "skelgrasp/common/logging.h"

namespace {

skelgrasp::fuzz::Target findTarget() {
  for (const auto& t : skelgrasp::fuzz::allTargets()) {
    if (std::strcmp(t.name, SKELGRASP_FUZZ_TARGET) == 0) return t.run;
  }
  std::fprintf(stderr, "fuzz: no target named %s\n", SKELGRASP_FUZZ_TARGET);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // Readers warn about odd but legal input; millions of warnings would drown the findings.
  skelgrasp::setLogLevel(spdlog::level::off);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const skelgrasp::fuzz::Target target = findTarget();
  return target(data, size);
}
