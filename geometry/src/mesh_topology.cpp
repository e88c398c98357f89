#include "skelgrasp/geometry/mesh_topology.h"

#include <numeric>
#include <unordered_map>

namespace skelgrasp::geometry {
namespace {

struct DisjointSets {
  explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::size_t find(std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(std::size_t a, std::size_t b) { parent[find(a)] = find(b); }
  std::vector<std::size_t> parent;
};

}  // namespace

MeshTopology analyzeTopology(const TriangleMesh& mesh) {
  MeshTopology topo;
  topo.faces = mesh.faces.size();
  const std::size_t n = mesh.vertices.size();

  // Edge key: (min, max) vertex; value: face count and orientation balance (+1 for min->max).
  struct EdgeUse {
    int count = 0;
    int forward = 0;
  };
  std::unordered_map<std::uint64_t, EdgeUse> edges;
  edges.reserve(mesh.faces.size() * 2);
  std::vector<char> referenced(n, 0);
  DisjointSets sets(n);
  for (const auto& f : mesh.faces) {
    for (int k = 0; k < 3; ++k) {
      const auto a = static_cast<std::uint64_t>(f[k]);
      const auto b = static_cast<std::uint64_t>(f[(k + 1) % 3]);
      referenced[a] = 1;
      auto& use = edges[a < b ? (a << 32 | b) : (b << 32 | a)];
      ++use.count;
      if (a < b) ++use.forward;
    }
    sets.unite(f[0], f[1]);
    sets.unite(f[1], f[2]);
  }
  topo.edges = edges.size();
  for (const auto& [key, use] : edges) {
    if (use.count == 1) ++topo.boundary_edges;
    if (use.count > 2) ++topo.non_manifold_edges;
    if (use.count == 2 && use.forward != 1) ++topo.inconsistently_oriented_edges;
  }
  std::vector<char> is_root(n, 0);
  for (std::size_t v = 0; v < n; ++v) {
    if (!referenced[v]) {
      ++topo.unreferenced_vertices;
      continue;
    }
    ++topo.vertices;
    const std::size_t r = sets.find(v);
    if (!is_root[r]) {
      is_root[r] = 1;
      ++topo.components;
    }
  }
  topo.closed = topo.boundary_edges == 0 && topo.non_manifold_edges == 0 && topo.faces > 0;
  topo.euler_characteristic =
      static_cast<int>(topo.vertices) - static_cast<int>(topo.edges) + static_cast<int>(topo.faces);
  if (topo.closed) {
    topo.genus = (2 * static_cast<int>(topo.components) - topo.euler_characteristic) / 2;
  }
  topo.signed_volume = mesh.signedVolume();
  return topo;
}

}  // namespace skelgrasp::geometry
