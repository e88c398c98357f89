#include "skelgrasp/pipeline/reconstruction_report.h"

#include "skelgrasp/common/json.h"

namespace skelgrasp::pipeline {

nlohmann::json reconstructionReport(const perception::Scan& scan,
                                    const ReconstructionParams& params,
                                    const ReconstructionResult& result,
                                    const std::vector<std::string>& mesh_files) {
  using nlohmann::json;
  const auto& ingest = result.ingest;
  json j;
  j["schema"] = "skelgrasp.reconstruction/1";
  j["status"] = skelgrasp::toJson(result.status);
  j.update(perception::toJson(scan, params.ingest, ingest));
  json objects = json::array();
  for (std::size_t k = 0; k < result.objects.size(); ++k) {
    objects.push_back(
        reconstruction::toJson(result.objects[k].meshing, params.meshing, result.objects[k].cluster,
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

}  // namespace skelgrasp::pipeline
