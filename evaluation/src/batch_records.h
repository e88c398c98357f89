#pragma once
// Internal: the typed records of a batch directory, one JSON line each: a run (runs.jsonl) and a
// kept grasp of a run (results.jsonl). Every writer and reader goes through these structs, so a
// missing or mistyped key is an error naming it, never a silent 0. docs/evaluation.md describes
// the keys; the JSON objects are written with their keys sorted (nlohmann::json's order).
#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>

#include "skelgrasp/evaluation/batch.h"

namespace skelgrasp::evaluation::internal {

// A record that does not have the expected keys: what from_json throws. The readers turn it into
// an IoError naming the file and the line.
class RecordError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class RunStatus {
  kOk,       // "ok": grasps were found
  kNoGrasp,  // "no_grasp": the planner ran and found none
  kError,    // "error": the object could not be evaluated (message in `error`)
};
const char* toString(RunStatus status);

// The physics judge's nominal executions of a run's first grasps (BatchParams::physics): judged,
// held, and the failed ones by the phase they failed in (physics::ExecutionPhase).
struct PhysicsMeasures {
  std::size_t judged = 0, holds = 0;
  std::size_t start_failures = 0, closing_failures = 0, disturbance_failures = 0;
  double cpu_s = 0;  // thread CPU time of the executions
};

// What a finished planner run measured (runs.jsonl keys of the same names).
struct RunMeasures {
  std::uint64_t seed = 0;  // of the planner and the robustness samples
  std::size_t hypotheses = 0, poses = 0, generated = 0, force_closure = 0;
  double force_closure_rate = 0;  // force_closure / generated (0 without generated grasps)
  std::size_t kept = 0;           // grasps written to results.jsonl
  std::size_t power = 0, precision = 0;
  std::map<std::string, std::size_t> rejections;  // by reason
  bool timed_out = false;
  double planning_s = 0;
  std::optional<double> ms_per_valid_grasp;  // none without force-closure grasps
  double regularise_s = 0, skeleton_s = 0;   // 0 for the surface planner
  std::size_t robustness_grasps = 0;         // kept grasps scored for robustness
  int robustness_samples = 0;                // perturbed poses per scored grasp
  double robustness_s = 0;
  std::optional<double> robustness_mean;  // none when no grasp was scored
  // Robust ranking (BatchParams::ranking): the returned grasps scored, the mean of their r (none
  // when ranking was off or no grasp was scored) and the ranking's time. Absent in records of a
  // skelgrasp before robust ranking: read as 0 / none.
  bool ranked = false;
  std::size_t ranked_grasps = 0;
  std::optional<double> ranked_r_mean;
  double ranking_s = 0;
  // The first grasp's r (the best) and how many scored grasps refinement for robustness moved.
  // Absent before that refinement existed: read as none / 0.
  std::optional<double> ranked_r_best;
  std::size_t ranked_refined = 0;
  // The scored grasps' perturbed executions added up: all of them, and the failed ones by cause
  // (robustness.h). Absent before the causes were recorded: read as 0 (and shown as unknown).
  std::size_t ranked_samples = 0;
  std::size_t ranked_start_collisions = 0, ranked_closing_failures = 0, ranked_no_force_closure = 0;
  // Force closure whose contacts could not carry the weight (the ranking's load check).
  std::size_t ranked_too_weak = 0;
  // What the refinement for robustness changed: the scored grasps' mean r before it (none when
  // ranked_r_mean is none) and its share of ranking_s. Absent in records of a skelgrasp that did
  // not record them: both read as none, and ranked_refinement_s says which records have them.
  std::optional<double> ranked_r_mean_unrefined;
  std::optional<double> ranked_refinement_s;
  // Only in batches run with the physics judge.
  std::optional<PhysicsMeasures> physics;
};

// One line of runs.jsonl: one object x hand x planner.
struct RunRecord {
  std::string object;  // the object's id in the batch
  std::string hand;
  ranking::Planner planner = ranking::Planner::kSkeleton;
  // FNV-1a of the object file's bytes; absent in records of a skelgrasp before content hashes.
  std::optional<std::string> object_hash;
  RunStatus status = RunStatus::kOk;
  std::string error;  // empty unless status is kError
  // Present unless status is kError (a failed run records only the fields above).
  std::optional<RunMeasures> measures;
};

// Robustness of one scored grasp.
struct GraspRobustness {
  double score = 0;          // r
  double low = 0, high = 0;  // 95 % Wilson interval of r
  int collisions = 0;        // perturbed poses that hit the object
};

// One line of results.jsonl: a kept grasp of a run.
struct GraspRecord {
  std::string object;
  std::string hand;
  ranking::Planner planner = ranking::Planner::kSkeleton;
  int grasp = -1;        // id in the run, best epsilon first
  std::string type;      // grasping::toString(GraspType)
  std::string strategy;  // "1a" ... "4" or "surface"
  double epsilon = 0;
  std::optional<double> volume;               // none when not computed
  double time_ms = 0;                         // the run's time per valid grasp
  std::optional<GraspRobustness> robustness;  // none when not scored
  // Whether the physics judge's nominal execution held; none when not judged.
  std::optional<bool> physics_holds;
};

// Key of a run: object id, hand, planner.
std::string runKey(const std::string& object, const std::string& hand, ranking::Planner planner);
std::string runKey(const RunRecord& run);
std::string runKey(const GraspRecord& grasp);

// JSON conversion (found by nlohmann through ADL). from_json throws RecordError naming the key
// that is missing or of the wrong type.
void to_json(nlohmann::json& j, const RunRecord& run);
void from_json(const nlohmann::json& j, RunRecord& run);
void to_json(nlohmann::json& j, const GraspRecord& grasp);
void from_json(const nlohmann::json& j, GraspRecord& grasp);

}  // namespace skelgrasp::evaluation::internal
