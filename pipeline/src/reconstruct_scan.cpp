#include "skelgrasp/pipeline/reconstruct_scan.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include "skelgrasp/common/logging.h"

namespace skelgrasp::pipeline {

Status meshingStatus(const std::vector<ObjectReconstruction>& objects) {
  for (const auto& object : objects) {
    if (!object.meshing.status.ok())
      return Status::Make(object.meshing.status.code, "object " + std::to_string(object.cluster) +
                                                          ": " + object.meshing.status.message);
  }
  return Status::Ok();
}

ReconstructionResult ingestObjects(const perception::Scan& scan,
                                   const ReconstructionParams& params) {
  Stopwatch total;
  // Fail fast, before filtering and segmentation: no object has more points than the scan (the
  // depth term dominates; meshObject checks again with the object's own points).
  checkPoissonMemory(scan.cloud.size(), params.meshing.poisson);
  ReconstructionResult result;
  result.ingest = perception::ingestScan(scan, params.ingest);
  if (!result.ingest.status.ok()) {
    result.status = result.ingest.status;
  } else {
    result.objects.resize(result.ingest.objects.size());
    for (std::size_t k = 0; k < result.objects.size(); ++k)
      result.objects[k].cluster = result.ingest.scene.selected[k];
  }
  result.total_s = total.seconds();
  return result;
}

ReconstructionResult reconstructScan(const perception::Scan& scan,
                                     const ReconstructionParams& params) {
  Stopwatch total;
  ReconstructionResult result = ingestObjects(scan, params);
  if (!result.status.ok()) {
    result.total_s = total.seconds();
    return result;
  }
  const auto& scene = result.ingest.scene;
  // Objects meshed in the caller's task arena (Poisson itself one at a time); the status names
  // the first failure in object order, whatever the thread count.
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, result.objects.size(), 1),
      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t k = range.begin(); k != range.end(); ++k) {
          result.objects[k].meshing =
              meshObject(result.ingest.objects[k], scene.plane, params.meshing);
        }
      },
      tbb::simple_partitioner());
  result.status = meshingStatus(result.objects);
  result.total_s = total.seconds();
  return result;
}

}  // namespace skelgrasp::pipeline
