#pragma once
// Internal: the summary of a batch's records (summary.csv, summary.md and the robustness
// histograms), in steps: aggregation into a BatchSummary, then each output from it.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch_store.h"

namespace skelgrasp::evaluation::internal {

// Robustness histograms: bins of 5 %, bin k holds r in (5k %, 5(k+1) %] and r = 0 goes to the
// first bin.
constexpr int kRobustnessBins = 20;

// Mean and sample standard deviation of a list of values (0 when undefined).
struct Stat {
  std::vector<double> values;
  void add(double v) { values.push_back(v); }
  double mean() const;
  double std() const;
  double median() const;  // 0 when empty
};

// What the summary shows of the runs and scored grasps of one hand and planner.
struct PlannerSummary {
  std::size_t objects = 0;  // runs that did not fail
  std::size_t failed = 0;
  std::size_t grasps = 0, precision = 0, power = 0;  // kept grasps
  std::size_t robustness_grasps = 0;                 // grasps scored for robustness
  Stat ms;          // time per valid grasp, per run with force-closure grasps
  Stat fc_rate;     // force-closure rate, per run with generated grasps
  Stat robustness;  // r of every scored grasp
  double regularise_s = 0, skeleton_s = 0, planning_s = 0, robustness_s = 0;  // summed over runs
  std::vector<int> histogram = std::vector<int>(kRobustnessBins, 0);  // scored grasps per bin
  // Robust ranking (runs made with BatchParams::ranking): the grasps a user of `plan` gets.
  std::size_t ranked_runs = 0;
  std::size_t ranked_with_grasps = 0;  // of ranked_runs: at least one grasp returned
  Stat ranked_r;  // per ranked run: mean r of the scored (top) grasps, 0 without any grasp
  Stat plan_s;    // per ranked run: regularise + skeleton + planning + ranking seconds
  // The scored grasps' samples over the ranked runs that recorded them, and the failed ones by
  // cause.
  std::size_t ranked_samples = 0;
  std::size_t ranked_start_collisions = 0, ranked_closing_failures = 0, ranked_no_force_closure = 0;
  // Force closure whose contacts could not carry the weight (the ranking's load check).
  std::size_t ranked_too_weak = 0;
  // The same without the refinement for robustness, over the ranked runs that recorded its share
  // (one value each in both Stats): top r from the scored grasps' r before it, and the plan time
  // less its time; and the scored grasps it moved.
  std::size_t ranked_refined = 0;
  Stat ranked_r_unrefined;
  Stat plan_s_unrefined;
  // The physics judge (runs made with BatchParams::physics): its nominal executions of the runs'
  // first grasps added up, and the failed ones by phase.
  std::size_t physics_runs = 0;
  std::size_t physics_judged = 0, physics_holds = 0;
  std::size_t physics_start_failures = 0, physics_closing_failures = 0,
              physics_disturbance_failures = 0;
  double physics_cpu_s = 0;
};

struct BatchSummary {
  // By (hand, planner), in the order of the tables.
  std::map<std::pair<std::string, ranking::Planner>, PlannerSummary> groups;
  std::set<std::string> hands;
  std::vector<std::string> failures;  // "OBJECT HAND PLANNER: error", in run key order
};

// The histogram bin of a robustness score r in [0, 1].
int robustnessBin(double r);

BatchSummary aggregateSummary(const BatchRecords& records);

// summary.csv: one line per hand and planner.
std::string summaryCsv(const BatchSummary& summary);

// A robustness chart written for a hand: its file name in the batch directory.
struct RobustnessChart {
  std::string hand;
  std::string file;
};

// Writes robustness_<hand>.png into `dir` for each hand with scored grasps (skeleton vs surface
// planner, fraction of scored grasps per bin); returns the charts written, by hand.
std::vector<RobustnessChart> writeRobustnessCharts(const std::string& dir,
                                                   const BatchSummary& summary);

// summary.md: the settings the runs were judged with (from batch.json's `options`, when there is
// one), the paper's Table I layout, time spent, throughput, failed runs and `charts`.
std::string summaryMarkdown(const BatchSummary& summary, const std::vector<RobustnessChart>& charts,
                            const std::optional<nlohmann::json>& options = std::nullopt);

}  // namespace skelgrasp::evaluation::internal
