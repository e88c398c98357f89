#include "skelgrasp/perception/ingest.h"

#include "skelgrasp/common/logging.h"
#include "skelgrasp/perception/cloud_ops.h"

namespace skelgrasp::perception {

IngestResult ingestScan(const Scan& scan, const IngestParams& params) {
  Stopwatch total;
  IngestResult result;
  result.points_in = scan.cloud.size();
  const bool masked = !scan.object_mask.empty();
  if (masked && scan.object_mask.size() != scan.cloud.size()) {
    throw InvalidArgument("ingestScan: object mask and cloud sizes differ");
  }

  // With a mask, object and scene are filtered apart so the voxel grid never mixes them.
  Stopwatch watch;
  PointCloud filtered;
  std::vector<std::uint8_t> mask;
  if (masked) {
    std::vector<int> object_indices, scene_indices;
    for (std::size_t i = 0; i < scan.cloud.size(); ++i) {
      (scan.object_mask[i] ? object_indices : scene_indices).push_back(static_cast<int>(i));
    }
    const FilterResult object = filterCloud(subset(scan.cloud, object_indices), params.filters);
    for (auto s : object.steps) {
      s.name = "object/" + s.name;
      result.filter_steps.push_back(s);
    }
    if (!object.status.ok()) {
      result.status = Status::Make(object.status.code, "object mask: " + object.status.message);
      result.total_time_s = total.seconds();
      return result;
    }
    FilterResult scene;
    if (!scene_indices.empty()) {
      scene = filterCloud(subset(scan.cloud, scene_indices), params.filters);
      for (auto s : scene.steps) {
        s.name = "scene/" + s.name;
        result.filter_steps.push_back(s);
      }
    }
    filtered = object.cloud;
    mask.assign(object.cloud.size(), 1);
    if (scene.status.ok() && !scene.cloud.empty()) {
      append(filtered, scene.cloud);
      mask.resize(filtered.size(), 0);
    }
  } else {
    FilterResult all = filterCloud(scan.cloud, params.filters);
    result.filter_steps = all.steps;
    if (!all.status.ok()) {
      result.status = all.status;
      result.total_time_s = total.seconds();
      return result;
    }
    filtered = std::move(all.cloud);
  }
  filtered.sensor_origin = scan.cloud.sensor_origin;
  filtered.sensor_orientation = scan.cloud.sensor_orientation;
  result.points_filtered = filtered.size();
  result.filter_time_s = watch.seconds();

  watch.restart();
  result.scene = parseScene(filtered, params.scene, mask);
  result.scene_time_s = watch.seconds();
  if (!result.scene.status.ok()) {
    result.status = result.scene.status;
    result.total_time_s = total.seconds();
    return result;
  }

  watch.restart();
  for (std::size_t s : result.scene.selected) {
    const PointCloud& cluster = result.scene.clusters[s];
    if (scan.per_view_normals && cluster.hasNormals()) {
      result.objects.push_back(cluster);
      continue;
    }
    const NormalResult normals = estimateNormals(cluster, params.normals);
    if (!normals.status.ok()) {
      result.status = Status::Make(normals.status.code, "normals: " + normals.status.message);
      result.total_time_s = total.seconds();
      return result;
    }
    result.objects.push_back(normals.cloud);
  }
  result.normals_time_s = watch.seconds();
  result.total_time_s = total.seconds();
  log().info("ingest: {} -> {} filtered points, {} object(s) in {:.3f} s", result.points_in,
             result.points_filtered, result.objects.size(), result.total_time_s);
  return result;
}

}  // namespace skelgrasp::perception
