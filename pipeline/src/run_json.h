#pragma once
// Pieces of the run outputs (grasps.json schema skelgrasp.run/4, docs/pipeline.md, and the scan
// picture) shared by the one-target and the scene writers.
#include <nlohmann/json.hpp>

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "skelgrasp/pipeline/run_pipeline.h"
#include "skelgrasp/pipeline/run_scene.h"

namespace skelgrasp::pipeline::internal {

inline constexpr const char* kRunSchema = "skelgrasp.run/4";

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
  const grasping::PlanSummary* plan = nullptr;                // null: not planned
  const std::vector<BlockingObstacle>* blocked_by = nullptr;  // null: not a scene run
  double time_s = 0;
  const std::vector<StageTime>* stages = nullptr;  // null: no per-object stage times
};

// One entry of "objects": id, cluster, points, centroid, box, mesh, status, reason, grasp count,
// best rank score, "blocked_by" (scene runs), time, its stage times ("timing", null when unknown)
// and "planning" (the
// planner's summary of the object, as in skelgrasp.grasps without "kept"; null when the object was
// not planned).
nlohmann::json objectJson(const ObjectEntry& entry);

// The ranked grasps of one object for "grasps", each with its "object" id and global "id" from
// `first_id` on.
void appendGraspsJson(nlohmann::json& grasps, const std::vector<RankedGrasp>& ranked,
                      const grasping::HandModel& hand, std::size_t object_id, std::size_t first_id);

// "scene": frame, support plane, sensor origin, obstacle points and the occupancy file.
nlohmann::json sceneJson(const std::optional<Eigen::Vector4d>& plane, const perception::Scan& scan,
                         std::size_t obstacle_points,
                         const std::shared_ptr<grasping::SceneOccupancy>& occupancy);

// "timing": seconds per stage and total_s.
nlohmann::json timingJson(const std::vector<StageTime>& stages, double total_s);

// The scan from the sensor's side (its own colours or a flat blue), the support grey and the
// given clusters of `scene` in their colours, with a caption; nothing when no point is finite.
void renderScanPng(const std::string& path, const perception::Scan& scan,
                   const perception::SceneResult& scene,
                   const std::vector<std::pair<std::size_t, Rgb>>& coloured_clusters,
                   const std::string& caption);

}  // namespace skelgrasp::pipeline::internal
