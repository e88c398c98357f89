#include "skelgrasp/pipeline/reconstruct_scan.h"

#include "skelgrasp/common/logging.h"

namespace skelgrasp::pipeline {

ReconstructionResult reconstructScan(const perception::Scan& scan,
                                     const ReconstructionParams& params) {
  Stopwatch total;
  // Fail fast, before filtering and segmentation: no object has more points than the scan (the
  // depth term dominates; meshObject checks again with the object's own points).
  checkPoissonMemory(scan.cloud.size(), params.meshing.poisson);
  ReconstructionResult result;
  result.ingest = perception::ingestScan(scan, params.ingest);
  if (!result.ingest.status.ok()) {
    result.status = result.ingest.status;
    result.total_s = total.seconds();
    return result;
  }
  const auto& scene = result.ingest.scene;
  for (std::size_t k = 0; k < result.ingest.objects.size(); ++k) {
    ObjectReconstruction object;
    object.cluster = scene.selected[k];
    object.meshing = meshObject(result.ingest.objects[k], scene.plane, params.meshing);
    if (!object.meshing.status.ok() && result.status.ok()) {
      result.status =
          Status::Make(object.meshing.status.code, "object " + std::to_string(object.cluster) +
                                                       ": " + object.meshing.status.message);
    }
    result.objects.push_back(std::move(object));
  }
  result.total_s = total.seconds();
  return result;
}

}  // namespace skelgrasp::pipeline
