#include "object_planning.h"

#include <algorithm>

#include "skelgrasp/common/logging.h"
#include "skelgrasp/geometry/mesh_query.h"

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
                                       std::vector<StageTime>& stages) {
  if (params.scene_check)
    checkSceneOccupancyMemory(scan.cloud, scan.cloud.sensor_origin, params.occupancy);
  ReconstructionResult reconstruction = reconstructScan(scan, params.reconstruction);
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
                       const skeleton::Skeleton& skeleton, const SceneChecker* checker,
                       const RunParams& params) {
  RankedPlan out;
  Stopwatch watch;
  const GraspObject target(mesh);
  SkeletonPlannerParams planner = params.planner;
  planner.hypothesis.scene = checker;
  out.plan = planSkeletonGrasps(hand, target, skeleton, planner);
  out.plan_s = watch.seconds();

  watch.restart();
  // The planner's object already holds a query tree over this mesh (same faces).
  const auto& query = target.surfaceQuery();
  // How far a grasp's r is trusted: the share of its contacts on observed surface, weighted.
  const auto trustOf = [&](double ratio) {
    return 1 - params.observed_weight + params.observed_weight * ratio;
  };
  std::vector<double> ratios, trust;
  for (const auto& g : out.plan.grasps) {
    ratios.push_back(observedContactRatio(g, mesh, observed, query));
    trust.push_back(trustOf(ratios.back()));
  }
  // The planner's hypothesis parameters with the scene check: refinement for robustness places
  // the hand anew and must keep it clear of the scene as the planner did.
  auto ranking = evaluation::rankByRobustness(hand, target, std::move(out.plan.grasps),
                                              planner.hypothesis, params.robust_ranking, trust);
  out.plan.grasps.clear();
  out.robustness_scored = ranking.scored;
  for (std::size_t i = 0; i < ranking.grasps.size(); ++i) {
    RankedGrasp r;
    r.observed_contact_ratio = ratios[ranking.order[i]];
    r.score = ranking.scores[i];
    r.grasp = std::move(ranking.grasps[i]);
    const auto& robustness = r.grasp.robustness;
    if (robustness && robustness->refinement && robustness->refinement->refined) {
      // A moved grasp touches elsewhere: its trust is that of its own contacts.
      r.observed_contact_ratio = observedContactRatio(r.grasp, mesh, observed, query);
      r.score = robustness->r * trustOf(r.observed_contact_ratio);
    }
    out.ranked.push_back(std::move(r));
  }
  // The scored grasps lead, by score; a moved grasp's new trust can reorder them.
  const auto scored_end = std::find_if(out.ranked.begin(), out.ranked.end(),
                                       [](const RankedGrasp& r) { return !r.grasp.robustness; });
  std::stable_sort(out.ranked.begin(), scored_end,
                   [](const RankedGrasp& a, const RankedGrasp& b) { return a.score > b.score; });
  for (std::size_t i = 0; i < out.ranked.size(); ++i) out.ranked[i].grasp.id = static_cast<int>(i);
  out.rank_s = watch.seconds();
  return out;
}

}  // namespace skelgrasp::pipeline::internal
