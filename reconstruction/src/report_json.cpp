#include "skelgrasp/reconstruction/report_json.h"

#include "skelgrasp/common/json.h"
#include "skelgrasp/geometry/mesh_topology.h"
#include "skelgrasp/geometry/regularisation.h"

namespace skelgrasp::reconstruction {

namespace {

nlohmann::json statusJson(const Status& s) {
  return {{"code", skelgrasp::toString(s.code)}, {"message", s.message}};
}

nlohmann::json clusterJson(std::size_t index, const perception::ClusterInfo& c) {
  return {{"index", index},
          {"points", c.points},
          {"centroid", skelgrasp::toJson(c.centroid)},
          {"box_min", skelgrasp::toJson(c.box.min)},
          {"box_max", skelgrasp::toJson(c.box.max)},
          {"extent_m", skelgrasp::toJson(c.extent)},
          {"height_above_plane_m", c.height_above_plane_m},
          {"selected", c.selected}};
}

nlohmann::json objectJson(const ObjectReconstruction& o, const MeshingParams& p,
                          const std::string& mesh_file) {
  const auto& r = o.meshing.report;
  const TriangleMesh& mesh = o.meshing.mesh;
  nlohmann::json j = {
      {"cluster", o.cluster},
      {"status", statusJson(o.meshing.status)},
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
      {"regularisation", toJson(r.regularisation)},
      {"observed",
       {{"distance_m", p.observed_distance_m},
        {"vertices", r.observed_vertices},
        {"fraction", r.observed_fraction},
        {"area_fraction", r.observed_area_fraction},
        {"time_s", r.observed_s}}},
      {"time_s", r.total_s}};
  if (o.meshing.status.ok()) {
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

}  // namespace

nlohmann::json reconstructionReport(const perception::Scan& scan,
                                    const ReconstructionParams& params,
                                    const ReconstructionResult& result,
                                    const std::vector<std::string>& mesh_files) {
  using nlohmann::json;
  const auto& ingest = result.ingest;
  const auto& scene = ingest.scene;
  json j;
  j["schema"] = "skelgrasp.reconstruction/1";
  j["status"] = statusJson(result.status);
  j["input"] = {{"source", scan.source},
                {"points", scan.cloud.size()},
                {"organized", scan.cloud.isOrganized()},
                {"views", scan.views},
                {"object_mask", !scan.object_mask.empty()},
                {"per_view_normals", scan.per_view_normals},
                {"sensor_origin", skelgrasp::toJson(scan.cloud.sensor_origin)}};
  json filters = json::array();
  for (const auto& s : ingest.filter_steps) {
    filters.push_back({{"name", s.name},
                       {"points_in", s.points_in},
                       {"points_out", s.points_out},
                       {"time_s", s.time_s}});
  }
  const auto& fp = params.ingest.filters;
  j["filters"] = {{"voxel_leaf_m", fp.voxel_leaf_m},
                  {"outlier_mean_k", fp.sor_mean_k},
                  {"outlier_stddev_mul", fp.sor_stddev_mul},
                  {"crop_box", fp.crop_box ? json{{"min", skelgrasp::toJson(fp.crop_box->min)},
                                                  {"max", skelgrasp::toJson(fp.crop_box->max)}}
                                           : json(nullptr)},
                  {"steps", filters},
                  {"points_out", ingest.points_filtered}};
  if (scene.plane) {
    const auto& pl = *scene.plane;
    j["plane"] = {{"coefficients", {pl.normal.x(), pl.normal.y(), pl.normal.z(), pl.d}},
                  {"inliers", pl.inliers}};
  } else {
    j["plane"] = nullptr;
  }
  j["scene"] = {{"plane_requirement", perception::toString(params.ingest.scene.plane)},
                {"target", params.ingest.scene.target.toString()},
                {"candidate_points", scene.candidate_points},
                {"other_points", scene.other_points.size()},
                {"cluster_tolerance_m", params.ingest.scene.cluster_tolerance_m}};
  json clusters = json::array();
  for (std::size_t i = 0; i < scene.cluster_info.size(); ++i) {
    clusters.push_back(clusterJson(i, scene.cluster_info[i]));
  }
  j["clusters"] = clusters;
  json objects = json::array();
  for (std::size_t k = 0; k < result.objects.size(); ++k) {
    objects.push_back(objectJson(result.objects[k], params.meshing,
                                 k < mesh_files.size() ? mesh_files[k] : std::string()));
  }
  j["objects"] = objects;
  double meshing_s = 0;
  for (const auto& o : result.objects) meshing_s += o.meshing.report.total_s;
  j["timings"] = {{"filters_s", ingest.filter_time_s},
                  {"scene_s", ingest.scene_time_s},
                  {"normals_s", ingest.normals_time_s},
                  {"meshing_s", meshing_s},
                  {"total_s", result.total_s}};
  return j;
}

}  // namespace skelgrasp::reconstruction
