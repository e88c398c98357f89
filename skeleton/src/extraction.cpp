#include "skelgrasp/skeleton/extraction.h"

#include "skelgrasp/common/logging.h"
#include "skelgrasp/geometry/point_index.h"
#include "skelgrasp/skeleton/cleanup.h"

namespace skelgrasp::skeleton {

SkeletonResult extractSkeleton(const TriangleMesh& input, const SkeletonParams& params) {
  Stopwatch total;
  SkeletonResult result;
  if (input.empty()) {
    result.status = Status::Make(StatusCode::kInvalidInput, "input mesh is empty");
    return result;
  }

  auto regularised = geometry::regularise(input, params.regularisation);
  result.regularisation = regularised.report;
  result.timing.regularise_s = regularised.report.time_s;
  if (!regularised.status.ok()) {
    result.status = regularised.status;
    return result;
  }
  result.regularised_mesh = std::move(regularised.mesh);
  result.diagnostics.regularised_vertices = result.regularised_mesh.numVertices();

  Contraction contraction = contractMesh(result.regularised_mesh, params.contraction);
  result.timing.skeleton_s = contraction.time_s;
  if (!contraction.status.ok()) {
    result.status = contraction.status;
    return result;
  }
  result.diagnostics.unassigned_mesh_vertices = contraction.unassigned_mesh_vertices;
  const auto pruned = pruneSpurs(contraction, result.regularised_mesh, params.spur_radius_factor);
  result.diagnostics.pruned_spurs = pruned.chains;
  result.diagnostics.pruned_spur_vertices = pruned.vertices;

  // Input vertex -> nearest regularised vertex -> its skeleton vertex. Without wrapping the
  // regularised mesh is the input itself and the map is the identity.
  Stopwatch mapping;
  std::vector<int> point_to_vertex(input.numVertices());
  std::vector<double> distances;
  const bool identity = params.regularisation.method == geometry::RegularisationMethod::kNone &&
                        result.regularised_mesh.numVertices() == input.numVertices();
  if (identity) {
    point_to_vertex = contraction.mesh_vertex_to_skeleton;
    distances.assign(input.numVertices(), 0.0);
  } else {
    const auto nearest =
        geometry::nearestPoints(result.regularised_mesh.vertices, input.vertices, &distances);
    for (std::size_t i = 0; i < nearest.size(); ++i) {
      point_to_vertex[i] = contraction.mesh_vertex_to_skeleton[nearest[i]];
    }
  }
  double sum = 0, worst = 0;
  for (double d : distances) {
    sum += d;
    worst = std::max(worst, d);
  }
  result.diagnostics.mean_mapping_distance_m = distances.empty() ? 0 : sum / distances.size();
  result.diagnostics.max_mapping_distance_m = worst;
  result.timing.mapping_s = mapping.seconds();

  Stopwatch analysis;
  result.skeleton =
      analyzeSkeletonGraph(contraction.positions, contraction.edges, point_to_vertex, params.graph);
  result.timing.analysis_s = analysis.seconds();
  result.timing.total_s = total.seconds();

  const auto& s = result.skeleton;
  log().info(
      "skeleton: {} vertices ({} branch, {} endpoint), {} segments, {} loop(s); regularise "
      "{:.2f} s, contract {:.2f} s",
      s.vertices.size(), s.countType(VertexType::kBranch), s.countType(VertexType::kEndpoint),
      s.segments.size(), s.cycleRank(), result.timing.regularise_s, result.timing.skeleton_s);
  return result;
}

}  // namespace skelgrasp::skeleton
