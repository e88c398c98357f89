#pragma once
// Grasps planned on a scan, judged on the object's TRUE mesh (`skelgrasp bench scan2grasp`,
// docs/scan2grasp.md): each grasp, mapped into the mesh's frame, is re-scored with the model
// (scoreGrasps: closing, force closure, robustness r) and executed by the physics judge
// (simulateGrasps); the figures compare what the run claimed with what the true object gives.
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/evaluation/score.h"
#include "skelgrasp/evaluation/simulate.h"

namespace skelgrasp::evaluation {

// A grasp as a run returned it, in the true mesh's frame.
struct ClaimedGrasp {
  grasping::GraspPlacement placement;  // hand pose in the true mesh's frame
  std::optional<double> claimed_r;     // the run's r (unset: not scored by the ranking)
  double observed_contact_ratio = 0;   // the run's share of contacts on observed surface
};

struct TrueObjectParams {
  // The model's judge on the true mesh: by default the run's own criterion (settled variant, mu
  // 0.35, the ranking's load check), 100 samples, seed 1.
  ScoreParams score = defaultScore();
  // The physics judge (when the caller gives a physical object), nominal executions by default
  // (samples 0); its friction is score's first.
  SimulateParams simulate;

  static ScoreParams defaultScore();
};

// One grasp judged on the true object.
struct TrueGraspJudgement {
  std::optional<double> claimed_r;
  double observed_contact_ratio = 0;
  // r on the true mesh; 0 when the hand does not close there (start inside, too few contacts).
  double true_r = 0;
  bool true_force_closure = false;
  // The open hand at the grasp's pose intersects the true object ("start_collision").
  bool starts_inside = false;
  std::string closing_failure;        // the simulator's reason, empty when it closed
  std::optional<bool> nominal_holds;  // physics judge (unset without it)
  std::string failed_phase;           // "start", "closing", "disturbance"; empty when it held
  std::optional<double> sim_r;        // with simulate.samples > 0
};

// Judges `grasps` on the true object (`object` and `physical` of the same mesh, the grasps'
// frame; `physical` null: the model's judge only). Throws InvalidArgument for bad parameters
// (scoreGrasps', simulateGrasps').
std::vector<TrueGraspJudgement> judgeOnTrueObject(const grasping::HandModel& hand,
                                                  const grasping::GraspObject& object,
                                                  const physics::PhysicalObject* physical,
                                                  const std::vector<ClaimedGrasp>& grasps,
                                                  const TrueObjectParams& params = {});

// One run (an object seen in one view, planned with one hand): its top grasps judged.
struct ScanToGraspCase {
  std::string object;
  int view = 0;
  std::string hand;
  std::string status;                   // the run's status code ("ok", "no_result", ...)
  std::string reason;                   // the run's status message when it returned no grasp
  std::size_t returned = 0;             // grasps the run returned
  std::vector<TrueGraspJudgement> top;  // its best N, in rank order
  double run_s = 0;                     // the run's wall time (one core)
};

// The figures of one hand over its cases (an object's views). Per view the mean over its top
// grasps (claimed: over those the run scored, 0 when none; a view without grasps counts 0), per
// object the mean over its views, then the median over objects.
struct ScanToGraspFigures {
  std::size_t objects = 0;
  std::size_t objects_with_grasps = 0;  // at least one view returned a grasp
  std::size_t cases = 0;                // views
  std::size_t cases_with_grasps = 0;
  double median_claimed_r = 0;
  double median_true_r = 0;
  std::size_t top_grasps = 0;       // top grasps judged, all cases
  std::size_t starts_inside = 0;    // of them, the open hand inside the true object
  std::optional<double> hold_rate;  // physics judge: share of top grasps that held nominally
  // Pooled over every top grasp the run scored: mean claimed r minus mean true r.
  std::optional<double> claimed_minus_true;
  std::size_t claimed_pairs = 0;
  double median_run_s = 0;  // over views
};

ScanToGraspFigures scanToGraspFigures(const std::vector<ScanToGraspCase>& cases);

// The median of `values` (the mean of the middle two for an even count); 0 when empty.
double median(std::vector<double> values);

}  // namespace skelgrasp::evaluation
