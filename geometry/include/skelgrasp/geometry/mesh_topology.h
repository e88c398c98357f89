#pragma once
// Combinatorial facts about an indexed triangle mesh, used to report what regularisation did.
#include <nlohmann/json.hpp>

#include <optional>

#include "skelgrasp/common/mesh.h"

namespace skelgrasp::geometry {

struct MeshTopology {
  std::size_t vertices = 0;  // referenced by at least one face
  std::size_t unreferenced_vertices = 0;
  std::size_t faces = 0;
  std::size_t edges = 0;
  std::size_t boundary_edges = 0;                 // used by one face
  std::size_t non_manifold_edges = 0;             // used by more than two faces
  std::size_t inconsistently_oriented_edges = 0;  // two faces traverse it the same way
  std::size_t components = 0;                     // face-connected through shared vertices
  bool closed = false;                            // no boundary and no non-manifold edge
  int euler_characteristic = 0;                   // V - E + F over referenced vertices
  // Total genus sum over components, (2*components - chi)/2: only defined for a closed mesh.
  std::optional<int> genus;
  double signed_volume = 0;  // > 0: outward orientation (for closed, consistently oriented meshes)
};

MeshTopology analyzeTopology(const TriangleMesh& mesh);

nlohmann::json toJson(const MeshTopology& topology);

}  // namespace skelgrasp::geometry
