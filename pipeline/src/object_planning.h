#pragma once
// The per-object part of `run`, shared by runPipeline (one target) and runScene (every object):
// skeleton with the regularisation retry, skeleton planner with the scene check, ranking.
#include <optional>
#include <vector>

#include "skelgrasp/pipeline/run_pipeline.h"

namespace skelgrasp::pipeline::internal {

// The shared start of runPipeline and runScene: the occupancy's memory checked against the whole
// scan (fail fast: the obstacles are a part of it), then filters, segmentation, normals and, with
// mesh_objects, meshing (pipeline::ingestObjects without); the times go to `stages` as filter,
// segment and normals.
ReconstructionResult reconstructForRun(const perception::Scan& scan, const RunParams& params,
                                       std::vector<StageTime>& stages, bool mesh_objects = true);

// The skeleton of a reconstruction. Reconstructions are normally closed single-part manifolds
// already (params.skeleton skips the regularisation); when one is not, the regularisation's
// automatic mode fills its pinholes or wraps it.
skeleton::SkeletonResult runSkeleton(const TriangleMesh& mesh, const RunParams& params);

// The octree region around one object's mesh: its box grown by the hand's reach.
AxisAlignedBox workspaceAround(const AxisAlignedBox& mesh_box, const RunParams& params);

struct RankedPlan {
  grasping::PlanResult plan;            // summary; grasps moved into `ranked`
  std::vector<RankedGrasp> ranked;      // best first, ids 0..n-1
  double plan_s = 0;                    // the object's geometry and the planner
  double rank_s = 0;                    // observed contacts and robust ranking
  std::size_t robustness_scored = 0;    // grasps scored for robustness
  std::vector<double> surface_error_m;  // per vertex (params.surface_clearance; empty without)
};

// Plans on `mesh` with its `skeleton` (scene check by `checker` when not null) and ranks the
// grasps by robustness (params.robust_ranking) with the trust 1 - w + w x observed contact ratio
// (RunParams): ranking::planGrasps. With params.surface_clearance, open hands keep clear of the
// mesh's error bounds (the sensor at `sensor_origin`, the mesh's frame).
RankedPlan planAndRank(const grasping::HandModel& hand, const TriangleMesh& mesh,
                       const std::vector<std::uint8_t>& observed,
                       const Eigen::Vector3d& sensor_origin,
                       const skeleton::SkeletonResult& skeleton,
                       const grasping::SceneChecker* checker, const RunParams& params);

}  // namespace skelgrasp::pipeline::internal
