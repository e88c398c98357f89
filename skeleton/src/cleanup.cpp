#include "skelgrasp/skeleton/cleanup.h"

#include <algorithm>

#include "skelgrasp/geometry/mesh_query.h"

namespace skelgrasp::skeleton {

SpurPruningStats pruneSpurs(Contraction& c, const TriangleMesh& closed_mesh, double radius_factor) {
  SpurPruningStats stats;
  if (radius_factor <= 0 || c.positions.size() < 4) return stats;
  const geometry::MeshQuery surface(closed_mesh);
  const int n = static_cast<int>(c.positions.size());
  std::vector<std::vector<int>> adjacency(n);
  for (const auto& e : c.edges) {
    adjacency[e[0]].push_back(e[1]);
    adjacency[e[1]].push_back(e[0]);
  }
  std::vector<char> removed(n, 0);
  std::vector<int> absorbed_by(n, -1);  // removed vertex -> branch vertex taking its points
  auto degree = [&](int v) {
    return static_cast<int>(std::count_if(adjacency[v].begin(), adjacency[v].end(),
                                          [&](int u) { return !removed[u]; }));
  };
  bool changed = true;
  while (changed) {
    changed = false;
    for (int start = 0; start < n; ++start) {
      if (removed[start] || degree(start) != 1) continue;
      // Walk the terminal chain to the first vertex of degree > 2.
      std::vector<int> chain{start};
      int prev = -1, cur = start;
      double length = 0;
      int branch = -1;
      while (true) {
        int next = -1;
        for (int u : adjacency[cur]) {
          if (!removed[u] && u != prev) {
            next = u;
            break;
          }
        }
        if (next < 0) break;
        length += (c.positions[next] - c.positions[cur]).norm();
        if (degree(next) > 2) {
          branch = next;
          break;
        }
        if (degree(next) != 2) break;  // reached another endpoint: a path, not a spur
        chain.push_back(next);
        prev = cur;
        cur = next;
      }
      if (branch < 0) continue;
      const double radius = surface.distance(c.positions[branch]);
      if (length >= radius_factor * radius) continue;
      for (int v : chain) {
        removed[v] = 1;
        absorbed_by[v] = branch;
      }
      ++stats.chains;
      stats.vertices += chain.size();
      changed = true;
    }
  }
  if (stats.chains == 0) return stats;

  // Resolve chains of absorption (a branch may itself be pruned later) and re-index.
  auto survivor = [&](int v) {
    while (removed[v]) v = absorbed_by[v];
    return v;
  };
  std::vector<int> new_index(n, -1);
  std::vector<Eigen::Vector3d> positions;
  for (int v = 0; v < n; ++v) {
    if (!removed[v]) {
      new_index[v] = static_cast<int>(positions.size());
      positions.push_back(c.positions[v]);
    }
  }
  std::vector<std::array<int, 2>> edges;
  for (const auto& e : c.edges) {
    if (!removed[e[0]] && !removed[e[1]]) edges.push_back({new_index[e[0]], new_index[e[1]]});
  }
  for (int& s : c.mesh_vertex_to_skeleton) s = new_index[survivor(s)];
  c.positions = std::move(positions);
  c.edges = std::move(edges);
  return stats;
}

}  // namespace skelgrasp::skeleton
