#pragma once
// Re-scoring given grasps (`skelgrasp score`, docs/evaluation.md): each grasp is known only by its
// hand pose and preshape (ours from plan or run, or another planner's converted to our schema).
// The hand is placed there again and closed with the grasping simulator; the contacts it reaches
// are judged at one or several friction coefficients: force closure (LP) with its margin, the
// Ferrari-Canny epsilon (Qhull) and the robustness r with its 95 % Wilson interval.
#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/common/error.h"
#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/grasping/io/grasps_file.h"
#include "skelgrasp/grasping/quality/quality.h"
#include "skelgrasp/grasping/simulation/grasp_object.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"
#include "skelgrasp/ranking/limits.h"
#include "skelgrasp/ranking/robustness.h"

namespace skelgrasp::evaluation {

// Most friction coefficients one scoring judges every grasp at (each one repeats the robustness
// samples).
inline constexpr std::size_t kMaxScoreFrictions = 64;
// Seconds between the progress lines of a long scoring or simulation (`score`, `simulate`): none
// before the first interval has passed, then one at most every interval, after a whole grasp.
inline constexpr double kGraspsProgressIntervalS = 5.0;

struct ScoreParams {
  // Coulomb coefficients mu at which every grasp is judged, in the order given (at least one, at
  // most kMaxScoreFrictions, each finite and >= 0). Default: QualityParams' 0.35.
  std::vector<double> frictions = {grasping::QualityParams{}.friction};
  // Everything of the quality measure but the friction (taken from `frictions`). The torsional
  // friction, unset, is the hand's contact model, as the planners use it.
  grasping::QualityParams quality;
  // Closing of the grasp itself and of every robustness sample (stepwise by default, as plan).
  grasping::ClosingParams closing;
  // false: no robustness (force closure, margin and epsilon only; much faster).
  bool compute_robustness = true;
  // Samples (100), variant (settled), pose error sigmas (the variant's), seed (1) and the load
  // check (on, as plan's r; unset it for force closure alone). Its quality and closing are
  // ignored: `quality` with each friction and `closing` are used. Every grasp is scored with
  // grasp_index 0 (ranking::evaluateRobustness), the convention plan and run share, so a grasp's r
  // depends on its pose and the seed only and `score` reproduces plan's r.
  ranking::RobustnessParams robustness = [] {
    ranking::RobustnessParams p;
    p.load = ranking::defaultLoadCheck();
    return p;
  }();
};

// One grasp judged at one friction coefficient.
struct FrictionScore {
  double mu = 0;
  bool force_closure = false;
  // The LP's margin l* (grasping::WrenchSpaceResult::closure_margin); NaN when no LP ran (hull
  // test, reference_compat).
  double closure_margin = 0;
  double epsilon = 0;  // 0 without force closure
  std::optional<ranking::RobustnessResult>
      robustness;  // unset: not asked for, or the hand did not close
};

struct GraspScore {
  nlohmann::json id;  // the input's id, as given (null without one)
  std::string preshape;
  // Empty when the hand closed with enough contacts, else the simulator's reason
  // ("start_collision": the open hand intersects the object; "too_few_contacts").
  std::string closing_failure;
  std::string colliding_link;  // with start_collision: the first link in collision
  std::vector<grasping::Contact> contacts;
  Eigen::VectorXd joints;                  // the closed configuration
  std::vector<FrictionScore> by_friction;  // one per ScoreParams::frictions, same order
  double time_s = 0;                       // closing, quality and robustness of this grasp
};

struct ScoreResult {
  // kNoResult when there was no grasp to score or none of them closed; the grasps are still
  // listed with their closing failures.
  Status status;
  std::vector<GraspScore> grasps;  // one per input placement, same order
  std::size_t closed = 0;          // grasps that closed with enough contacts
  double time_s = 0;
  double robustness_s = 0;  // part of time_s spent on robustness samples
};

// The hand closings scoreGrasps runs for `grasps` grasps: one per grasp, and with robustness
// `samples` more per grasp and friction.
std::uint64_t scoreClosings(std::size_t grasps, const ScoreParams& params);
// Throws InvalidArgument when scoreClosings exceeds ranking::kMaxScoreClosings, saying how the
// count arises.
void checkScoreWork(std::size_t grasps, const ScoreParams& params);

// Throws InvalidArgument for bad parameters (no friction, too many, a negative or non-finite one,
// robustness samples < 1 when robustness is asked for, more closings than
// ranking::kMaxScoreClosings). `object` must be the mesh the poses refer
// to (same frame and units).
ScoreResult scoreGrasps(const grasping::HandModel& hand, const grasping::GraspObject& object,
                        const std::vector<grasping::GraspPlacement>& grasps,
                        const ScoreParams& params = {});

// The skelgrasp.score/1 document (docs/evaluation.md). `object` and `grasps_file` name the inputs.
nlohmann::json scoreToJson(const ScoreResult& result, const ScoreParams& params,
                           const grasping::HandModel& hand, const std::string& object,
                           const std::string& grasps_file);

// One line for the terminal: grasps scored, closed, force closure and mean r per mu, time.
std::string scoreSummaryLine(const ScoreResult& result, const ScoreParams& params);

}  // namespace skelgrasp::evaluation
