// JSON of the ingest stage: the "input", "filters", "plane", "scene" and "clusters" members of
// report.json (`skelgrasp ingest` and `reconstruct`, docs/reconstruction.md).
#include "skelgrasp/common/json.h"
#include "skelgrasp/perception/ingest.h"

namespace skelgrasp::perception {
namespace {

nlohmann::json clusterJson(std::size_t index, const ClusterInfo& c) {
  return {{"index", index},
          {"points", c.points},
          {"centroid", skelgrasp::toJson(c.centroid)},
          {"box_min", skelgrasp::toJson(c.box.min)},
          {"box_max", skelgrasp::toJson(c.box.max)},
          {"extent_m", skelgrasp::toJson(c.extent)},
          {"height_above_plane_m", c.height_above_plane_m},
          {"selected", c.selected}};
}

}  // namespace

nlohmann::json toJson(const Scan& scan, const IngestParams& params, const IngestResult& ingest) {
  using nlohmann::json;
  const auto& scene = ingest.scene;
  json j;
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
  const auto& fp = params.filters;
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
  json dropped = json::array();
  for (const auto& d : scene.dropped) {
    dropped.push_back(
        {{"points", d.points}, {"centroid", skelgrasp::toJson(d.centroid)}, {"reason", d.reason}});
  }
  j["scene"] = {{"plane_requirement", toString(params.scene.plane)},
                {"target", params.scene.target.toString()},
                {"candidate_points", scene.candidate_points},
                {"other_points", scene.other_points.size()},
                {"cluster_tolerance_m", params.scene.cluster_tolerance_m},
                {"plane_hull_margin_m", params.scene.restrict_to_plane_hull
                                            ? json(params.scene.plane_hull_margin_m)
                                            : json(nullptr)},
                {"segmentation", toString(scene.segmentation)},
                {"merged_fragments", scene.merged_fragments},
                {"dropped", dropped}};
  json clusters = json::array();
  for (std::size_t i = 0; i < scene.cluster_info.size(); ++i) {
    clusters.push_back(clusterJson(i, scene.cluster_info[i]));
  }
  j["clusters"] = clusters;
  return j;
}

}  // namespace skelgrasp::perception
