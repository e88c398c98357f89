#include "skelgrasp/pipeline/run_scene.h"

#include "object_planning.h"
#include "scene_obstacles.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/perception/cloud_ops.h"

namespace skelgrasp::pipeline {
using namespace grasping;

std::size_t SceneRunResult::objectsWithGrasps() const {
  std::size_t n = 0;
  for (const auto& o : objects) n += !o.ranked.empty();
  return n;
}

namespace {

// Everything the sensor saw that a hand may hit: every object, the support (less its top, which
// the plane stands for), the clutter.
PointCloud sceneObstacles(const perception::SceneResult& scene,
                          const internal::ObstacleParts& parts) {
  PointCloud obstacles = parts.objects;  // unselected clusters
  perception::append(obstacles, parts.loose);
  for (std::size_t c : scene.selected) perception::append(obstacles, scene.clusters[c]);
  return obstacles;
}

// Plans one meshed object; the failure of any step is the object's status and reason.
// `loose`: the obstacle points in no cluster (internal::ObstacleParts); those at the object's
// foot are cleared from its map with its own points. `sensor_origin`: the scan's (the objects'
// error bounds).
void planSceneObject(SceneObjectRun& object, const HandModel& hand, const SceneOccupancy* scene_map,
                     const PointCloud& own_points, const PointCloud& loose,
                     const std::optional<SupportPlane>& plane, const Eigen::Vector3d& sensor_origin,
                     const RunParams& params) {
  Stopwatch total;
  Stopwatch watch;
  object.skeleton = internal::runSkeleton(object.mesh, params);
  object.stages.push_back({"skeleton", watch.seconds()});
  if (!object.skeleton->status.ok()) {
    object.status =
        Status::Make(object.skeleton->status.code, "skeleton: " + object.skeleton->status.message);
    object.reason = object_reason::kSkeletonFailed;
    object.total_s += total.seconds();
    return;
  }
  watch.restart();
  std::unique_ptr<SceneOccupancy> own_map;
  std::unique_ptr<SceneChecker> checker;
  if (params.scene_check) {
    if (scene_map != nullptr) {
      PointCloud own = own_points;
      perception::append(own, internal::splitByDistanceToMesh(
                                  loose, object.mesh, params.table_obstacles.target_foot_distance_m)
                                  .near);
      own_map = scene_map->withPointsCleared(own);
    }
    checker = std::make_unique<SceneChecker>(hand, own_map.get(), plane, params.approach);
  }
  object.stages.push_back({"occupancy", watch.seconds()});
  auto ranked = internal::planAndRank(hand, object.mesh, object.observed, sensor_origin,
                                      *object.skeleton, checker.get(), params);
  object.plan = std::move(ranked.plan);
  object.ranked = std::move(ranked.ranked);
  object.stages.push_back({"plan", ranked.plan_s});
  object.stages.push_back({"rank", ranked.rank_s});
  object.status = object.ranked.empty() ? object.plan.status : Status::Ok();
  if (object.ranked.empty()) object.reason = object_reason::kNoGrasp;
  object.total_s += total.seconds();
}

}  // namespace

SceneRunResult runScene(const perception::Scan& scan, const HandModel& hand,
                        const RunParams& params) {
  Stopwatch total;
  SceneRunResult out;
  auto stage = [&](const char* name, double seconds) { out.stages.push_back({name, seconds}); };

  out.reconstruction = internal::reconstructForRun(scan, params, out.stages);
  const auto& ingest = out.reconstruction.ingest;
  if (!ingest.status.ok() || out.reconstruction.objects.empty()) {
    out.status = ingest.status.ok() ? Status::Make(StatusCode::kNoResult, "no object selected")
                                    : ingest.status;
    out.total_s = total.seconds();
    return out;
  }
  const auto& scene = ingest.scene;
  std::optional<SupportPlane> support;
  if (scene.plane) {
    out.plane = Eigen::Vector4d(scene.plane->normal.x(), scene.plane->normal.y(),
                                scene.plane->normal.z(), scene.plane->d);
    support = SupportPlane{*out.plane};
  }

  for (std::size_t k = 0; k < out.reconstruction.objects.size(); ++k) {
    const auto& reconstruction = out.reconstruction.objects[k];
    SceneObjectRun object;
    object.id = k;
    object.cluster = reconstruction.cluster;
    object.info = scene.cluster_info[reconstruction.cluster];
    object.stages.push_back({"reconstruct", reconstruction.meshing.report.total_s});
    object.total_s = reconstruction.meshing.report.total_s;
    if (reconstruction.meshing.status.ok()) {
      object.mesh = reconstruction.meshing.mesh;
      object.observed = reconstruction.meshing.observed;
    } else {
      object.status = Status::Make(reconstruction.meshing.status.code,
                                   "meshing: " + reconstruction.meshing.status.message);
      object.reason = object_reason::kMeshingFailed;
    }
    out.objects.push_back(std::move(object));
  }

  // One map of the scene, covering every meshed object's workspace.
  Stopwatch watch;
  internal::ObstacleParts parts;
  if (params.scene_check) {
    parts = internal::obstacleParts(scene, out.plane, params);
    const PointCloud obstacles = sceneObstacles(scene, parts);
    out.obstacle_points = obstacles.size();
    SceneOccupancyParams occupancy = params.occupancy;
    AxisAlignedBox objects_box;
    for (const auto& o : out.objects) {
      if (o.mesh.empty()) continue;
      const AxisAlignedBox box = o.mesh.bounds();
      objects_box.extend(box.min);
      objects_box.extend(box.max);
    }
    if (occupancy.region.empty() && !objects_box.empty())
      occupancy.region = internal::workspaceAround(objects_box, params);
    out.occupancy = std::make_shared<SceneOccupancy>(obstacles, scan.cloud.sensor_origin, occupancy,
                                                     objects_box);
  }
  stage("occupancy", watch.seconds());

  for (auto& object : out.objects) {
    if (!object.reason.empty()) continue;  // not meshed
    log().info("run: object {} of {} ({} points)", object.id + 1, out.objects.size(),
               object.info.points);
    planSceneObject(object, hand, out.occupancy.get(), scene.clusters[object.cluster], parts.loose,
                    support, scan.cloud.sensor_origin, params);
  }
  const std::size_t with_grasps = out.objectsWithGrasps();
  out.status =
      with_grasps > 0 ? Status::Ok() : Status::Make(StatusCode::kNoResult, "no object got a grasp");
  out.total_s = total.seconds();
  log().info("run: {} of {} objects got grasps in {:.2f} s", with_grasps, out.objects.size(),
             out.total_s);
  return out;
}

}  // namespace skelgrasp::pipeline
