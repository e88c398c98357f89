#include "skelgrasp/pipeline/run_pipeline.h"

#include "object_planning.h"
#include "scene_obstacles.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/perception/cloud_ops.h"

namespace skelgrasp::pipeline {
// The pipeline composes the grasping stage's types throughout.
using namespace grasping;

RunResult runPipeline(const perception::Scan& scan, const HandModel& hand,
                      const RunParams& params) {
  if (params.reconstruction.ingest.scene.target.mode == perception::TargetMode::kAll) {
    throw InvalidArgument("runPipeline plans for one object: use runScene for every object");
  }
  Stopwatch total;
  RunResult out;
  auto stage = [&](const char* name, double seconds) { out.stages.push_back({name, seconds}); };

  out.reconstruction = internal::reconstructForRun(scan, params, out.stages);
  const auto& ingest = out.reconstruction.ingest;
  if (!out.reconstruction.status.ok() || out.reconstruction.objects.empty()) {
    out.status = out.reconstruction.status.ok()
                     ? Status::Make(StatusCode::kNoResult, "no object selected")
                     : out.reconstruction.status;
    out.total_s = total.seconds();
    return out;
  }
  const auto& object = out.reconstruction.objects.front();
  out.cluster = object.cluster;
  out.mesh = object.meshing.mesh;
  out.observed = object.meshing.observed;
  stage("reconstruct", object.meshing.report.total_s);
  const auto& scene = ingest.scene;
  if (scene.plane)
    out.plane = Eigen::Vector4d(scene.plane->normal.x(), scene.plane->normal.y(),
                                scene.plane->normal.z(), scene.plane->d);

  Stopwatch watch;
  out.skeleton = internal::runSkeleton(out.mesh, params);
  stage("skeleton", watch.seconds());
  if (!out.skeleton->status.ok()) {
    out.status =
        Status::Make(out.skeleton->status.code, "skeleton: " + out.skeleton->status.message);
    out.total_s = total.seconds();
    return out;
  }

  // Obstacles: everything but the target — the table's inliers, other objects, clutter.
  watch.restart();
  std::unique_ptr<SceneChecker> checker;
  if (params.scene_check) {
    // Other objects whole; the table (less its top, which the plane stands for) and the loose
    // points, less the target's foot.
    internal::ObstacleParts parts = internal::obstacleParts(scene, out.plane, params);
    out.obstacles = std::move(parts.objects);
    perception::append(out.obstacles,
                       internal::splitByDistanceToMesh(
                           parts.loose, out.mesh, params.table_obstacles.target_foot_distance_m)
                           .far);
    SceneOccupancyParams occupancy = params.occupancy;
    if (occupancy.region.empty())
      occupancy.region = internal::workspaceAround(out.mesh.bounds(), params);
    out.occupancy = std::make_shared<SceneOccupancy>(out.obstacles, scan.cloud.sensor_origin,
                                                     occupancy, out.mesh.bounds());
    std::optional<SupportPlane> plane;
    if (out.plane) plane = SupportPlane{*out.plane};
    checker = std::make_unique<SceneChecker>(hand, out.occupancy.get(), plane, params.approach);
  }
  stage("occupancy", watch.seconds());

  auto ranked = internal::planAndRank(hand, out.mesh, out.observed, scan.cloud.sensor_origin,
                                      *out.skeleton, checker.get(), params);
  out.plan = std::move(ranked.plan);
  out.surface_error_m = std::move(ranked.surface_error_m);
  out.ranked = std::move(ranked.ranked);
  stage("plan", ranked.plan_s);
  stage("rank", ranked.rank_s);
  out.status = out.ranked.empty() ? out.plan.status : Status::Ok();
  out.total_s = total.seconds();
  log().info("run: {} grasps on the target in {:.2f} s", out.ranked.size(), out.total_s);
  return out;
}

}  // namespace skelgrasp::pipeline
