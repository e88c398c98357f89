#pragma once
// Internal: the built-in hands' files, embedded at build time (see grasping/CMakeLists.txt).
#include <cstddef>

namespace skelgrasp::grasping::internal {

struct EmbeddedHand {
  const char* name;
  const char* urdf;
  const char* description;
};

extern const EmbeddedHand kEmbeddedHands[];
extern const std::size_t kNumEmbeddedHands;

}  // namespace skelgrasp::grasping::internal
