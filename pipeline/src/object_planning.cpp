#include "object_planning.h"

#include "skelgrasp/common/logging.h"
#include "skelgrasp/geometry/mesh_query.h"
#include "skelgrasp/ranking/plan_grasps.h"
#include "skelgrasp/reconstruction/surface_error.h"

namespace skelgrasp::pipeline::internal {
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

ReconstructionResult reconstructForRun(const perception::Scan& scan, const RunParams& params,
                                       std::vector<StageTime>& stages, bool mesh_objects) {
  if (params.scene_check)
    checkSceneOccupancyMemory(scan.cloud, scan.cloud.sensor_origin, params.occupancy);
  ReconstructionResult reconstruction = mesh_objects ? reconstructScan(scan, params.reconstruction)
                                                     : ingestObjects(scan, params.reconstruction);
  const auto& ingest = reconstruction.ingest;
  stages.push_back({"filter", ingest.filter_time_s});
  stages.push_back({"segment", ingest.scene_time_s});
  stages.push_back({"normals", ingest.normals_time_s});
  return reconstruction;
}

skeleton::SkeletonResult runSkeleton(const TriangleMesh& mesh, const RunParams& params) {
  skeleton::SkeletonResult result = skeleton::extractSkeleton(mesh, params.skeleton);
  if (result.status.code == StatusCode::kInvalidInput &&
      params.skeleton.regularisation.method == geometry::RegularisationMethod::kNone) {
    skeleton::SkeletonParams regularised = params.skeleton;
    regularised.regularisation.method = geometry::RegularisationMethod::kAuto;
    // A Poisson surface of any size: its ~1 mm cells are fine enough for the contraction even where
    // a small object has fewer vertices than the skeleton stage's floor for using a mesh as it is.
    regularised.regularisation.auto_min_vertices = std::nullopt;
    result = skeleton::extractSkeleton(mesh, regularised);
  }
  return result;
}

AxisAlignedBox workspaceAround(const AxisAlignedBox& mesh_box, const RunParams& params) {
  AxisAlignedBox region;
  region.extend(mesh_box.min.array() - params.workspace_margin_m);
  region.extend(mesh_box.max.array() + params.workspace_margin_m);
  return region;
}

RankedPlan planAndRank(const HandModel& hand, const TriangleMesh& mesh,
                       const std::vector<std::uint8_t>& observed,
                       const Eigen::Vector3d& sensor_origin,
                       const skeleton::SkeletonResult& skeleton, const SceneChecker* checker,
                       const RunParams& params) {
  const Stopwatch watch;
  const GraspObject target(mesh);
  ranking::PlanOptions options;
  options.planner = ranking::Planner::kSkeleton;
  // The scene check in the planner's hypothesis parameters: the ranking judges r with them, and
  // refinement for robustness places the hand anew and must keep it clear of the scene as the
  // planner did.
  options.skeleton_planner = params.planner;
  options.skeleton_planner.hypothesis.scene = checker;
  // The clearance likewise: refinement for robustness backs its hands off as the planner did.
  std::vector<double> surface_error;
  if (params.surface_clearance) {
    auto bounds = reconstruction::surfaceErrorBounds(mesh, observed, sensor_origin,
                                                     *params.surface_clearance);
    if (bounds.status.code != StatusCode::kInvalidInput) {
      surface_error = std::move(bounds.bound_m);
      const auto clearance = std::make_shared<const reconstruction::SurfaceClearance>(
          mesh, surface_error, *params.surface_clearance);
      options.skeleton_planner.hypothesis.clearance = [clearance](const Eigen::Vector3d& gcp) {
        return clearance->at(gcp);
      };
    } else {
      log().warn("run: no clearance from the surface's error bounds: {}", bounds.status.message);
    }
  }
  options.ranking = params.robust_ranking;
  // How far a grasp's r is trusted: the share of its contacts on observed surface, weighted. The
  // planner's object already holds a query tree over this mesh (same faces).
  const auto& query = target.surfaceQuery();
  const auto ratioOf = [&](const Grasp& grasp) {
    return observedContactRatio(grasp, mesh, observed, query);
  };
  ranking::PlanInputs inputs;
  inputs.skeleton = &skeleton;
  inputs.trust = [&](const Grasp& grasp) {
    return 1 - params.observed_weight + params.observed_weight * ratioOf(grasp);
  };
  ranking::GraspPlan plan = ranking::planGrasps(target, hand, options, inputs);

  RankedPlan out;
  out.robustness_scored = plan.ranking.scored;
  out.surface_error_m = std::move(surface_error);
  for (std::size_t i = 0; i < plan.grasps.size(); ++i) {
    RankedGrasp r;
    r.observed_contact_ratio = ratioOf(plan.grasps[i]);
    r.score = plan.ranking.scores[i];
    r.grasp = std::move(plan.grasps[i]);
    out.ranked.push_back(std::move(r));
  }
  plan.grasps.clear();
  out.rank_s = plan.timing.ranking_s;
  out.plan_s = watch.seconds() - out.rank_s;
  out.plan = std::move(static_cast<grasping::PlanResult&>(plan));
  return out;
}

}  // namespace skelgrasp::pipeline::internal
