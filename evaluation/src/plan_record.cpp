#include "skelgrasp/evaluation/plan_record.h"

#include <algorithm>
#include <cmath>

#include "skelgrasp/common/error.h"

namespace skelgrasp::evaluation {
namespace {

// A time written to a document must be one: a stopwatch never gives a negative or NaN reading, so
// such a value is a caller's arithmetic slip that would otherwise reach users as a number.
void checkSeconds(double seconds, const char* what) {
  if (!(std::isfinite(seconds) && seconds >= 0))
    throw InvalidArgument(std::string("plan record: ") + what + " must be finite and >= 0");
}

nlohmann::json optionalSeconds(const std::optional<double>& seconds) {
  return seconds ? nlohmann::json(*seconds) : nlohmann::json(nullptr);
}

}  // namespace

nlohmann::json rankingRecordJson(const ranking::RobustRankingResult& ranking) {
  return {{"screened", ranking.screened},
          {"screen_pruned", ranking.screen_pruned},
          {"confirmed", ranking.confirmed},
          {"scored", ranking.scored},
          {"refined", ranking.refined},
          {"screening_s", ranking.screening_s},
          {"scoring_s", ranking.scoring_s},
          {"refinement_s", ranking.refinement_s},
          {"budget",
           {{"screen_grasps", ranking.budget.screen_k},
            {"screen_samples", ranking.budget.screen_samples},
            {"screen_by", toString(ranking.budget.screen_candidates)},
            {"confirm_samples", ranking.budget.confirm_samples},
            {"refine_below_r", ranking.budget.search_below_r}}}};
}

nlohmann::json planTimingJson(const ranking::PlanTiming& timing) {
  if (timing.regularise_s) checkSeconds(*timing.regularise_s, "regularise_s");
  if (timing.skeleton_s) checkSeconds(*timing.skeleton_s, "skeleton_s");
  checkSeconds(timing.planning_s, "planning_s");
  checkSeconds(timing.ranking_s, "ranking_s");
  return {{"regularise_s", optionalSeconds(timing.regularise_s)},
          {"skeleton_s", optionalSeconds(timing.skeleton_s)},
          {"planning_s", timing.planning_s},
          {"ranking_s", timing.ranking_s},
          {"total_s", timing.total_s()}};
}

void addPlanRecords(nlohmann::json& document, const ranking::RobustRankingResult& ranking,
                    const ranking::PlanTiming& timing) {
  if (!document.is_object()) throw InvalidArgument("plan record: the document must be an object");
  document["ranking"] = ranking.enabled ? rankingRecordJson(ranking) : nlohmann::json(nullptr);
  document["timing"] = planTimingJson(timing);
}

}  // namespace skelgrasp::evaluation
