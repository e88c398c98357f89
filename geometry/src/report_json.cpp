// JSON forms of the geometry stages' reports (written by the stage that owns them).
#include "skelgrasp/common/json.h"
#include "skelgrasp/geometry/mesh_topology.h"
#include "skelgrasp/geometry/regularisation.h"

namespace skelgrasp::geometry {

nlohmann::json toJson(const MeshTopology& t) {
  return {{"vertices", t.vertices},
          {"faces", t.faces},
          {"edges", t.edges},
          {"boundary_edges", t.boundary_edges},
          {"non_manifold_edges", t.non_manifold_edges},
          {"inconsistently_oriented_edges", t.inconsistently_oriented_edges},
          {"components", t.components},
          {"closed", t.closed},
          {"euler_characteristic", t.euler_characteristic},
          {"genus", t.genus ? nlohmann::json(*t.genus) : nlohmann::json(nullptr)},
          {"signed_volume_m3", t.signed_volume}};
}

nlohmann::json toJson(const RegularisationReport& reg) {
  return {{"method", reg.method},
          {"bbox_diagonal_m", reg.bbox_diagonal_m},
          {"alpha_m", reg.alpha_m},
          {"offset_m", reg.offset_m},
          {"remeshed", reg.remeshed},
          {"decimated_from_vertices", reg.decimated_from},
          {"orientation_flipped", reg.orientation_flipped},
          {"filled_holes", reg.filled_holes},
          {"wrap_components", reg.wrap_components},
          {"join_retries", reg.join_retries},
          {"dropped_area_fraction", reg.dropped_area_fraction},
          {"input", toJson(reg.input)},
          {"output", toJson(reg.output)},
          {"time_s", reg.time_s}};
}

}  // namespace skelgrasp::geometry
