#include "skelgrasp/pipeline/run_pipeline.h"

#include "skelgrasp/common/logging.h"
#include "skelgrasp/geometry/mesh_query.h"
#include "skelgrasp/perception/cloud_ops.h"

namespace skelgrasp::pipeline {
// The pipeline composes the grasping stage's types throughout.
using namespace grasping;

namespace {

// Share of the contacts lying on observed surface: a contact counts when at least two vertices of
// the face it lies on were observed.
double observedContactRatio(const Grasp& grasp, const TriangleMesh& mesh,
                            const std::vector<std::uint8_t>& observed,
                            const geometry::MeshQuery& query) {
  if (grasp.contacts.empty() || observed.size() != mesh.numVertices()) return 0;
  std::size_t on_observed = 0;
  for (const auto& c : grasp.contacts) {
    const auto face = mesh.faces[query.closestPointAndFace(c.point).second];
    on_observed += observed[face[0]] + observed[face[1]] + observed[face[2]] >= 2;
  }
  return static_cast<double>(on_observed) / grasp.contacts.size();
}

}  // namespace

RunResult runPipeline(const perception::Scan& scan, const HandModel& hand,
                      const RunParams& params) {
  if (params.reconstruction.ingest.scene.target.mode == perception::TargetMode::kAll) {
    throw InvalidArgument(
        "run plans for one object at a time: use --object largest or nearest:x,y,z");
  }
  // Fail fast, before reconstruction: the obstacles are a part of the scan, so the whole scan
  // bounds the occupancy's memory (the constructor checks again with the obstacles themselves).
  if (params.scene_check)
    checkSceneOccupancyMemory(scan.cloud, scan.cloud.sensor_origin, params.occupancy);
  Stopwatch total;
  RunResult out;
  auto stage = [&](const char* name, double seconds) { out.stages.push_back({name, seconds}); };

  out.reconstruction = pipeline::reconstructScan(scan, params.reconstruction);
  const auto& ingest = out.reconstruction.ingest;
  stage("filter", ingest.filter_time_s);
  stage("segment", ingest.scene_time_s);
  stage("normals", ingest.normals_time_s);
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
  out.skeleton = skeleton::extractSkeleton(out.mesh, params.skeleton);
  if (out.skeleton->status.code == StatusCode::kInvalidInput &&
      params.skeleton.regularisation.method == geometry::RegularisationMethod::kNone) {
    // The reconstruction is normally a closed single-part manifold already; if not, the
    // regularisation's automatic mode fills its pinholes or wraps it.
    skeleton::SkeletonParams regularised = params.skeleton;
    regularised.regularisation.method = geometry::RegularisationMethod::kAuto;
    out.skeleton = skeleton::extractSkeleton(out.mesh, regularised);
  }
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
    out.obstacles = scene.other_points;  // other objects and clutter already
    perception::append(out.obstacles, scene.plane_points);
    SceneOccupancyParams occupancy = params.occupancy;
    if (occupancy.region.empty()) {
      const AxisAlignedBox box = out.mesh.bounds();
      occupancy.region.extend(box.min.array() - params.workspace_margin_m);
      occupancy.region.extend(box.max.array() + params.workspace_margin_m);
    }
    out.occupancy = std::make_shared<SceneOccupancy>(out.obstacles, scan.cloud.sensor_origin,
                                                     occupancy, out.mesh.bounds());
    std::optional<SupportPlane> plane;
    if (out.plane) plane = SupportPlane{*out.plane};
    checker = std::make_unique<SceneChecker>(hand, out.occupancy.get(), plane, params.approach);
  }
  stage("occupancy", watch.seconds());

  watch.restart();
  const GraspObject target(out.mesh);
  SkeletonPlannerParams planner = params.planner;
  planner.hypothesis.scene = checker.get();
  out.plan = planSkeletonGrasps(hand, target, out.skeleton->skeleton, planner);
  stage("plan", watch.seconds());

  watch.restart();
  // The planner's object already holds a query tree over this mesh (same faces).
  const auto& query = target.surfaceQuery();
  for (auto& g : out.plan.grasps) {
    RankedGrasp r;
    r.observed_contact_ratio = observedContactRatio(g, out.mesh, out.observed, query);
    r.score = g.epsilon *
              (1 - params.observed_weight + params.observed_weight * r.observed_contact_ratio);
    r.grasp = std::move(g);
    out.ranked.push_back(std::move(r));
  }
  out.plan.grasps.clear();
  std::stable_sort(out.ranked.begin(), out.ranked.end(),
                   [](const auto& a, const auto& b) { return a.score > b.score; });
  for (std::size_t i = 0; i < out.ranked.size(); ++i) out.ranked[i].grasp.id = static_cast<int>(i);
  stage("rank", watch.seconds());
  out.status = out.ranked.empty() ? out.plan.status : Status::Ok();
  out.total_s = total.seconds();
  log().info("run: {} grasps on the target in {:.2f} s", out.ranked.size(), out.total_s);
  return out;
}

}  // namespace skelgrasp::pipeline
