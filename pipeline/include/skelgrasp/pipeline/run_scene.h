#pragma once
// `skelgrasp run --object all`: every object of a table scene in one run. The scan is filtered
// and segmented once, every selected object is meshed, one occupancy map of the whole scene is
// built, and each object is planned against the table and all the other objects (its own points
// cleared from its copy of the map). One object's failure is recorded with a reason code and does
// not stop the others.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/pipeline/run_pipeline.h"

namespace skelgrasp::pipeline {

// Why an object of a scene run has no grasp (SceneObjectRun::reason).
namespace object_reason {
inline constexpr const char* kMeshingFailed = "meshing_failed";    // too small, too thin, noise
inline constexpr const char* kSkeletonFailed = "skeleton_failed";  // no usable skeleton
inline constexpr const char* kNoGrasp = "no_grasp";                // planned, nothing kept
// Planned, nothing kept, and wider at its narrowest across the support than any grasp of the hand
// (twice its largest lambda2): a flat box lying on the table offers no two faces it can reach.
inline constexpr const char* kTooWide = "too_wide";
}  // namespace object_reason

// One obstacle that blocked a hand's pose or approach (SceneObjectRun::blocked_by).
struct BlockingObstacle {
  // "table" (the support plane), "object" (another object of the scene, `object` its id) or
  // "clutter" (points in no object: the table's edge, fragments, whatever stands beside it).
  std::string obstacle;
  std::optional<std::size_t> object;
  std::size_t poses = 0;  // hand poses or approaches it blocked
};

struct SceneObjectRun {
  std::size_t id = 0;       // position in SceneRunResult::objects, the id in the outputs
  std::size_t cluster = 0;  // index into reconstruction.ingest.scene.clusters
  perception::ClusterInfo info;
  Status status;                       // ok when the object has at least one grasp
  std::string reason;                  // empty when ok, else one of object_reason
  TriangleMesh mesh;                   // closed reconstruction (empty when meshing failed)
  std::vector<std::uint8_t> observed;  // per mesh vertex
  std::optional<skeleton::SkeletonResult> skeleton;
  grasping::PlanResult plan;        // summary; grasps moved into `ranked`
  std::vector<RankedGrasp> ranked;  // best first, ids 0..n-1 within the object
  // What the scene check's rejected poses hit, most first (planned objects). An object without a
  // grasp whose poses the scene blocked says so in its status, naming these.
  std::vector<BlockingObstacle> blocked_by;
  std::vector<StageTime> stages;  // reconstruct, skeleton, occupancy, plan, rank
  double total_s = 0;
};

struct SceneRunResult {
  // ok when at least one object got a grasp; kNoResult when none did (each object says why), or
  // the ingest's failure (no plane, no object above it) with no objects.
  Status status;
  ReconstructionResult reconstruction;
  std::optional<Eigen::Vector4d> plane;  // a x + b y + c z + d = 0, objects on the positive side
  std::size_t obstacle_points = 0;       // scene points in the occupancy map
  std::shared_ptr<grasping::SceneOccupancy> occupancy;  // the whole scene, objects included
  std::vector<SceneObjectRun> objects;                  // in scene.selected order
  std::vector<StageTime> stages;                        // shared stages: filter ... occupancy
  double total_s = 0;

  std::size_t objectsWithGrasps() const;
};

// Runs every object that params.reconstruction.ingest.scene.target selects (normally kAll; the
// single-target modes give one object). Caller mistakes (bad parameters) throw.
SceneRunResult runScene(const perception::Scan& scan, const grasping::HandModel& hand,
                        const RunParams& params = {});

}  // namespace skelgrasp::pipeline
