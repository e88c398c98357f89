#include "skelgrasp/internal/cloud_file_check.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <vector>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/file_header.h"

namespace skelgrasp::internal {
namespace {

// A PCD header is a dozen short lines; a file without a DATA line in its first MiB is not PCD
// (PCL then reports it), and the limit keeps a newline-free binary file from being read whole.
constexpr std::uint64_t kMaxPcdHeaderBytes = 1 << 20;
// binary_compressed data starts with two uint32: compressed and uncompressed byte counts.
constexpr std::uint64_t kPcdCompressedPrefixBytes = 8;
// LZF turns at most 264 repeated bytes into a 3-byte back reference (ratio 88); a header claiming
// more than this expansion does not describe LZF data, however the bytes decompress.
constexpr std::uint64_t kLzfMaxExpansion = 100;

const std::set<std::string> kPcdHeaderKeywords = {
    "VERSION", "FIELDS", "SIZE", "TYPE", "COUNT", "WIDTH", "HEIGHT", "VIEWPOINT", "POINTS"};
const std::set<std::string> kPcdDataTypes = {"ascii", "binary", "binary_compressed"};

// The header line a keyword means to PCL, which matches keywords by their beginning and takes
// COLUMNS for FIELDS (old PCD files): "COLUMNSNT" redefined the fields after SIZE and TYPE and PCL
// read past its buffer (found by fuzzing). Other words are returned unchanged.
std::string pclHeaderKeyword(const std::string& word) {
  static const std::pair<const char*, const char*> kPrefixes[] = {
      {"FIELDS", "FIELDS"}, {"COLUMNS", "FIELDS"},      {"SIZE", "SIZE"},
      {"TYPE", "TYPE"},     {"COUNT", "COUNT"},         {"WIDTH", "WIDTH"},
      {"HEIGHT", "HEIGHT"}, {"VIEWPOINT", "VIEWPOINT"}, {"POINTS", "POINTS"},
      {"DATA", "DATA"},     {"VERSION", "VERSION"}};
  for (const auto& [prefix, keyword] : kPrefixes) {
    if (word.rfind(prefix, 0) == 0) return keyword;
  }
  return word;
}

std::uint32_t readUint32Le(const unsigned char* b) {
  return b[0] | (b[1] << 8) | (b[2] << 16) | (static_cast<std::uint32_t>(b[3]) << 24);
}

// SIZE and TYPE of each field must be a size PCL copies by: F 4 or 8 bytes, I and U 1, 2, 4 or 8.
// PCL converts fields by their type's size whatever SIZE says, so `SIZE 4 0 0` made it copy
// 12 bytes out of a 4-byte point (a heap overflow; found by fuzzing).
void checkPcdFieldTypes(const std::string& path, const std::vector<std::string>& sizes,
                        const std::vector<std::string>& types) {
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    const std::string& size = sizes[i];
    const bool integer_size = size == "1" || size == "2" || size == "4" || size == "8";
    const bool float_size = size == "4" || size == "8";
    // Without TYPE only the sizes are checked.
    const std::string type = i < types.size() ? types[i] : "?";
    const bool ok = (type == "F" && float_size) || ((type == "I" || type == "U") && integer_size) ||
                    (type == "?" && integer_size);
    if (!ok) {
      throw IoError(path, "PCD header: field " + std::to_string(i + 1) + " has SIZE " + size +
                              " and TYPE " + type +
                              " (F takes 4 or 8 bytes, I and U take 1, 2, 4 or 8)");
    }
  }
}

}  // namespace

DeclaredCloud checkPcdDeclaredSize(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, "cannot open for reading");
  std::map<std::string, std::vector<std::string>> keys;
  std::string data_type;
  std::uint64_t data_offset = 0;
  std::error_code size_error;
  const std::uint64_t whole_file = std::filesystem::file_size(path, size_error);
  if (size_error) throw IoError(path, "cannot read file size: " + size_error.message());
  for (std::string line; data_type.empty() && std::getline(in, line);) {
    // A last line without a newline leaves the stream at its end, where tellg() fails: the next
    // byte is the end of the file.
    const std::int64_t offset =
        in.eof() ? static_cast<std::int64_t>(whole_file) : static_cast<std::int64_t>(in.tellg());
    if (offset < 0 || static_cast<std::uint64_t>(offset) > kMaxPcdHeaderBytes) return {};
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream tokens(line);
    std::string word;
    if (!(tokens >> word) || word[0] == '#') continue;
    const std::string keyword = pclHeaderKeyword(word);
    std::vector<std::string> values;
    for (std::string v; tokens >> v;) values.push_back(v);
    // PCL parses a repeated header line again (a second FIELDS after SIZE and TYPE leaves fields
    // without sizes) and then writes past its point buffer (found by fuzzing, seen with valgrind
    // in PCL 1.13): every header line may appear once.
    if (kPcdHeaderKeywords.count(keyword) && keys.count(keyword)) {
      throw IoError(path, "PCD header: " + keyword + " appears twice");
    }
    if (keyword == "DATA") {
      if (values.size() != 1 || !kPcdDataTypes.count(values[0])) {
        throw IoError(path, "PCD header: DATA must be ascii, binary or binary_compressed");
      }
      data_type = values[0];
      data_offset = static_cast<std::uint64_t>(offset);
    } else {
      keys[keyword] = values;
    }
  }
  // FIELDS, SIZE, TYPE and COUNT describe the same fields; PCL sizes its buffer from one and
  // writes by another.
  const std::size_t fields = keys["FIELDS"].size();
  for (const char* keyword : {"SIZE", "TYPE", "COUNT"}) {
    if (keys.count(keyword) && keys[keyword].size() != fields) {
      throw IoError(path, std::string("PCD header: ") + keyword + " has " +
                              std::to_string(keys[keyword].size()) + " entries for " +
                              std::to_string(fields) + " FIELDS");
    }
  }
  // PCL converts each field by its TYPE; SIZE without TYPE (or TYPE without SIZE) leaves one of
  // them to PCL's defaults, and `SIZE 8 1 1` without TYPE overflowed like `SIZE 4 0 0` (found by
  // fuzzing).
  if (keys.count("SIZE") != keys.count("TYPE")) {
    throw IoError(path, std::string("PCD header: ") + (keys.count("SIZE") ? "SIZE" : "TYPE") +
                            " without " + (keys.count("SIZE") ? "TYPE" : "SIZE"));
  }
  checkPcdFieldTypes(path, keys["SIZE"], keys["TYPE"]);
  // PCL reads the first word of WIDTH, HEIGHT and POINTS as the count and ignores the rest, so
  // a line with more words is sized by PCL but was not by this check: `POINTS 0005000000000\301 0`
  // made PCL allocate 160 GB (found by fuzzing). Each is one count.
  for (const char* keyword : {"WIDTH", "HEIGHT", "POINTS"}) {
    if (keys.count(keyword) && keys[keyword].size() != 1) {
      throw IoError(path, std::string("PCD header: ") + keyword + " must be one count, not " +
                              std::to_string(keys[keyword].size()) + " words");
    }
  }
  // PCL rejects a header without DATA, but only after it has allocated the points POINTS declares
  // (335 million took seconds; found by fuzzing).
  if (data_type.empty()) throw IoError(path, "PCD header has no DATA line");
  const auto& sizes = keys["SIZE"];
  const auto& counts = keys["COUNT"];
  DeclaredCloud declared;
  std::uint64_t values_per_point = 0;
  if (!sizes.empty() && keys["WIDTH"].size() == 1) {
    for (std::size_t i = 0; i < sizes.size(); ++i) {
      const std::uint64_t size = parseHeaderCount(path, "PCD header: SIZE", sizes[i]);
      const std::uint64_t count =
          i < counts.size() ? parseHeaderCount(path, "PCD header: COUNT", counts[i]) : 1;
      declared.point_bytes += mulSaturating(size, count);
      values_per_point += count;
    }
    const std::uint64_t width = parseHeaderCount(path, "PCD header: WIDTH", keys["WIDTH"][0]);
    const std::uint64_t height =
        keys["HEIGHT"].size() == 1 ? parseHeaderCount(path, "PCD header: HEIGHT", keys["HEIGHT"][0])
                                   : 1;
    declared.points = mulSaturating(width, height);
  } else if (keys["POINTS"].size() == 1) {
    // Without SIZE or WIDTH PCL fills in what it can (the width from POINTS) and allocates every
    // declared point before reading (a 244-byte file declaring 5 million points took seconds;
    // found by fuzzing): POINTS still bounds the data at one value, or one byte, per point.
    declared.point_bytes = 1;
    values_per_point = 1;
  } else {
    return {};  // nothing to size: PCL rejects the header before reading data
  }
  if (keys["POINTS"].size() == 1) {
    declared.points =
        std::max(declared.points, parseHeaderCount(path, "PCD header: POINTS", keys["POINTS"][0]));
  }

  std::error_code ec;
  const std::uint64_t file_size = std::filesystem::file_size(path, ec);
  if (ec) throw IoError(path, "cannot read file size: " + ec.message());
  const std::uint64_t available = file_size > data_offset ? file_size - data_offset : 0;
  const std::uint64_t data_bytes = mulSaturating(declared.points, declared.point_bytes);
  const std::string declares = "PCD header declares " + std::to_string(declared.points) +
                               " points of " + std::to_string(declared.point_bytes) + " bytes";
  const std::string truncated = " bytes follow the header (truncated file or corrupt header)";
  if (data_type == "binary") {
    if (data_bytes > available) {
      throw IoError(path, declares + " (" + bytesText(data_bytes) +
                              " bytes of binary data), but only " + std::to_string(available) +
                              truncated);
    }
  } else if (data_type == "binary_compressed") {
    unsigned char prefix[kPcdCompressedPrefixBytes];
    in.seekg(static_cast<std::streamoff>(data_offset));
    if (available < kPcdCompressedPrefixBytes ||
        !in.read(reinterpret_cast<char*>(prefix), sizeof(prefix))) {
      throw IoError(path, "binary_compressed PCD has no compressed data after its header");
    }
    const std::uint64_t compressed = readUint32Le(prefix);
    const std::uint64_t uncompressed = readUint32Le(prefix + 4);
    if (compressed > available - kPcdCompressedPrefixBytes) {
      throw IoError(path, "binary_compressed PCD says " + std::to_string(compressed) +
                              " bytes of compressed data, but only " +
                              std::to_string(available - kPcdCompressedPrefixBytes) + truncated);
    }
    if (uncompressed != data_bytes) {
      throw IoError(path, declares + " (" + bytesText(data_bytes) +
                              " bytes), but its compressed data says " +
                              std::to_string(uncompressed) + " bytes (corrupt header)");
    }
    if (data_bytes > mulSaturating(compressed, kLzfMaxExpansion)) {
      throw IoError(path, declares + " (" + bytesText(data_bytes) + " bytes) from " +
                              std::to_string(compressed) +
                              " bytes of compressed data, more than LZF can expand to (corrupt "
                              "header)");
    }
  } else if (data_type == "ascii") {
    const std::uint64_t needed =
        mulSaturating(mulSaturating(declared.points, values_per_point), kMinAsciiBytesPerValue);
    // The last value may end the file without a separator.
    if (needed > available + 1) {
      throw IoError(path, declares + " (at least " + bytesText(needed) +
                              " bytes of ASCII data), but only " + std::to_string(available) +
                              truncated);
    }
  }
  return declared;
}

DeclaredCloud checkPlyCloudHeader(const std::string& path) {
  const PlyHeader header = readPlyHeader(path);
  requirePlyVertexXyz(path, header);
  const PlyElement* vertex = header.element("vertex");
  DeclaredCloud declared;
  declared.points = vertex->count;
  for (const auto& p : vertex->properties) declared.point_bytes += p.is_list ? 0 : p.value_bytes;
  return declared;
}

}  // namespace skelgrasp::internal
