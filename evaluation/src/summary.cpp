// The summary of a batch directory: aggregation of its records, then summary.csv, the robustness
// charts and summary.md (summary_tables.cpp, summary_charts.cpp).
#include "summary.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "batch_setup.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/evaluation/batch.h"

namespace skelgrasp::evaluation {
namespace internal {
namespace {

// Scores on a bin edge (5 %, 10 %, ...) computed with rounding error still go to the lower bin.
constexpr double kBinEdgeTolerance = 1e-9;

}  // namespace

double Stat::mean() const {
  double s = 0;
  for (double v : values) s += v;
  return values.empty() ? 0 : s / values.size();
}

double Stat::std() const {
  if (values.size() < 2) return 0;
  const double m = mean();
  double s = 0;
  for (double v : values) s += (v - m) * (v - m);
  return std::sqrt(s / (values.size() - 1));
}

double Stat::median() const {
  if (values.empty()) return 0;
  std::vector<double> sorted = values;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t n = sorted.size();
  return n % 2 ? sorted[n / 2] : (sorted[n / 2 - 1] + sorted[n / 2]) / 2;
}

int robustnessBin(double r) {
  const int bin = static_cast<int>(std::ceil(r * kRobustnessBins - kBinEdgeTolerance)) - 1;
  return std::clamp(bin, 0, kRobustnessBins - 1);
}

BatchSummary aggregateSummary(const BatchRecords& records) {
  BatchSummary summary;
  for (const auto& [key, r] : records.runs) {
    auto& g = summary.groups[{r.hand, r.planner}];
    summary.hands.insert(r.hand);
    if (r.status == RunStatus::kError) {
      ++g.failed;
      summary.failures.push_back(
          fmt::format("{} {} {}: {}", r.object, r.hand, toString(r.planner), r.error));
      continue;
    }
    const RunMeasures& m = *r.measures;  // the reader guarantees them for a run that did not fail
    ++g.objects;
    g.grasps += m.kept;
    g.precision += m.precision;
    g.power += m.power;
    if (m.ms_per_valid_grasp) g.ms.add(*m.ms_per_valid_grasp);
    if (m.generated > 0) g.fc_rate.add(m.force_closure_rate);
    g.regularise_s += m.regularise_s;
    g.skeleton_s += m.skeleton_s;
    g.planning_s += m.planning_s;
    g.robustness_s += m.robustness_s;
    g.robustness_grasps += m.robustness_grasps;
    if (m.physics) {
      ++g.physics_runs;
      g.physics_judged += m.physics->judged;
      g.physics_holds += m.physics->holds;
      g.physics_start_failures += m.physics->start_failures;
      g.physics_closing_failures += m.physics->closing_failures;
      g.physics_disturbance_failures += m.physics->disturbance_failures;
      g.physics_cpu_s += m.physics->cpu_s;
    }
    if (m.ranked) {
      ++g.ranked_runs;
      if (m.kept > 0) ++g.ranked_with_grasps;
      // An object left without a grasp counts as r = 0: the user gets nothing that holds.
      g.ranked_r.add(m.ranked_r_mean.value_or(0.0));
      const double plan_s = m.regularise_s + m.skeleton_s + m.planning_s + m.ranking_s;
      g.plan_s.add(plan_s);
      g.ranked_samples += m.ranked_samples;
      g.ranked_start_collisions += m.ranked_start_collisions;
      g.ranked_closing_failures += m.ranked_closing_failures;
      g.ranked_no_force_closure += m.ranked_no_force_closure;
      g.ranked_too_weak += m.ranked_too_weak;
      if (m.ranked_refinement_s) {
        g.ranked_refined += m.ranked_refined;
        g.ranked_r_unrefined.add(m.ranked_r_mean_unrefined.value_or(0.0));
        g.plan_s_unrefined.add(plan_s - *m.ranked_refinement_s);
      }
    }
  }
  for (const auto& [key, list] : records.results) {
    for (const auto& grasp : list) {
      if (!grasp.robustness) continue;
      auto& g = summary.groups[{grasp.hand, grasp.planner}];
      g.robustness.add(grasp.robustness->score);
      ++g.histogram[robustnessBin(grasp.robustness->score)];
    }
  }
  return summary;
}

}  // namespace internal

void writeSummary(const std::string& dir) {
  // Through the loader, so records of interrupted or retried attempts count once.
  const auto summary = internal::aggregateSummary(internal::loadBatchRecords(dir));
  const auto charts = internal::writeRobustnessCharts(dir, summary);
  writeFileAtomically(dir + "/summary.csv", internal::summaryCsv(summary));
  // The settings line is a courtesy: a damaged batch.json (which a resume reports) leaves it out
  // rather than the summary.
  std::optional<nlohmann::json> options;
  try {
    options = internal::readBatchOptions(dir);
  } catch (const IoError& e) {
    log().warn("summary: settings left out: {}", e.what());
  }
  writeFileAtomically(dir + "/summary.md", internal::summaryMarkdown(summary, charts, options));
}

}  // namespace skelgrasp::evaluation
