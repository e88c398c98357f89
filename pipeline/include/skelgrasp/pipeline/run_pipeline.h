#pragma once
// The product's main job (`skelgrasp run`): a scan of a table scene in, ranked collision-free
// grasps on one target object out. Stages: filters -> support plane and objects -> reconstruction
// (closed mesh, observed flags) -> skeleton -> skeleton planner with the scene's occupancy ->
// ranking. Everything is in the scan's frame, metres.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/grasping/planning/planners.h"
#include "skelgrasp/grasping/planning/scene.h"
#include "skelgrasp/perception/scan.h"
#include "skelgrasp/pipeline/reconstruct_scan.h"
#include "skelgrasp/ranking/robust_ranking.h"
#include "skelgrasp/reconstruction/surface_error.h"
#include "skelgrasp/skeleton/extraction.h"

namespace skelgrasp::pipeline {

// Where `run` departs from the stages' own defaults, visibly and in one place.
// Planning limits of one run: the first grasps found are ranked, not all the object has.
constexpr double kRunPlanningTimeoutS = 10;
constexpr std::size_t kRunMaxGrasps = 20;
// Reconstructions are closed single-part manifolds already: no second wrap (0.5 s saved). When one
// is not, runPipeline retries with the regularisation's automatic mode (pinholes filled, else
// wrapped).
// A scan's Poisson mesh has ~1 mm cells (3-15k vertices per object); the contraction's cost grows
// with the vertex count, so it runs on the mesh simplified to this many (docs/pipeline.md): the
// skeleton stage's own default since it became the default of every command.
constexpr std::size_t kRunMaxContractionVertices = skeleton::kDefaultContractionVertices;
inline skeleton::SkeletonParams runSkeletonParams() {
  skeleton::SkeletonParams params;
  params.regularisation.method = geometry::RegularisationMethod::kNone;
  params.regularisation.max_vertices = kRunMaxContractionVertices;
  return params;
}
inline grasping::SkeletonPlannerParams runPlannerParams() {
  grasping::SkeletonPlannerParams params;
  params.timeout_s = kRunPlanningTimeoutS;
  params.max_grasps = kRunMaxGrasps;
  return params;
}

// Which of the support plane's inliers become octree obstacles (docs/pipeline.md, "Scene check").
struct TableObstacleParams {
  // Points in no object cluster at most this high above the support plane (or below it) are the
  // table top the plane's half-space stands for: it is an obstacle everywhere below the plane, to
  // within SceneCheckParams::plane_tolerance_m. As octree cells (5 mm) they would stand up to a
  // cell above the table. Unset: that tolerance (2 mm; the cells of points higher up still keep
  // fingers a few millimetres off the table, where a single view's completed mesh is a guess).
  std::optional<double> surface_height_m;
  // Such points within this distance of the target's mesh (or inside it) are the target's foot:
  // the segmentation gives the table every point within its plane distance (10 mm), so a flat
  // object's lowest centimetre, and the mixed depth pixels at its outline, count as table. They
  // are no obstacle to the target's own grasps (they still are to its neighbours'). 0: kept.
  double target_foot_distance_m = 0.01;
};

struct RunParams {
  ReconstructionParams reconstruction;  // target: largest or nearest:x,y,z
  skeleton::SkeletonParams skeleton = runSkeletonParams();
  grasping::SkeletonPlannerParams planner = runPlannerParams();
  bool scene_check = true;  // occupancy octree and support plane
  grasping::SceneOccupancyParams occupancy;
  TableObstacleParams table_obstacles;
  // The octree covers the target's box grown by this much (hand size plus pre-grasp distance).
  double workspace_margin_m = 0.4;
  grasping::SceneCheckParams approach;
  // Trust of a grasp = 1 - w + w * observed contact ratio: a grasp whose contacts lie on surface
  // the sensor saw is trusted more than one on filled-in surface. Ranking score (robust ranking,
  // ranking/robust_ranking.h): r * trust for the grasps scored for robustness (the best
  // robust_ranking.top_k by screening, whose candidates are chosen by epsilon * trust), ranked
  // first; epsilon * trust for the others (all of
  // them with robust_ranking.enabled = false, the ranking before robustness).
  double observed_weight = 0.5;
  // Error bounds of the reconstruction (reconstruction/surface_error.h: 2 sigma of the sensor's
  // noise where observed, growing with the distance to the data where filled in) and the clearance
  // open hands keep from them: each hypothesis' hand is backed off along its approach by the
  // largest bound of the surface around its grasp centre (HypothesisParams::clearance), so that
  // a hand placed against a surface that is not quite there does not start inside the real object
  // (docs/pipeline.md, "Clearance from uncertain surface"). Unset: the mesh is taken as exact.
  std::optional<reconstruction::SurfaceErrorParams> surface_clearance =
      reconstruction::SurfaceErrorParams{};
  // The seed of r is robust_ranking.robustness.seed; the robustness is judged on the object alone
  // (the perturbed hand is not checked against the rest of the scene).
  ranking::RobustRankingParams robust_ranking;
  // runScene: objects planned at once (0 = one per core). The grasps do not depend on it: each
  // object is planned on its own, with its own seeds, and the results are kept in object order.
  int object_jobs = 0;
};

struct RankedGrasp {
  grasping::Grasp grasp;
  double observed_contact_ratio = 0;  // contacts on observed surface / contacts
  double score = 0;                   // the ranking score (RunParams::observed_weight)
};

struct StageTime {
  std::string stage;
  double seconds = 0;
};

struct RunResult {
  Status status;
  ReconstructionResult reconstruction;
  std::size_t cluster = 0;             // the target's index in reconstruction.ingest.scene.clusters
  TriangleMesh mesh;                   // the target's closed mesh
  std::vector<std::uint8_t> observed;  // per mesh vertex
  std::vector<double> surface_error_m;   // per mesh vertex: its error bound (empty: no clearance)
  std::optional<Eigen::Vector4d> plane;  // a x + b y + c z + d = 0, the object on the positive side
  PointCloud obstacles;                  // scene points that are not the target (octree input)
  std::shared_ptr<grasping::SceneOccupancy> occupancy;
  std::optional<skeleton::SkeletonResult> skeleton;
  grasping::PlanResult plan;        // summary; grasps moved into `ranked`
  std::vector<RankedGrasp> ranked;  // best first
  std::vector<StageTime> stages;
  double total_s = 0;
};

// Runs the pipeline on one target object. Data failures (no plane, no object, meshing or skeleton
// failure) are in the status, with the stage named; no grasps is kNoResult with the rejections.
// Throws InvalidArgument when the target mode asks for all objects.
RunResult runPipeline(const perception::Scan& scan, const grasping::HandModel& hand,
                      const RunParams& params = {});

}  // namespace skelgrasp::pipeline
