#pragma once
// The members `skelgrasp plan` and the Python module's PlanResult.to_dict() add to a grasps.json
// document (skelgrasp.grasps/3, docs/planning.md): what the robust ranking did, and where the
// time of planning one object with one hand went, in the parts issue 16's plan-time goal counts.
// One function for both, so that the two documents cannot drift apart.
#include <nlohmann/json.hpp>

#include <optional>

#include "skelgrasp/evaluation/robust_ranking.h"
#include "skelgrasp/skeleton/extraction.h"

namespace skelgrasp::evaluation {

// Seconds of the stages of planning one object with one hand. The skeleton's parts are unset for
// the surface planner, which needs no skeleton. Loading the mesh and writing outputs are not
// counted: they depend on the disk, not on the method.
struct PlanTiming {
  std::optional<double> regularise_s;  // the closed manifold the contraction needs
  std::optional<double> skeleton_s;    // contraction, mapping and analysis
  double planning_s = 0;               // hypotheses generated, closed and judged
  double ranking_s = 0;                // robust ranking, refinement for robustness included
  double total_s() const;
};

// The timing of a plan from the skeleton stage's times (null: the surface planner, no skeleton),
// the planner's and the ranking's. The skeleton's time is its total less the regularisation.
PlanTiming planTimingOf(const skeleton::SkeletonTimings* skeleton, double planning_s,
                        double ranking_s);

// {"screened", "screen_pruned", "confirmed", "scored", "refined", "screening_s", "scoring_s",
// "refinement_s"} of a ranking (RobustRankingResult's members of those names), and "budget":
// {"screen_grasps", "screen_samples", "screen_by", "confirm_samples", "refine_below_r"}
// (RankingBudgetUsed: what it ran with, or would have where no screening ran).
nlohmann::json rankingRecordJson(const RobustRankingResult& ranking);

// {"regularise_s", "skeleton_s" (null without a skeleton), "planning_s", "ranking_s", "total_s"}.
nlohmann::json planTimingJson(const PlanTiming& timing);

// Adds "ranking" (rankingRecordJson, or null when the ranking was disabled: `ranking.enabled`)
// and "timing" (planTimingJson) to a grasps.json document. Throws InvalidArgument when `document`
// is not a JSON object or a time is negative or not finite.
void addPlanRecords(nlohmann::json& document, const RobustRankingResult& ranking,
                    const PlanTiming& timing);

}  // namespace skelgrasp::evaluation
