#pragma once
// From a scan to object clouds: filters, scene parsing, normals. This is `skelgrasp ingest`; the
// reconstruction pipeline continues from its result.
#include <nlohmann/json.hpp>

#include <vector>

#include "skelgrasp/perception/filters.h"
#include "skelgrasp/perception/scan.h"
#include "skelgrasp/perception/scene.h"

namespace skelgrasp::perception {

struct IngestParams {
  FilterParams filters;
  SceneParams scene;
  NormalParams normals;
};

struct IngestResult {
  Status status;  // first failing stage's status, message prefixed with the stage
  // Filter steps; with an object mask, the object and the scene parts are filtered separately
  // (steps named "object/..." and "scene/...").
  std::vector<FilterStep> filter_steps;
  std::size_t points_in = 0;
  std::size_t points_filtered = 0;
  SceneResult scene;
  std::vector<PointCloud> objects;  // selected clusters with normals, in scene.selected order
  double filter_time_s = 0;
  double scene_time_s = 0;
  double normals_time_s = 0;
  double total_time_s = 0;
};

IngestResult ingestScan(const Scan& scan, const IngestParams& params = {});

// The ingest stage's members of report.json ("input", "filters", "plane", "scene", "clusters";
// docs/reconstruction.md).
nlohmann::json toJson(const Scan& scan, const IngestParams& params, const IngestResult& ingest);

}  // namespace skelgrasp::perception
