// JSON of the meshing stage (one entry of "objects" in report.json, docs/reconstruction.md).
#include "skelgrasp/common/json.h"
#include "skelgrasp/geometry/mesh_topology.h"
#include "skelgrasp/reconstruction/meshing.h"

namespace skelgrasp::reconstruction {

nlohmann::json toJson(const MeshingResult& meshing, const MeshingParams& p, std::size_t cluster,
                      const std::string& mesh_file) {
  const auto& r = meshing.report;
  const TriangleMesh& mesh = meshing.mesh;
  nlohmann::json j = {
      {"cluster", cluster},
      {"status", skelgrasp::toJson(meshing.status)},
      {"mesh_file", mesh_file.empty() ? nlohmann::json(nullptr) : nlohmann::json(mesh_file)},
      {"points", r.input_points},
      {"completion",
       {{"support_plane", p.completion.support_plane},
        {"points", r.completion_points},
        {"cell_m", p.completion.cell_m},
        {"time_s", r.completion_s}}},
      {"poisson",
       {{"depth", p.poisson.depth},
        {"point_weight", p.poisson.point_weight},
        {"samples_per_node", p.poisson.samples_per_node},
        {"scale", p.poisson.scale},
        {"vertices", r.poisson_vertices},
        {"faces", r.poisson_faces},
        {"time_s", r.poisson_s}}},
      {"trimming",
       {{"mode", toString(p.trim.mode)},
        {"threshold_m", r.trim_threshold_m},
        {"min_density_points", p.trim.min_density_points},
        {"faces_removed", r.trimmed_faces},
        {"faces_kept", r.faces_after_trim},
        {"time_s", r.trim_s}}},
      {"regularisation", geometry::toJson(r.regularisation)},
      {"observed",
       {{"distance_m", p.observed_distance_m},
        {"vertices", r.observed_vertices},
        {"fraction", r.observed_fraction},
        {"area_fraction", r.observed_area_fraction},
        {"time_s", r.observed_s}}},
      {"time_s", r.total_s}};
  if (meshing.status.ok()) {
    const geometry::MeshTopology t = geometry::analyzeTopology(mesh);
    j["mesh"] = {{"vertices", mesh.numVertices()},
                 {"faces", mesh.numFaces()},
                 {"box_min", skelgrasp::toJson(mesh.bounds().min)},
                 {"box_max", skelgrasp::toJson(mesh.bounds().max)},
                 {"extent_m", skelgrasp::toJson(mesh.bounds().extent())},
                 {"area_m2", mesh.area()},
                 {"volume_m3", mesh.signedVolume()},
                 {"closed", t.closed},
                 {"components", t.components},
                 {"genus", t.genus ? nlohmann::json(*t.genus) : nlohmann::json(nullptr)}};
  }
  return j;
}

}  // namespace skelgrasp::reconstruction
