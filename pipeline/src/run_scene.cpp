#include "skelgrasp/pipeline/run_scene.h"

#include <map>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include "object_planning.h"
#include "scene_obstacles.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/geometry/principal_axes.h"
#include "skelgrasp/perception/cloud_ops.h"
#include "skelgrasp/reconstruction/meshing.h"

namespace skelgrasp::pipeline {
using namespace grasping;

std::size_t SceneRunResult::objectsWithGrasps() const {
  std::size_t n = 0;
  for (const auto& o : objects) n += !o.ranked.empty();
  return n;
}

namespace {

// The obstacles an object's no-grasp status names, most blocking first.
constexpr std::size_t kNamedObstacles = 3;

// Everything the sensor saw that a hand may hit: every object, the support (less its top, which
// the plane stands for), the clutter. Labelled for the scene check: the points of cluster c
// c + 1, the rest (parts.loose) 0.
PointCloud sceneObstacles(const perception::SceneResult& scene,
                          const internal::ObstacleParts& parts) {
  PointCloud obstacles;
  obstacles.sensor_origin = parts.loose.sensor_origin;
  for (std::size_t c = 0; c < scene.clusters.size(); ++c) {
    const auto& points = scene.clusters[c].points;
    obstacles.points.insert(obstacles.points.end(), points.begin(), points.end());
    obstacles.labels.resize(obstacles.points.size(), static_cast<std::uint32_t>(c + 1));
  }
  obstacles.points.insert(obstacles.points.end(), parts.loose.points.begin(),
                          parts.loose.points.end());
  obstacles.labels.resize(obstacles.points.size(), 0);
  return obstacles;
}

// What blocked an object's rejected poses, named: the support plane is the table, octree label
// c + 1 the object of cluster c (sceneObstacles), label 0 clutter.
std::vector<BlockingObstacle> blockingObstacles(const grasping::PlanSummary& summary,
                                                const std::vector<SceneObjectRun>& objects) {
  std::map<std::optional<std::size_t>, std::size_t> by_object;  // nullopt: clutter
  for (const auto& [label, poses] : summary.scene_collision_labels) {
    std::optional<std::size_t> object;
    for (const auto& o : objects) {
      if (label != 0 && o.cluster == label - 1) object = o.id;
    }
    by_object[object] += poses;
  }
  std::vector<BlockingObstacle> out;
  for (const auto& [object, poses] : by_object)
    out.push_back({object ? "object" : "clutter", object, poses});
  const auto table = summary.scene_collision_obstacles.find("support_plane");
  if (table != summary.scene_collision_obstacles.end()) out.push_back({"table", {}, table->second});
  std::stable_sort(out.begin(), out.end(),
                   [](const auto& a, const auto& b) { return a.poses > b.poses; });
  return out;
}

std::string describe(const BlockingObstacle& b) {
  return b.obstacle == "object" ? "object " + std::to_string(*b.object) : b.obstacle;
}

// The widest object a hand closes around: twice the largest lambda2 its grasp types accept.
double widestGrasp(const HandModel& hand) {
  double lambda2 = 0;
  for (const auto& limits : {hand.thresholds().precision, hand.thresholds().power}) {
    if (limits) lambda2 = std::max(lambda2, limits->lambda2_max_m);
  }
  return 2 * lambda2;
}

// An object without a grasp: its status says whether it is wider than the hand's grasps
// (reason too_wide) and names what the scene blocked.
void explainNoGrasp(SceneObjectRun& object, const HandModel& hand,
                    const std::optional<SupportPlane>& plane) {
  std::string why;
  if (plane) {
    const double width =
        geometry::footprintExtents(object.mesh.vertices, plane->coefficients.head<3>().normalized())
            .narrowest_m;
    const double widest = widestGrasp(hand);
    if (width > widest) {
      object.reason = object_reason::kTooWide;
      why = fmt::format(
          "{:.2f} m wide at its narrowest across the table, the {} closes around at "
          "most {:.2f} m",
          width, hand.name(), widest);
    }
  }
  const auto& summary = object.plan.summary;
  const auto blocked = summary.rejections.find(grasping::reason::kSceneCollision);
  if (!object.blocked_by.empty() && blocked != summary.rejections.end()) {
    std::string names;
    for (std::size_t k = 0; k < object.blocked_by.size() && k < kNamedObstacles; ++k) {
      names += (k ? ", " : "") + describe(object.blocked_by[k]) + " " +
               std::to_string(object.blocked_by[k].poses);
    }
    why += fmt::format("{}the scene blocked {} of {} hand poses ({})", why.empty() ? "" : "; ",
                       blocked->second, summary.poses, names);
  }
  if (why.empty()) return;
  object.status = Status::Make(
      object.status.code, "no grasp: " + why + "; the other rejections are in planning.rejections");
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
      // The copy holds the object's workspace only (RunParams::workspace_margin_m: no hand
      // reaches beyond it), so that each object of a large scene copies its surroundings.
      own_map = scene_map->withPointsCleared(
          own, 1, internal::workspaceAround(object.mesh.bounds(), params));
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

  if (params.object_jobs < 0) throw InvalidArgument("runScene: object_jobs must be >= 0");
  // The scene is parsed and mapped once; then each object is meshed and planned as one task, in an
  // arena of params.object_jobs threads that the stages' own parallel loops share. Poisson runs
  // one object at a time (reconstruction::meshObject), the planning of others goes on meanwhile.
  tbb::task_arena arena(params.object_jobs == 0 ? tbb::task_arena::automatic : params.object_jobs);
  arena.execute(
      [&] { out.reconstruction = internal::reconstructForRun(scan, params, out.stages, false); });
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
  AxisAlignedBox objects_box;  // of the objects' points; their meshes close what those show
  for (std::size_t k = 0; k < out.reconstruction.objects.size(); ++k) {
    SceneObjectRun object;
    object.id = k;
    object.cluster = out.reconstruction.objects[k].cluster;
    object.info = scene.cluster_info[object.cluster];
    for (const auto& p : scene.clusters[object.cluster].points) objects_box.extend(p);
    out.objects.push_back(std::move(object));
  }

  // One map of the scene, covering every object's workspace.
  Stopwatch watch;
  internal::ObstacleParts parts;
  if (params.scene_check) {
    parts = internal::obstacleParts(scene, out.plane, params);
    const PointCloud obstacles = sceneObstacles(scene, parts);
    out.obstacle_points = obstacles.size();
    SceneOccupancyParams occupancy = params.occupancy;
    if (occupancy.region.empty() && !objects_box.empty())
      occupancy.region = internal::workspaceAround(objects_box, params);
    out.occupancy = std::make_shared<SceneOccupancy>(obstacles, scan.cloud.sensor_origin, occupancy,
                                                     objects_box);
  }
  stage("occupancy", watch.seconds());

  // The largest objects first, as the objects are ordered.
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, out.objects.size(), 1),
        [&](const tbb::blocked_range<std::size_t>& range) {
          for (std::size_t k = range.begin(); k != range.end(); ++k) {
            SceneObjectRun& object = out.objects[k];
            auto& meshing = out.reconstruction.objects[k].meshing;
            meshing = reconstruction::meshObject(ingest.objects[k], scene.plane,
                                                 params.reconstruction.meshing);
            object.stages.push_back({"reconstruct", meshing.report.total_s});
            object.total_s = meshing.report.total_s;
            if (!meshing.status.ok()) {
              object.status =
                  Status::Make(meshing.status.code, "meshing: " + meshing.status.message);
              object.reason = object_reason::kMeshingFailed;
              continue;
            }
            object.mesh = meshing.mesh;
            object.observed = meshing.observed;
            log().info("run: object {} of {} ({} points)", object.id + 1, out.objects.size(),
                       object.info.points);
            planSceneObject(object, hand, out.occupancy.get(), scene.clusters[object.cluster],
                            parts.loose, support, scan.cloud.sensor_origin, params);
            object.blocked_by = blockingObstacles(object.plan.summary, out.objects);
            if (object.ranked.empty()) explainNoGrasp(object, hand, support);
          }
        },
        tbb::simple_partitioner());
  });
  out.reconstruction.status = meshingStatus(out.reconstruction.objects);
  const std::size_t with_grasps = out.objectsWithGrasps();
  out.status =
      with_grasps > 0 ? Status::Ok() : Status::Make(StatusCode::kNoResult, "no object got a grasp");
  out.total_s = total.seconds();
  log().info("run: {} of {} objects got grasps in {:.2f} s", with_grasps, out.objects.size(),
             out.total_s);
  return out;
}

}  // namespace skelgrasp::pipeline
