#pragma once
// Pieces of grasps.json (schema skelgrasp.run/2, docs/pipeline.md) shared by the one-target and
// the scene writers.
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "skelgrasp/pipeline/run_pipeline.h"

namespace skelgrasp::pipeline::internal {

inline constexpr const char* kRunSchema = "skelgrasp.run/2";

struct ObjectEntry {
  std::size_t id = 0;
  std::size_t cluster = 0;
  const perception::ClusterInfo* info = nullptr;  // null: unknown cluster
  std::string mesh_file;                          // empty: no mesh written
  std::size_t mesh_vertices = 0;
  double observed_fraction = 0;
  const Status* status = nullptr;
  std::string reason;  // empty when the object has grasps
  const std::vector<RankedGrasp>* ranked = nullptr;
  double time_s = 0;
};

// One entry of "objects": id, cluster, points, centroid, box, mesh, status, reason, grasp count,
// best rank score, time.
nlohmann::json objectJson(const ObjectEntry& entry);

// The ranked grasps of one object for "grasps", each with its "object" id and global "id" from
// `first_id` on.
void appendGraspsJson(nlohmann::json& grasps, const std::vector<RankedGrasp>& ranked,
                      const grasping::HandModel& hand, std::size_t object_id, std::size_t first_id);

}  // namespace skelgrasp::pipeline::internal
