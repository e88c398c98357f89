#pragma once
// Reading and writing triangle meshes: PLY (ASCII and binary), OBJ, OFF, STL.
// Vertex order of PLY, OBJ and OFF files is preserved, so vertex indices in skelgrasp's outputs
// refer to the file's own vertices; STL (a triangle soup) is welded by exact position.
#include <cstdint>
#include <string>
#include <vector>

#include "skelgrasp/common/mesh.h"

namespace skelgrasp {

enum class LengthUnit { kAuto, kMeters, kMillimeters };

// "auto" | "m" | "mm" -> LengthUnit; throws InvalidArgument otherwise.
LengthUnit parseLengthUnit(const std::string& text);

struct MeshLoadOptions {
  // kAuto: a mesh whose bounding-box diagonal exceeds `auto_millimetre_diagonal` (in file units)
  // is taken to be in millimetres and scaled to metres, with a warning.
  LengthUnit units = LengthUnit::kAuto;
  double auto_millimetre_diagonal = 5.0;
};

struct MeshLoadInfo {
  std::string path;
  std::string format;                        // "ply", "obj", "off", "stl"
  double scale_to_meters = 1.0;              // factor applied to the file's coordinates
  bool units_guessed = false;                // scale chosen by the kAuto rule
  std::size_t polygons_triangulated = 0;     // faces with > 3 corners fan-split
  std::size_t degenerate_faces_dropped = 0;  // faces repeating a vertex index
};

// Loads a mesh. Throws IoError("<path>: <problem>") for a missing/unreadable file, an unknown
// extension, a parse failure, a mesh without triangles, non-finite coordinates or out-of-range
// face indices.
TriangleMesh loadMesh(const std::string& path, const MeshLoadOptions& options = {},
                      MeshLoadInfo* info = nullptr);

// Writes a mesh; the format follows the extension. PLY is written binary little-endian with
// per-vertex colours when the mesh has them. Throws IoError on failure.
void saveMesh(const std::string& path, const TriangleMesh& mesh);

// One extra per-vertex PLY property of type uchar (e.g. "observed"), one value per vertex.
struct PlyVertexProperty {
  std::string name;
  std::vector<std::uint8_t> values;
};

// Writes a binary PLY with the extra uchar vertex properties after x y z (and colours). Readers
// that do not know them (loadMesh, most viewers) ignore them; vertex order is kept. Throws
// InvalidArgument for a non-PLY path, a bad name or a size mismatch, IoError on failure.
void saveMesh(const std::string& path, const TriangleMesh& mesh,
              const std::vector<PlyVertexProperty>& extra_properties);

// Reads one uchar vertex property from a PLY mesh (through CGAL's Surface_mesh PLY reader, which
// keeps vertex order, so value i belongs to vertex i of loadMesh(path)). Throws IoError when the
// file cannot be read as a 2-manifold PLY mesh or has no such uchar property.
std::vector<std::uint8_t> loadPlyVertexProperty(const std::string& path, const std::string& name);

// Lower-cased extension without the dot ("" if none).
std::string fileExtension(const std::string& path);

}  // namespace skelgrasp
