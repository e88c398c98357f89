#pragma once
// The skeleton stage: input mesh -> regularised closed mesh -> CGAL mean-curvature-flow skeleton
// -> every input vertex mapped to one skeleton vertex -> classification and segments.
#include <optional>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/mesh.h"
#include "skelgrasp/geometry/regularisation.h"
#include "skelgrasp/skeleton/skeleton.h"

namespace skelgrasp::skeleton {

// CGAL Mean_curvature_flow_skeletonization parameters. Defaults are CGAL's, which are also the
// values the reference implementation sets explicitly.
struct ContractionParams {
  double max_triangle_angle_rad = radiansFromDegrees(110.0);
  double quality_speed_tradeoff = 0.1;            // omega_H
  double medially_centered_speed_tradeoff = 0.2;  // omega_P
  double area_variation_factor = 1e-4;  // converged when area change / original area < this
  int max_iterations = 500;
  bool is_medially_centered = true;
  // Edges shorter than this fraction of the mesh's bounding-box diagonal are collapsed.
  double min_edge_length_fraction = 0.002;
  // Address space (bytes) of the ordered arena that keeps the contraction deterministic, on the
  // first attempt; it grows 4x per retry when used up. Unset: 16 KiB per vertex, at least 64 MiB
  // (a contraction uses about 1 KiB per vertex). The skeleton does not depend on it.
  std::optional<std::size_t> arena_reserve_bytes;
};

// The contraction's input by default: a mesh of at least this many vertices as it is when it
// already is a closed, self-intersection-free manifold (most YCB scans are: no wrap, 0.5-1.7 s
// saved per object), else its alpha wrap (a coarse CAD model too); either simplified to about this
// many vertices. The contraction's cost grows with the vertex count while its skeleton depends on
// the shape (docs/regularisation.md, "The skeleton stage's default").
inline constexpr std::size_t kDefaultContractionVertices = 2000;
inline geometry::RegularisationParams defaultSkeletonRegularisation() {
  geometry::RegularisationParams params;
  params.method = geometry::RegularisationMethod::kAuto;
  params.auto_min_vertices = kDefaultContractionVertices;
  params.max_vertices = kDefaultContractionVertices;
  return params;
}

struct SkeletonParams {
  geometry::RegularisationParams regularisation = defaultSkeletonRegularisation();
  ContractionParams contraction;
  // Terminal branches shorter than this factor times the inscribed radius where they attach are
  // removed as contraction artefacts (see cleanup.h); 0 keeps the raw CGAL skeleton.
  double spur_radius_factor = 0.5;
  GraphAnalysisParams graph;
};

struct Contraction {
  Status status;
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::array<int, 2>> edges;
  // Skeleton vertex of each vertex of the contracted (closed) mesh.
  std::vector<int> mesh_vertex_to_skeleton;
  std::size_t unassigned_mesh_vertices = 0;  // not reported by CGAL; mapped to the nearest vertex
  double time_s = 0;
};

// MCF contraction of a closed, single-part, outward 2-manifold (status kInvalidInput otherwise).
Contraction contractMesh(const TriangleMesh& closed_mesh, const ContractionParams& params = {});

struct SkeletonTimings {
  double regularise_s = 0;
  double skeleton_s = 0;  // contraction and conversion to the skeleton graph
  double mapping_s = 0;   // input vertices -> skeleton vertices
  double analysis_s = 0;  // classification, segments, curvature
  double total_s = 0;
};

struct SkeletonDiagnostics {
  std::size_t regularised_vertices = 0;
  std::size_t unassigned_mesh_vertices = 0;
  std::size_t pruned_spurs = 0;
  std::size_t pruned_spur_vertices = 0;
  // Distance from each input vertex to the regularised vertex it was mapped through.
  double mean_mapping_distance_m = 0;
  double max_mapping_distance_m = 0;
};

struct SkeletonResult {
  Status status;
  Skeleton skeleton;              // surface_points index the *input* mesh's vertices
  TriangleMesh regularised_mesh;  // the closed mesh that was contracted
  geometry::RegularisationReport regularisation;
  SkeletonTimings timing;
  SkeletonDiagnostics diagnostics;
};

// Runs the whole stage. Data problems (empty mesh, wrap failure) are reported in the status.
SkeletonResult extractSkeleton(const TriangleMesh& input, const SkeletonParams& params = {});

}  // namespace skelgrasp::skeleton
