#pragma once
// Header checks for mesh and point-cloud files, run before a third-party reader (CGAL, PCL) sees
// the file: the properties skelgrasp uses must be declared, and the element counts a header
// declares must fit in the file, so that a tiny file declaring a billion vertices fails at once
// with a message naming it instead of making the reader allocate gigabytes.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace skelgrasp {

// Byte counts declared by a file header can overflow 64 bits; these saturate at kSaturatedBytes
// instead, which is larger than any file, so a size check against it fails as it should.
constexpr std::uint64_t kSaturatedBytes = std::numeric_limits<std::uint64_t>::max();
inline std::uint64_t mulSaturating(std::uint64_t a, std::uint64_t b) {
  std::uint64_t r = 0;
  return __builtin_mul_overflow(a, b, &r) ? kSaturatedBytes : r;
}
inline std::uint64_t addSaturating(std::uint64_t a, std::uint64_t b) {
  std::uint64_t r = 0;
  return __builtin_add_overflow(a, b, &r) ? kSaturatedBytes : r;
}
// A byte count for a message ("more than 2^64" when saturated).
inline std::string bytesText(std::uint64_t bytes) {
  return bytes == kSaturatedBytes ? std::string("more than 2^64") : std::to_string(bytes);
}

// Smallest size of one number in a text format: one digit and one separator ("0 ").
inline constexpr std::uint64_t kMinAsciiBytesPerValue = 2;

// A count written in a file header: digits only. Throws IoError naming `what` for a negative,
// non-numeric or too large value (a sign or a fraction is malformed, not zero).
std::uint64_t parseHeaderCount(const std::string& path, const std::string& what,
                               const std::string& token);

// At most a few characters of `text` for an error line, non-printable bytes as '?'.
std::string printableText(const std::string& text);

struct PlyProperty {
  std::string name;
  bool is_list = false;
  std::uint64_t value_bytes = 0;  // scalar: its size; list: the size of one item
  std::uint64_t count_bytes = 0;  // list only: the size of its length prefix
  std::string type;               // as written: scalar type, or a list's item type
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  const PlyProperty* property(const std::string& property_name) const;
};

struct PlyHeader {
  enum class Format { kAscii, kBinaryLittleEndian, kBinaryBigEndian };
  Format format = Format::kAscii;
  std::vector<PlyElement> elements;
  std::uint64_t data_offset = 0;  // first byte after "end_header\n"
  const PlyElement* element(const std::string& element_name) const;
};

// Parses a PLY header and checks every declared element count against the bytes after the
// header: binary files need at least the exact minimum (fixed-size properties, and for list
// properties their length prefix), ASCII files kMinAsciiBytesPerValue per value. Throws
// IoError("<path>: <problem>") for a malformed header or counts larger than the file.
PlyHeader readPlyHeader(const std::string& path);

// Throws IoError unless the header has a "vertex" element with scalar x, y and z properties
// (e.g. "PLY vertex element has no 'z' property").
void requirePlyVertexXyz(const std::string& path, const PlyHeader& header);

// Checks what a mesh file declares before it is parsed; `ext` is the lower-case extension.
// PLY: the header above, vertex x/y/z, and a face element (when it has faces) with a
// vertex_indices list. OFF: vertex and face counts non-negative and fitting in the file. Binary
// STL: the triangle count against the file size. OBJ declares no counts. Throws IoError.
void checkMeshFileHeader(const std::string& path, const std::string& ext);

}  // namespace skelgrasp
