#pragma once
// The members `skelgrasp plan` and the Python module's PlanResult.to_dict() add to a grasps.json
// document (skelgrasp.grasps/3, docs/planning.md): what the robust ranking did, and where the
// time of planning one object with one hand went, in the parts issue 16's plan-time goal counts.
// One function for both, so that the two documents cannot drift apart.
#include <nlohmann/json.hpp>

#include "skelgrasp/ranking/plan_grasps.h"
#include "skelgrasp/ranking/robust_ranking.h"

namespace skelgrasp::evaluation {

// {"screened", "screen_pruned", "confirmed", "scored", "refined", "screening_s", "scoring_s",
// "refinement_s"} of a ranking (ranking::RobustRankingResult's members of those names), and
// "budget":
// {"screen_grasps", "screen_samples", "screen_by", "confirm_samples", "refine_below_r"}
// (ranking::RankingBudgetUsed: what it ran with, or would have where no screening ran).
nlohmann::json rankingRecordJson(const ranking::RobustRankingResult& ranking);

// {"regularise_s", "skeleton_s" (null without a skeleton), "planning_s", "ranking_s", "total_s"}.
nlohmann::json planTimingJson(const ranking::PlanTiming& timing);

// Adds "ranking" (rankingRecordJson, or null when the ranking was disabled: `ranking.enabled`)
// and "timing" (planTimingJson) to a grasps.json document. Throws InvalidArgument when `document`
// is not a JSON object or a time is negative or not finite.
void addPlanRecords(nlohmann::json& document, const ranking::RobustRankingResult& ranking,
                    const ranking::PlanTiming& timing);

}  // namespace skelgrasp::evaluation
