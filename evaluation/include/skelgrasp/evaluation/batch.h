#pragma once
// Batch evaluation: every object x hand x planner, robustness of the planned grasps, the paper's
// table and histograms. Resumable, shardable, parallel (TBB). File formats: docs/evaluation.md.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/grasping/planning/planners.h"
#include "skelgrasp/ranking/plan_grasps.h"
#include "skelgrasp/ranking/robust_ranking.h"
#include "skelgrasp/ranking/robustness.h"
#include "skelgrasp/skeleton/extraction.h"

namespace skelgrasp::evaluation {

// The physics judge in a batch (`evaluate --judge physics`, docs/physics.md): the first `grasps`
// grasps of every run, in the order the run returns them (ranked, with BatchParams::ranking),
// executed nominally by the rigid-body simulation at the batch's friction.
struct PhysicsJudging {
  std::size_t grasps = 10;  // >= 1
  double mass_kg = 0.1;     // the object's mass (kg, > 0): physics::kDefaultObjectMassKg
};

struct BatchParams {
  std::vector<std::string> objects;  // mesh files
  // Only the first this many objects (0: all). Their ids stay those of the whole list, so a later
  // batch over all of it resumes them.
  std::size_t object_limit = 0;
  std::vector<std::string> hands = {"armar3", "sdh", "shadow"};  // built-in hand names
  std::vector<ranking::Planner> planners = {ranking::Planner::kSkeleton,
                                            ranking::Planner::kSurface};
  std::string out_dir = "evaluation";
  int jobs = 1;                          // objects evaluated in parallel
  int shard_index = 0, shard_count = 1;  // this process runs objects k with k % count == index
  double timeout_s = 30;                 // per planner run
  double vertex_distance_m = 0;          // skeleton planner d
  // Skeleton planner: power grasps about the centre on every object (SkeletonPlannerParams).
  bool centre_candidates = grasping::SkeletonPlannerParams{}.centre_candidates;
  // Skeleton planner: also close the hands' alternative preshapes (the SDH's tripods;
  // SkeletonPlannerParams).
  bool alternative_preshapes = grasping::SkeletonPlannerParams{}.alternative_preshapes;
  // Skeleton planner: surface-normal hypotheses added to the pool (SkeletonPlannerParams).
  std::size_t surface_candidates = grasping::SkeletonPlannerParams{}.surface_candidates;
  // Used when no skeleton run gives the pose count.
  std::size_t surface_hypotheses = grasping::SurfacePlannerParams{}.max_hypotheses;
  // Robustness for up to this many grasps per run, drawn uniformly (seeded) from the kept grasps;
  // 0 = all of them.
  std::size_t robustness_grasps = 20;
  ranking::RobustnessParams robustness;  // samples (100), variant
  // The grasps a user of `plan` gets: each run's grasps ranked by robustness as `plan` ranks them
  // (robust_ranking.h; its samples, variant and seed as set here, the run's seed, friction and
  // closing), and the mean r of the top_k returned grasps recorded per run. Off by default:
  // the paper's protocol scores a random sample of the planner's grasps (above) and nothing else.
  ranking::RobustRankingParams ranking = [] {
    ranking::RobustRankingParams p;
    p.enabled = false;
    return p;
  }();
  // Unset: the model's figures only.
  std::optional<PhysicsJudging> physics;
  grasping::QualityParams quality;  // mu, reference_compat
  skeleton::SkeletonParams skeleton;
  MeshLoadOptions load;
  std::uint64_t seed = 1;
  // Stop after this many newly evaluated objects (0: no limit); lets tests interrupt a batch.
  std::size_t max_objects = 0;
  // Discard out_dir's runs (and its recorded options) and start afresh; without it, a resume with
  // options other than the recorded ones is refused.
  bool restart = false;
  // Evaluate again the objects with a run recorded as failed, replacing all their runs.
  bool retry_failed = false;
};

struct BatchStats {
  std::size_t objects_total = 0;    // in this shard
  std::size_t objects_skipped = 0;  // already finished in out_dir (resumed)
  std::size_t objects_run = 0;
  std::size_t objects_retried = 0;  // of objects_run: had a failed run (retry_failed)
  std::size_t objects_changed = 0;  // of objects_run: file changed since its runs were recorded
  std::size_t runs_failed = 0;
  double time_s = 0;
};

// Runs are keyed on (object id, hand, planner): the id is the object's path relative to the
// deepest directory holding the whole list (unique within the batch; its file name when they
// share one folder), and each run records a hash of the file's bytes. A run is done when out_dir
// holds it with the same content hash; seeds derive from (seed, id, hand, planner).
//
// Before any work, throws InvalidArgument for bad batch options (unknown hand, shard out
// of range, non-finite or negative numbers) or for a resume whose result-shaping options differ
// from out_dir/batch.json (naming them), and IoError when out_dir cannot be written or another
// process holds its lock. After that, every error of an object (unloadable file, a stage throwing
// for it) is recorded as a failed run with its message and the batch goes on.
BatchStats runBatch(const BatchParams& params);

// Rewrites summary.md, summary.csv and the robustness histograms (one PNG per hand) of out_dir
// from its runs.jsonl and results.jsonl.
void writeSummary(const std::string& out_dir);

// Joins the runs.jsonl and results.jsonl of shard directories into out_dir (duplicates of a run
// are kept once) and writes its batch.json and summary. Throws IoError for a missing or malformed
// input or a shard still being written (locked), InvalidArgument for shards run with different
// options.
void mergeBatches(const std::vector<std::string>& shard_dirs, const std::string& out_dir);

}  // namespace skelgrasp::evaluation
