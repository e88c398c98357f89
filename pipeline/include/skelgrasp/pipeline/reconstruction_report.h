#pragma once
// report.json of `skelgrasp reconstruct` and `ingest`: the ingest stage's members
// (perception/ingest.h) and one meshing entry per object (reconstruction/meshing.h).
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "skelgrasp/pipeline/reconstruct_scan.h"

namespace skelgrasp::pipeline {

// report.json (schema "skelgrasp.reconstruction/1", documented in docs/reconstruction.md).
// `mesh_files` names the written mesh of each object (parallel to result.objects; may be empty).
nlohmann::json reconstructionReport(const perception::Scan& scan,
                                    const ReconstructionParams& params,
                                    const ReconstructionResult& result,
                                    const std::vector<std::string>& mesh_files = {});

}  // namespace skelgrasp::pipeline
