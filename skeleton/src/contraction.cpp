// CGAL translation unit: mean-curvature-flow skeletonization.
// CGAL containers of this file allocate from an ordered arena while one is active (see
// ordered_arena.h): it makes the contraction's address-ordered edge collapses deterministic.
#include "ordered_arena.h"
#define CGAL_ALLOCATOR(T) skelgrasp::internal::OrderedArenaAllocator<T>

#include <CGAL/Mean_curvature_flow_skeletonization.h>
#include <CGAL/Random.h>
#include <CGAL/boost/graph/property_maps.h>

#include <set>

#include "skelgrasp/common/logging.h"
#include "skelgrasp/geometry/point_index.h"
#include "skelgrasp/internal/cgal_conversions.h"
#include "skelgrasp/skeleton/extraction.h"

namespace skelgrasp::skeleton {

using internal::CgalKernel;
using internal::CgalMesh;
using internal::CgalPoint;

namespace {

// First guess of the ordered arena's address space per input vertex, with a floor; the arena grows
// kArenaGrowth-fold per retry up to kMaxArenaBytes. Address space only (pages are committed when
// touched), so a generous guess costs nothing but must stay below common `ulimit -v` settings.
constexpr std::size_t kMiB = std::size_t(1) << 20;
constexpr std::size_t kArenaBytesPerInputVertex = 16 * 1024;  // measured use: ~1 KiB (YCB)
constexpr std::size_t kMinArenaBytes = 64 * kMiB;
constexpr std::size_t kMaxArenaBytes = std::size_t(64) << 30;
constexpr std::size_t kArenaGrowth = 4;

// One contraction inside an ordered arena of `reserve_bytes`. Returns false when the arena ran
// out and the heap took over (the caller repeats it in a larger one); otherwise fills `out`
// (status, positions, vertex map, edges). Every CGAL object lives inside this function so that it
// dies before the arena.
bool contractInArena(const CgalMesh& mesh, const TriangleMesh& closed_mesh,
                     const ContractionParams& params, std::size_t reserve_bytes, Contraction& out) {
  using Skeletonization = CGAL::Mean_curvature_flow_skeletonization<CgalMesh>;
  internal::OrderedArenaScope arena(reserve_bytes);
  Skeletonization::Skeleton graph;
  CGAL::get_default_random() = CGAL::Random(0);  // results depend on the input only
  try {
    Skeletonization mcs(mesh);
    mcs.set_max_triangle_angle(params.max_triangle_angle_rad);
    mcs.set_quality_speed_tradeoff(params.quality_speed_tradeoff);
    mcs.set_medially_centered_speed_tradeoff(params.medially_centered_speed_tradeoff);
    mcs.set_area_variation_factor(params.area_variation_factor);
    mcs.set_max_iterations(params.max_iterations);
    mcs.set_is_medially_centered(params.is_medially_centered);
    mcs.set_min_edge_length(params.min_edge_length_fraction * closed_mesh.bounds().diagonal());
    mcs.contract_until_convergence();
    mcs.convert_to_skeleton(graph);
  } catch (const std::exception& e) {
    if (arena.overflowed()) return false;  // heap addresses may have changed the outcome
    out.status =
        Status::Make(StatusCode::kFailed, std::string("MCF contraction failed: ") + e.what());
    return true;
  }
  if (arena.overflowed()) return false;  // correct but not reproducible: repeat in a larger arena
  log().debug("contraction: ordered arena used {} MiB for {} vertices", arena.usedBytes() / kMiB,
              closed_mesh.vertices.size());
  const std::size_t nv = boost::num_vertices(graph);
  if (nv == 0) {
    out.status = Status::Make(StatusCode::kFailed, "MCF contraction produced an empty skeleton");
    return true;
  }
  out.positions.resize(nv);
  out.mesh_vertex_to_skeleton.assign(closed_mesh.vertices.size(), -1);
  for (auto v : CGAL::make_range(boost::vertices(graph))) {
    out.positions[v] = internal::toEigen(graph[v].point);
    for (auto mv : graph[v].vertices) out.mesh_vertex_to_skeleton[mv.idx()] = static_cast<int>(v);
  }
  std::set<std::pair<int, int>> unique_edges;  // the graph type would allow parallel edges
  for (auto e : CGAL::make_range(boost::edges(graph))) {
    const int a = static_cast<int>(boost::source(e, graph));
    const int b = static_cast<int>(boost::target(e, graph));
    if (a != b && unique_edges.insert({std::min(a, b), std::max(a, b)}).second) {
      out.edges.push_back({a, b});
    }
  }
  return true;
}

}  // namespace

Contraction contractMesh(const TriangleMesh& closed_mesh, const ContractionParams& params) {
  if (!(params.max_triangle_angle_rad > 0) || !(params.quality_speed_tradeoff > 0) ||
      !(params.medially_centered_speed_tradeoff > 0) || !(params.area_variation_factor > 0) ||
      params.max_iterations <= 0 || !(params.min_edge_length_fraction > 0)) {
    throw InvalidArgument("contractMesh: contraction parameters must be positive");
  }
  Stopwatch watch;
  Contraction out;
  CgalMesh mesh;
  if (!internal::toCgalMesh(closed_mesh, mesh) || !CGAL::is_closed(mesh) ||
      !CGAL::is_triangle_mesh(mesh)) {
    out.status = Status::Make(StatusCode::kInvalidInput,
                              "contraction needs a closed triangle 2-manifold; regularise first");
    return out;
  }
  // Address space of the ordered arena: a first guess from the vertex count, four times more per
  // retry (see ordered_arena.h); the result does not depend on it.
  std::size_t reserve_bytes = params.arena_reserve_bytes.value_or(
      std::max(kMinArenaBytes, kArenaBytesPerInputVertex * closed_mesh.vertices.size()));
  if (reserve_bytes == 0)
    throw InvalidArgument("contractMesh: arena_reserve_bytes must be positive");
  for (;;) {
    try {
      if (contractInArena(mesh, closed_mesh, params, reserve_bytes, out)) break;
    } catch (const std::bad_alloc&) {
      out.status = Status::Make(StatusCode::kFailed, "MCF contraction: cannot reserve " +
                                                         std::to_string(reserve_bytes >> 20) +
                                                         " MiB of address space");
      return out;
    }
    if (reserve_bytes >= kMaxArenaBytes) {
      out.status = Status::Make(StatusCode::kFailed, "MCF contraction: arena limit reached");
      return out;
    }
    reserve_bytes = std::min(kMaxArenaBytes, reserve_bytes * kArenaGrowth);
    log().debug("contraction: ordered arena exhausted, retrying with {} MiB", reserve_bytes >> 20);
  }
  if (!out.status.ok()) return out;
  // CGAL assigns every vertex in practice; a fallback keeps the partition exact if it does not.
  std::vector<Eigen::Vector3d> orphans;
  std::vector<std::size_t> orphan_ids;
  for (std::size_t i = 0; i < out.mesh_vertex_to_skeleton.size(); ++i) {
    if (out.mesh_vertex_to_skeleton[i] < 0) {
      orphans.push_back(closed_mesh.vertices[i]);
      orphan_ids.push_back(i);
    }
  }
  if (!orphans.empty()) {
    const auto nearest = geometry::nearestPoints(out.positions, orphans);
    for (std::size_t k = 0; k < orphans.size(); ++k)
      out.mesh_vertex_to_skeleton[orphan_ids[k]] = nearest[k];
    out.unassigned_mesh_vertices = orphans.size();
  }
  out.time_s = watch.seconds();
  return out;
}

}  // namespace skelgrasp::skeleton
