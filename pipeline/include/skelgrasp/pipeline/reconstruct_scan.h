#pragma once
// The whole perception-to-mesh job behind `skelgrasp reconstruct`: ingest (filters, scene
// parsing, normals) and then meshing of every selected object.
#include <vector>

#include "skelgrasp/perception/ingest.h"
#include "skelgrasp/reconstruction/meshing.h"

namespace skelgrasp::pipeline {

struct ReconstructionParams {
  perception::IngestParams ingest;
  reconstruction::MeshingParams meshing;
};

struct ObjectReconstruction {
  std::size_t cluster = 0;  // index into ingest.scene.clusters
  reconstruction::MeshingResult meshing;
};

struct ReconstructionResult {
  // ok when every selected object was meshed; otherwise the first failure (ingest or meshing).
  Status status;
  perception::IngestResult ingest;
  std::vector<ObjectReconstruction> objects;
  double total_s = 0;
};

ReconstructionResult reconstructScan(const perception::Scan& scan,
                                     const ReconstructionParams& params = {});

// Ok, or the first meshing failure in object order, naming the object's cluster: the status of a
// reconstruction whose objects were meshed, whatever order they were meshed in.
Status meshingStatus(const std::vector<ObjectReconstruction>& objects);

// reconstructScan without the meshing: filters, segmentation and normals, with each selected
// object's cluster in `objects` and its meshing left empty (the caller meshes it with
// reconstruction::meshObject, e.g. while other objects are planned).
ReconstructionResult ingestObjects(const perception::Scan& scan,
                                   const ReconstructionParams& params = {});

}  // namespace skelgrasp::pipeline
