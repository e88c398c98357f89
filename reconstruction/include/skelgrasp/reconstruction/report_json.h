#pragma once
// JSON forms of the reconstruction stages' reports.
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "skelgrasp/geometry/regularisation.h"
#include "skelgrasp/reconstruction/pipeline.h"

namespace skelgrasp::reconstruction {

// report.json (schema "skelgrasp.reconstruction/1", documented in docs/reconstruction.md).
// `mesh_files` names the written mesh of each object (parallel to result.objects; may be empty).
nlohmann::json reconstructionReport(const perception::Scan& scan,
                                    const ReconstructionParams& params,
                                    const ReconstructionResult& result,
                                    const std::vector<std::string>& mesh_files = {});

}  // namespace skelgrasp::reconstruction
