#include "skelgrasp/geometry/mesh_validity.h"

#include <cmath>

namespace skelgrasp::geometry {

std::string degenerateMeshProblem(const TriangleMesh& mesh) {
  if (mesh.empty()) return "";
  const double diagonal = mesh.bounds().diagonal();
  if (!std::isfinite(diagonal)) return "degenerate mesh: vertex coordinates are not finite";
  if (!(diagonal > 0)) return "degenerate mesh: all vertices coincide";
  const double min_area = kMinFaceAreaOfDiagonalSquared * diagonal * diagonal;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    if (mesh.faceArea(f) > min_area) return "";
  return "degenerate mesh: no face has a positive area (all faces are collinear or degenerate)";
}

}  // namespace skelgrasp::geometry
