#include "skelgrasp/common/file_header.h"

#include <charconv>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>

#include "skelgrasp/common/error.h"

namespace skelgrasp {

std::string printableText(const std::string& text) {
  constexpr std::size_t kMaxShownChars = 16;
  std::string out;
  for (char c : text.substr(0, kMaxShownChars)) out += (c >= ' ' && c <= '~') ? c : '?';
  return text.size() > kMaxShownChars ? out + "..." : out;
}

namespace {

// A PLY header is a few hundred bytes; a file without "end_header" in its first MiB is not PLY,
// and stopping there keeps a binary file without newlines from being read whole as one line.
constexpr std::uint64_t kMaxPlyHeaderBytes = 1 << 20;
// Binary STL: 80-byte header, uint32 triangle count, then 50 bytes per triangle.
constexpr std::uint64_t kStlHeaderBytes = 84;
constexpr std::uint64_t kStlTriangleBytes = 50;

std::uint64_t fileSize(const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw IoError(path, "cannot read file size: " + ec.message());
  return size;
}

std::uint64_t plyTypeBytes(const std::string& path, const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" || type == "float" ||
      type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  throw IoError(path, "unknown PLY property type '" + type + "'");
}

}  // namespace

std::uint64_t parseHeaderCount(const std::string& path, const std::string& what,
                               const std::string& token) {
  if (!token.empty() && token[0] == '-') {
    throw IoError(path, what + " is negative (" + token + ")");
  }
  std::uint64_t value = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec == std::errc::result_out_of_range)
    throw IoError(path, what + " is too large (" + token + ")");
  if (ec != std::errc() || end != token.data() + token.size()) {
    throw IoError(path, what + " is not a count ('" + token + "')");
  }
  return value;
}

namespace {

// Least number of bytes one element occupies in the file's encoding.
std::uint64_t minElementBytes(const PlyElement& element, PlyHeader::Format format) {
  std::uint64_t bytes = 0;
  for (const auto& p : element.properties) {
    if (format == PlyHeader::Format::kAscii) {
      bytes += kMinAsciiBytesPerValue;  // a scalar, or a list's length (an empty list)
    } else {
      bytes += p.is_list ? p.count_bytes : p.value_bytes;
    }
  }
  return bytes;
}

void checkPlyCounts(const std::string& path, const PlyHeader& header) {
  const std::uint64_t size = fileSize(path);
  const std::uint64_t available = size > header.data_offset ? size - header.data_offset : 0;
  // The last ASCII value may end the file without a separator.
  const std::uint64_t slack = header.format == PlyHeader::Format::kAscii ? 1 : 0;
  std::uint64_t needed = 0;
  for (const auto& element : header.elements) {
    const std::uint64_t element_bytes =
        mulSaturating(element.count, minElementBytes(element, header.format));
    needed = addSaturating(needed, element_bytes);
    if (needed > addSaturating(available, slack)) {
      throw IoError(path, "PLY header declares " + std::to_string(element.count) + " '" +
                              element.name + "' elements, which need at least " +
                              bytesText(needed) + " bytes of " +
                              (header.format == PlyHeader::Format::kAscii ? "ASCII" : "binary") +
                              " data, but only " + std::to_string(available) +
                              " bytes follow the header (truncated file or corrupt header)");
    }
  }
}

}  // namespace

const PlyProperty* PlyElement::property(const std::string& property_name) const {
  for (const auto& p : properties) {
    if (p.name == property_name) return &p;
  }
  return nullptr;
}

const PlyElement* PlyHeader::element(const std::string& element_name) const {
  for (const auto& e : elements) {
    if (e.name == element_name) return &e;
  }
  return nullptr;
}

PlyHeader readPlyHeader(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, "cannot open for reading");
  PlyHeader header;
  bool format_seen = false;
  bool ended = false;
  std::string line;
  for (std::size_t number = 1; !ended; ++number) {
    if (!std::getline(in, line)) throw IoError(path, "PLY header has no 'end_header' line");
    const auto offset = in.tellg();
    if (offset < 0 || static_cast<std::uint64_t>(offset) > kMaxPlyHeaderBytes) {
      throw IoError(path, "PLY header has no 'end_header' line in its first 1 MiB");
    }
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream tokens(line);
    std::string keyword;
    tokens >> keyword;
    const std::string where = "PLY header line " + std::to_string(number);
    if (number == 1) {
      if (keyword != "ply") throw IoError(path, "not a PLY file (first line is not 'ply')");
      continue;
    }
    if (keyword.empty() || keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "format") {
      std::string format;
      tokens >> format;
      if (format == "ascii") {
        header.format = PlyHeader::Format::kAscii;
      } else if (format == "binary_little_endian") {
        header.format = PlyHeader::Format::kBinaryLittleEndian;
      } else if (format == "binary_big_endian") {
        header.format = PlyHeader::Format::kBinaryBigEndian;
      } else {
        throw IoError(path, where + ": unknown PLY format '" + format + "'");
      }
      format_seen = true;
    } else if (keyword == "element") {
      PlyElement element;
      std::string count;
      if (!(tokens >> element.name >> count)) {
        throw IoError(path, where + ": expected 'element NAME COUNT'");
      }
      element.count =
          parseHeaderCount(path, where + ": count of element '" + element.name + "'", count);
      // CGAL reads every element of a name, and this check sizes and types only the first: a
      // second 'vertex' element whose x was no float made CGAL call through a null pointer
      // (found by fuzzing). An element name means one element.
      if (header.element(element.name)) {
        throw IoError(path,
                      where + ": element '" + printableText(element.name) + "' declared twice");
      }
      header.elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (header.elements.empty()) throw IoError(path, where + ": property before any element");
      PlyProperty property;
      std::string type;
      tokens >> type;
      if (type == "list") {
        std::string count_type, item_type;
        tokens >> count_type >> item_type;
        property.is_list = true;
        property.count_bytes = plyTypeBytes(path, count_type);
        property.value_bytes = plyTypeBytes(path, item_type);
        property.type = item_type;
      } else {
        property.value_bytes = plyTypeBytes(path, type);
        property.type = type;
      }
      if (!(tokens >> property.name)) throw IoError(path, where + ": property without a name");
      if (header.elements.back().property(property.name)) {
        throw IoError(path, where + ": property '" + printableText(property.name) +
                                "' declared twice in element '" +
                                printableText(header.elements.back().name) + "'");
      }
      header.elements.back().properties.push_back(property);
    } else if (keyword == "end_header") {
      header.data_offset = static_cast<std::uint64_t>(offset);
      ended = true;
    } else {
      throw IoError(path, where + ": unknown PLY keyword '" + keyword + "'");
    }
  }
  if (!format_seen) throw IoError(path, "PLY header has no 'format' line");
  checkPlyCounts(path, header);
  return header;
}

void requirePlyVertexXyz(const std::string& path, const PlyHeader& header) {
  const PlyElement* vertex = header.element("vertex");
  if (!vertex) throw IoError(path, "PLY file has no 'vertex' element");
  for (const char* axis : {"x", "y", "z"}) {
    const PlyProperty* p = vertex->property(axis);
    if (!p) throw IoError(path, std::string("PLY vertex element has no '") + axis + "' property");
    if (p->is_list) {
      throw IoError(path,
                    std::string("PLY vertex property '") + axis + "' is a list, not a number");
    }
    // CGAL's PLY reader reads coordinates only as float or double: an integer coordinate makes
    // it call through a null pointer (found by fuzzing: `property uint8 z`).
    if (p->type != "float" && p->type != "float32" && p->type != "double" && p->type != "float64") {
      throw IoError(path, std::string("PLY vertex property '") + axis + "' is of type " + p->type +
                              ", expected float or double");
    }
  }
}

void checkMeshFileHeader(const std::string& path, const std::string& ext) {
  if (ext == "ply") {
    const PlyHeader header = readPlyHeader(path);
    requirePlyVertexXyz(path, header);
    const PlyElement* face = header.element("face");
    if (face && face->count > 0) {
      const PlyProperty* indices = face->property("vertex_indices");
      if (!indices) indices = face->property("vertex_index");
      if (!indices || !indices->is_list) {
        throw IoError(path, "PLY face element has no 'vertex_indices' list property");
      }
    }
    return;
  }
  if (ext == "off") {
    std::ifstream in(path, std::ios::binary);
    std::vector<std::string> tokens;
    std::string token;
    // Magic, then vertex, face and edge counts; '#' starts a comment.
    while (tokens.size() < 4 && in >> token) {
      if (token[0] == '#') {
        in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
        continue;
      }
      tokens.push_back(token);
    }
    // The magic word is OFF with optional prefixes (ST, C, N, 4, n: texture, colour, normal,
    // homogeneous, n-dimensional). Anything else is not OFF; CGAL's reader reads uninitialised
    // memory on some such headers (found by make fuzz, seen with valgrind), so it never sees them.
    static const std::regex kOffMagic("(ST)?C?N?4?n?OFF");
    if (tokens.empty() || !std::regex_match(tokens[0], kOffMagic)) {
      throw IoError(path, "OFF header: the file must start with OFF (or COFF, NOFF, ...), not '" +
                              printableText(tokens.empty() ? std::string() : tokens[0]) + "'");
    }
    // Variants skelgrasp does not size here (n-dimensional, binary) are left to the parser.
    if (tokens.size() < 3 || tokens[0].find('n') != std::string::npos || tokens[1] == "BINARY") {
      return;
    }
    const std::uint64_t vertices = parseHeaderCount(path, "OFF header: vertex count", tokens[1]);
    const std::uint64_t faces = parseHeaderCount(path, "OFF header: face count", tokens[2]);
    const auto offset = in.tellg();
    const std::uint64_t size = fileSize(path);
    const std::uint64_t available =
        offset < 0 ? 0 : size - std::min<std::uint64_t>(size, static_cast<std::uint64_t>(offset));
    // Three coordinates per vertex, at least a corner count per face.
    const std::uint64_t needed = addSaturating(mulSaturating(vertices, 3 * kMinAsciiBytesPerValue),
                                               mulSaturating(faces, kMinAsciiBytesPerValue));
    if (needed > available + 1) {
      throw IoError(path, "OFF header declares " + std::to_string(vertices) + " vertices and " +
                              std::to_string(faces) + " faces, which need at least " +
                              bytesText(needed) + " bytes, but only " + std::to_string(available) +
                              " bytes follow the header (truncated file or corrupt header)");
    }
    return;
  }
  if (ext == "stl") {
    const std::uint64_t size = fileSize(path);
    if (size < kStlHeaderBytes) return;  // too short to be binary; the parser tries ASCII
    std::ifstream in(path, std::ios::binary);
    char head[kStlHeaderBytes];
    if (!in.read(head, sizeof(head))) return;
    const auto* count_bytes = reinterpret_cast<const unsigned char*>(head + 80);
    const std::uint64_t triangles = count_bytes[0] | (count_bytes[1] << 8) |
                                    (count_bytes[2] << 16) |
                                    (static_cast<std::uint64_t>(count_bytes[3]) << 24);
    const std::uint64_t needed = kStlHeaderBytes + triangles * kStlTriangleBytes;
    if (needed <= size) return;  // binary STL with its triangles (extra bytes are tolerated)
    if (std::strncmp(head, "solid", 5) == 0) return;  // ASCII STL
    throw IoError(path, "binary STL declares " + std::to_string(triangles) +
                            " triangles, which need " + std::to_string(needed) +
                            " bytes, but the file has " + std::to_string(size) +
                            " bytes (truncated file or corrupt header)");
  }
}

}  // namespace skelgrasp
