// Mesh I/O through CGAL's polygon-soup readers (the only CGAL translation unit of common/).
#include "skelgrasp/common/mesh_io.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>

#include "skelgrasp/common/atomic_file.h"
#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/file_header.h"
#include "skelgrasp/common/logging.h"

namespace skelgrasp {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalPoint = Kernel::Point_3;

bool isSupported(const std::string& ext) {
  return ext == "ply" || ext == "obj" || ext == "off" || ext == "stl";
}

void checkReadable(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw IoError(path, "no such file");
  if (fs::is_directory(path, ec)) throw IoError(path, "is a directory, expected a mesh file");
  std::ifstream probe(path, std::ios::binary);
  if (!probe) throw IoError(path, "cannot open for reading");
  if (fs::file_size(path, ec) == 0) throw IoError(path, "file is empty");
}

void writePlyBinary(std::ostream& out, const TriangleMesh& mesh,
                    const std::vector<PlyVertexProperty>& extra = {}) {
  const bool colors = mesh.vertex_colors.size() == mesh.vertices.size() && !mesh.vertices.empty();
  out << "ply\nformat binary_little_endian 1.0\ncomment written by skelgrasp (units: m)\n"
      << "element vertex " << mesh.vertices.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\n";
  if (colors) out << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  for (const auto& property : extra) out << "property uchar " << property.name << "\n";
  out << "element face " << mesh.faces.size() << "\nproperty list uchar int vertex_indices\n"
      << "end_header\n";
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const float xyz[3] = {static_cast<float>(mesh.vertices[i].x()),
                          static_cast<float>(mesh.vertices[i].y()),
                          static_cast<float>(mesh.vertices[i].z())};
    out.write(reinterpret_cast<const char*>(xyz), sizeof(xyz));
    if (colors) out.write(reinterpret_cast<const char*>(mesh.vertex_colors[i].data()), 3);
    for (const auto& property : extra) {
      out.write(reinterpret_cast<const char*>(&property.values[i]), 1);
    }
  }
  for (const auto& f : mesh.faces) {
    const unsigned char n = 3;
    const std::int32_t idx[3] = {f[0], f[1], f[2]};
    out.write(reinterpret_cast<const char*>(&n), 1);
    out.write(reinterpret_cast<const char*>(idx), sizeof(idx));
  }
}

void writePlyBinary(const std::string& path, const TriangleMesh& mesh,
                    const std::vector<PlyVertexProperty>& extra = {}) {
  writeFileAtomically(path, [&](std::ostream& out) { writePlyBinary(out, mesh, extra); });
}

// An OFF file declaring zero vertices is a valid but empty mesh, not a parse error.
bool isEmptyMeshHeader(const std::string& path, const std::string& ext) {
  if (ext != "off") return false;
  std::ifstream in(path);
  std::string magic;
  long nv = -1;
  in >> magic >> nv;
  return magic == "OFF" && nv == 0;
}

// CGAL stores face indices as std::size_t, so a negative index in the file arrives wrapped
// around; report it as the number the file holds. OBJ's negative indices are legal and relative
// to the last vertex (CGAL resolves them), so a negative result there reached before vertex 1.
std::string faceIndexProblem(const std::string& ext, std::size_t face, std::int64_t index,
                             std::size_t vertices) {
  if (index < 0 && ext == "obj") {
    return "face " + std::to_string(face) +
           " has a relative (negative) vertex index reaching before the first vertex";
  }
  if (index < 0) {
    return "face " + std::to_string(face) + " has a negative vertex index (" +
           std::to_string(index) + ")";
  }
  return "face " + std::to_string(face) + " references vertex " + std::to_string(index) +
         ", but the file has only " + std::to_string(vertices) +
         " vertices (index out of range; indices count from 0)";
}

// One whitespace-separated token of an OFF file; '#' starts a comment to the end of its line.
bool nextOffToken(std::istream& in, std::string& token) {
  while (in >> token) {
    if (token[0] != '#') return true;
    in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  return false;
}

// A face's vertex index as the file writes it: an integer of at most 18 digits (so it fits
// std::int64_t), else nullopt.
std::optional<std::int64_t> offIndexValue(const std::string& token) {
  constexpr std::size_t kMaxIndexDigits = 18;
  const std::size_t sign = token[0] == '-' || token[0] == '+';
  const std::size_t digits = token.size() - sign;
  if (digits == 0 || digits > kMaxIndexDigits ||
      !std::all_of(token.begin() + sign, token.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return std::nullopt;
  return std::stoll(token);
}

// The largest vertex, face or edge count an OFF header may declare: CGAL reads them into int and
// computes twice the edge count.
constexpr std::int64_t kMaxOffHeaderCount = std::numeric_limits<int>::max() / 2;

// CGAL's OFF reader reads face indices as floating-point numbers and converts them to
// std::size_t: an index that is not an integer in range is undefined behaviour there (1e62 was
// found by fuzzing), and otherwise it stops without saying which. This walks the file as CGAL
// does (header counts, then per vertex three coordinates and the rest of its line, per face a
// corner count and that many indices and the rest of its line) and names the first bad index.
std::string findOffFaceIndexProblem(const std::string& path) {
  std::ifstream in(path);
  std::string magic, token;
  if (!nextOffToken(in, magic) || magic.find("OFF") == std::string::npos) return {};
  // CGAL reads the counts as numbers, not words: "00-10" is an edge count of 0 followed by a
  // corner count of -10 (found by fuzzing), so each count must be a whole word of digits.
  std::int64_t counts[3] = {0, 0, 0};
  const char* count_names[3] = {"vertex", "face", "edge"};
  for (int k = 0; k < 3; ++k) {
    if (!nextOffToken(in, token)) return {};
    const auto value = offIndexValue(token);
    if (!value || *value < 0) {
      return std::string("OFF header: the ") + count_names[k] + " count is not a whole number ('" +
             printableText(token) + "')";
    }
    // CGAL keeps the counts in int and doubles the edge count (half-edges): 1700413616 edges
    // overflowed (found by fuzzing). No mesh skelgrasp can hold comes near these counts.
    if (*value > kMaxOffHeaderCount) {
      return std::string("OFF header: the ") + count_names[k] + " count " + token +
             " is too large (at most " + std::to_string(kMaxOffHeaderCount) + ")";
    }
    counts[k] = *value;
  }
  const std::int64_t vertices = counts[0], faces = counts[1];
  constexpr int kCoordinatesPerVertex = 3;
  for (std::int64_t v = 0; v < vertices; ++v) {
    for (int k = 0; k < kCoordinatesPerVertex; ++k) {
      if (!nextOffToken(in, token)) return {};  // too short: CGAL says so
    }
    in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  for (std::int64_t face = 0; face < faces; ++face) {
    if (!nextOffToken(in, token)) return {};
    const auto corners = offIndexValue(token);
    if (!corners || *corners < 0) {
      return "face " + std::to_string(face) + " has a corner count that is not a count ('" +
             printableText(token) + "')";
    }
    // CGAL sizes the face before reading its indices: a corner count of 10^17 allocated until
    // the fuzzer's time ran out. A face has at most as many corners as the file has vertices.
    if (*corners > vertices) {
      return "face " + std::to_string(face) + " has " + std::to_string(*corners) +
             " corners, but the file has only " + std::to_string(vertices) + " vertices";
    }
    for (std::int64_t k = 0; k < *corners; ++k) {
      if (!nextOffToken(in, token)) return {};
      const auto index = offIndexValue(token);
      if (!index) {
        return "face " + std::to_string(face) + " has a vertex index that is not an integer ('" +
               printableText(token) + "')";
      }
      if (*index < 0 || *index >= vertices) {
        return faceIndexProblem("off", static_cast<std::size_t>(face), *index,
                                static_cast<std::size_t>(vertices));
      }
    }
    in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  return {};
}

// CGAL's readers only say "failed"; name the likeliest problem from what was read before it.
std::string diagnoseParseFailure(const std::string& path, const std::string& ext,
                                 std::size_t points,
                                 const std::vector<std::vector<std::size_t>>& polygons) {
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    for (std::size_t idx : polygons[f]) {
      if (idx >= points) return faceIndexProblem(ext, f, static_cast<std::int64_t>(idx), points);
    }
  }
  if (ext == "off") {
    const std::string problem = findOffFaceIndexProblem(path);
    if (!problem.empty()) return problem;
  }
  // Text formats: a NaN/inf token stops the number parser; report its line.
  std::ifstream in(path);
  std::string line;
  for (std::size_t number = 1; std::getline(in, line) && number <= 50'000'000; ++number) {
    std::string lower;
    for (char c : line) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    std::istringstream tokens(lower);
    std::string token;
    while (tokens >> token) {
      if (token == "nan" || token == "-nan" || token == "inf" || token == "-inf" ||
          token == "+inf" || token == "infinity") {
        return "non-finite (NaN or inf) coordinate on line " + std::to_string(number);
      }
    }
    if (line.find('\0') != std::string::npos) break;  // binary payload: stop scanning
  }
  if (points == 0)
    return "cannot parse " + ext + " file: not a valid " + ext + " header or no vertex data";
  if (polygons.empty()) {
    return "cannot parse " + ext + " file: read " + std::to_string(points) +
           " vertices but no faces (truncated, malformed, or a point set without triangles)";
  }
  return "cannot parse " + ext + " file: stopped after " + std::to_string(points) +
         " vertices and " + std::to_string(polygons.size()) +
         " faces (truncated, malformed, or a face index out of range)";
}

}  // namespace

std::string fileExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

LengthUnit parseLengthUnit(const std::string& text) {
  if (text == "auto") return LengthUnit::kAuto;
  if (text == "m" || text == "meters" || text == "metres") return LengthUnit::kMeters;
  if (text == "mm" || text == "millimeters" || text == "millimetres")
    return LengthUnit::kMillimeters;
  throw InvalidArgument("unknown length unit '" + text + "' (use auto, m or mm)");
}

TriangleMesh loadMesh(const std::string& path, const MeshLoadOptions& options, MeshLoadInfo* info) {
  const std::string ext = fileExtension(path);
  checkReadable(path);
  if (!isSupported(ext)) {
    throw IoError(path, "unknown mesh format '." + ext + "' (supported: .ply .obj .off .stl)");
  }
  // Before CGAL allocates what the header declares and silently defaults missing coordinates.
  checkMeshFileHeader(path, ext);
  if (ext == "off") {
    const std::string problem = findOffFaceIndexProblem(path);
    if (!problem.empty()) throw IoError(path, problem);
  }

  std::vector<CgalPoint> points;
  std::vector<std::vector<std::size_t>> polygons;
  bool ok = false;
  try {
    ok = CGAL::IO::read_polygon_soup(path, points, polygons, CGAL::parameters::verbose(false));
  } catch (const std::exception& e) {
    throw IoError(path, std::string("cannot parse ") + ext + " file: " + e.what());
  }
  if (!ok && points.empty() && polygons.empty() && isEmptyMeshHeader(path, ext)) {
    throw IoError(path, "mesh has no vertices");
  }
  if (!ok) throw IoError(path, diagnoseParseFailure(path, ext, points.size(), polygons));
  if (points.empty()) throw IoError(path, "mesh has no vertices");

  MeshLoadInfo local;
  local.path = path;
  local.format = ext;
  TriangleMesh mesh;
  mesh.vertices.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d p(points[i].x(), points[i].y(), points[i].z());
    if (!p.allFinite()) {
      throw IoError(path, "non-finite (NaN or inf) coordinate at vertex " + std::to_string(i));
    }
    mesh.vertices.push_back(p);
  }
  mesh.faces.reserve(polygons.size());
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    const auto& poly = polygons[f];
    for (std::size_t idx : poly) {
      if (idx >= points.size())
        throw IoError(path,
                      faceIndexProblem(ext, f, static_cast<std::int64_t>(idx), points.size()));
    }
    if (poly.size() < 3) {
      ++local.degenerate_faces_dropped;
      continue;
    }
    if (poly.size() > 3) ++local.polygons_triangulated;
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
      const Eigen::Vector3i t(static_cast<int>(poly[0]), static_cast<int>(poly[k]),
                              static_cast<int>(poly[k + 1]));
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
        ++local.degenerate_faces_dropped;
        continue;
      }
      mesh.faces.push_back(t);
    }
  }
  if (mesh.faces.empty()) throw IoError(path, "mesh has no triangles");

  const double diagonal = mesh.bounds().diagonal();
  switch (options.units) {
    case LengthUnit::kMeters:
      break;
    case LengthUnit::kMillimeters:
      local.scale_to_meters = kMetresPerMillimetre;
      break;
    case LengthUnit::kAuto:
      if (diagonal > options.auto_millimetre_diagonal) {
        local.scale_to_meters = kMetresPerMillimetre;
        local.units_guessed = true;
        log().warn(
            "{}: bounding-box diagonal {:.3g} exceeds {:.3g}, assuming millimetres and scaling "
            "to metres (pass --units m to keep the values)",
            path, diagonal, options.auto_millimetre_diagonal);
      }
      break;
  }
  if (local.scale_to_meters != 1.0) mesh.scale(local.scale_to_meters);
  if (local.degenerate_faces_dropped > 0) {
    log().warn("{}: dropped {} degenerate face(s)", path, local.degenerate_faces_dropped);
  }
  log().debug("{}: loaded {} vertices, {} triangles", path, mesh.numVertices(), mesh.numFaces());
  if (info) *info = local;
  return mesh;
}

void saveMesh(const std::string& path, const TriangleMesh& mesh) {
  const std::string ext = fileExtension(path);
  if (ext == "ply") {
    writePlyBinary(path, mesh);
    return;
  }
  if (!isSupported(ext)) {
    throw IoError(path, "unknown mesh format '." + ext + "' (supported: .ply .obj .off .stl)");
  }
  std::vector<CgalPoint> points;
  points.reserve(mesh.vertices.size());
  for (const auto& v : mesh.vertices) points.emplace_back(v.x(), v.y(), v.z());
  std::vector<std::vector<std::size_t>> polygons;
  polygons.reserve(mesh.faces.size());
  for (const auto& f : mesh.faces) {
    polygons.push_back({static_cast<std::size_t>(f[0]), static_cast<std::size_t>(f[1]),
                        static_cast<std::size_t>(f[2])});
  }
  // CGAL picks the format from the extension, which the temporary name keeps.
  writeFileViaTemporary(path, [&](const std::string& temporary) {
    if (!CGAL::IO::write_polygon_soup(temporary, points, polygons,
                                      CGAL::parameters::stream_precision(9))) {
      throw IoError(temporary, "write failed");
    }
  });
}

void saveMesh(const std::string& path, const TriangleMesh& mesh,
              const std::vector<PlyVertexProperty>& extra_properties) {
  if (fileExtension(path) != "ply") {
    throw InvalidArgument(path + ": extra vertex properties can only be written to .ply files");
  }
  for (const auto& property : extra_properties) {
    const bool name_ok = !property.name.empty() &&
                         std::all_of(property.name.begin(), property.name.end(),
                                     [](unsigned char c) { return std::isalnum(c) || c == '_'; });
    if (!name_ok) throw InvalidArgument("bad PLY property name '" + property.name + "'");
    if (property.values.size() != mesh.vertices.size()) {
      throw InvalidArgument("PLY property '" + property.name + "' has " +
                            std::to_string(property.values.size()) + " values for " +
                            std::to_string(mesh.vertices.size()) + " vertices");
    }
  }
  writePlyBinary(path, mesh, extra_properties);
}

std::vector<std::uint8_t> loadPlyVertexProperty(const std::string& path, const std::string& name) {
  checkReadable(path);
  if (fileExtension(path) != "ply") throw IoError(path, "not a .ply file");
  checkMeshFileHeader(path, "ply");
  CGAL::Surface_mesh<CgalPoint> mesh;
  std::ifstream in(path, std::ios::binary);
  bool ok = false;
  try {
    ok = CGAL::IO::read_PLY(in, mesh);
  } catch (const std::exception& e) {
    throw IoError(path, std::string("cannot parse ply file: ") + e.what());
  }
  if (!ok) {
    throw IoError(path, "cannot read as a 2-manifold PLY mesh (needed for vertex properties)");
  }
  using VertexIndex = CGAL::Surface_mesh<CgalPoint>::Vertex_index;
  const auto [map, found] = mesh.property_map<VertexIndex, std::uint8_t>("v:" + name);
  if (!found) throw IoError(path, "no uchar vertex property '" + name + "'");
  std::vector<std::uint8_t> values;
  values.reserve(mesh.number_of_vertices());
  for (VertexIndex v : mesh.vertices()) values.push_back(map[v]);
  return values;
}

}  // namespace skelgrasp
