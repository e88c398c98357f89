#pragma once
// Checks of what a point-cloud file declares, run before PCL reads it: PCL sizes its buffers
// from the header (WIDTH x HEIGHT x point size, or the PLY vertex count) and allocates before it
// finds that the data is not there.
#include <cstdint>
#include <string>

namespace skelgrasp::internal {

struct DeclaredCloud {
  std::uint64_t points = 0;       // points the header declares
  std::uint64_t point_bytes = 0;  // bytes of one point in PCL's in-memory layout
};

// PCD: the header's WIDTH x HEIGHT (and POINTS) against the bytes after DATA: binary needs the
// exact size, binary_compressed an uncompressed size that matches and compressed data that is
// present, ascii at least kMinAsciiBytesPerValue per value. Throws IoError naming the file.
// Headers it cannot size (no SIZE line, ...) are left to PCL's own checks: returns points 0.
DeclaredCloud checkPcdDeclaredSize(const std::string& path);

// PLY: the vertex element with x, y, z and every element count against the file size.
DeclaredCloud checkPlyCloudHeader(const std::string& path);

}  // namespace skelgrasp::internal
