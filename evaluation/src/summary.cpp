// summary.md, summary.csv and robustness histograms from a batch's runs.jsonl / results.jsonl, and
// merging of shard outputs.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

#include "batch_setup.h"
#include "batch_store.h"
#include "directory_lock.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/render.h"
#include "skelgrasp/evaluation/batch.h"

namespace skelgrasp::evaluation {
namespace {

struct Stat {
  std::vector<double> values;
  void add(double v) { values.push_back(v); }
  double mean() const {
    double s = 0;
    for (double v : values) s += v;
    return values.empty() ? 0 : s / values.size();
  }
  double std() const {
    if (values.size() < 2) return 0;
    const double m = mean();
    double s = 0;
    for (double v : values) s += (v - m) * (v - m);
    return std::sqrt(s / (values.size() - 1));
  }
};

struct Group {
  std::size_t objects = 0, failed = 0, grasps = 0, precision = 0, power = 0, robustness_grasps = 0;
  Stat ms, fc_rate, robustness;
  double regularise_s = 0, skeleton_s = 0, planning_s = 0, robustness_s = 0;
  std::vector<int> histogram = std::vector<int>(20, 0);
};

double number(const nlohmann::json& j, const char* key) {
  return j.contains(key) && j.at(key).is_number() ? j.at(key).get<double>() : 0.0;
}

}  // namespace

void writeSummary(const std::string& dir) {
  // Through the loader, so records of interrupted or retried attempts count once.
  const internal::BatchRecords records = internal::loadBatchRecords(dir);
  std::vector<nlohmann::json> runs, results;
  for (const auto& [key, run] : records.runs) runs.push_back(run);
  for (const auto& [key, list] : records.results)
    results.insert(results.end(), list.begin(), list.end());
  std::map<std::pair<std::string, std::string>, Group> groups;  // (hand, planner)
  std::set<std::string> hands;
  std::vector<std::string> failures;
  for (const auto& r : runs) {
    auto& g = groups[{r.at("hand").get<std::string>(), r.at("planner").get<std::string>()}];
    hands.insert(r.at("hand").get<std::string>());
    if (r.at("status") == "error") {
      ++g.failed;
      failures.push_back(fmt::format("{} {} {}: {}", r.at("object").get<std::string>(),
                                     r.at("hand").get<std::string>(),
                                     r.at("planner").get<std::string>(), r.value("error", "")));
      continue;
    }
    ++g.objects;
    g.grasps += static_cast<std::size_t>(number(r, "kept"));
    g.precision += static_cast<std::size_t>(number(r, "precision"));
    g.power += static_cast<std::size_t>(number(r, "power"));
    if (r.at("ms_per_valid_grasp").is_number()) g.ms.add(r.at("ms_per_valid_grasp").get<double>());
    if (number(r, "generated") > 0) g.fc_rate.add(number(r, "force_closure_rate"));
    g.regularise_s += number(r, "regularise_s");
    g.skeleton_s += number(r, "skeleton_s");
    g.planning_s += number(r, "planning_s");
    g.robustness_s += number(r, "robustness_s");
    g.robustness_grasps += static_cast<std::size_t>(number(r, "robustness_grasps"));
  }
  for (const auto& res : results) {
    if (!res.at("robustness").is_number()) continue;
    auto& g = groups[{res.at("hand").get<std::string>(), res.at("planner").get<std::string>()}];
    const double r = res.at("robustness").get<double>();
    g.robustness.add(r);
    // Bin k holds (5k %, 5(k+1) %]; r = 0 goes to the first bin.
    const int bin = std::clamp(static_cast<int>(std::ceil(r * 20 - 1e-9)) - 1, 0, 19);
    ++g.histogram[bin];
  }

  std::string csv =
      "hand,planner,objects,grasps,ms_per_valid_grasp,ms_per_valid_grasp_std,force_closure_rate,"
      "force_closure_rate_std,robustness,robustness_std,precision,power\n";
  std::string md =
      "# Evaluation summary\n\n"
      "Per hand and planner (the paper's Table I layout): average time per valid grasp and "
      "force-closure "
      "rate (mean ± std over objects), robustness r (mean ± std over the grasps evaluated), grasp "
      "counts. Files: runs.jsonl, results.jsonl (docs/evaluation.md).\n\n"
      "| hand | planner | objects | grasps | time per valid grasp | force-closure rate | "
      "robustness r | "
      "precision / power |\n|---|---|---|---|---|---|---|---|\n";
  std::string timings =
      "\n## Time spent\n\n| hand | planner | regularise s | skeleton s | planning s | robustness s "
      "| "
      "robustness grasps per second |\n|---|---|---|---|---|---|---|\n";
  double all_robustness_s = 0;
  std::size_t all_robustness_grasps = 0;
  for (const auto& [key, g] : groups) {
    csv +=
        fmt::format("{},{},{},{},{:.3f},{:.3f},{:.4f},{:.4f},{:.4f},{:.4f},{},{}\n", key.first,
                    key.second, g.objects, g.grasps, g.ms.mean(), g.ms.std(), g.fc_rate.mean(),
                    g.fc_rate.std(), g.robustness.mean(), g.robustness.std(), g.precision, g.power);
    md += fmt::format(
        "| {} | {} | {} | {} | {:.2f} ms ± {:.2f} | {:.2f}% ± {:.2f} | {} | {} / {} |\n", key.first,
        key.second, g.objects, g.grasps, g.ms.mean(), g.ms.std(), 100 * g.fc_rate.mean(),
        100 * g.fc_rate.std(),
        g.robustness.values.empty()
            ? std::string("n/a")
            : fmt::format("{:.2f}% ± {:.2f} ({} grasps)", 100 * g.robustness.mean(),
                          100 * g.robustness.std(), g.robustness.values.size()),
        g.precision, g.power);
    timings += fmt::format("| {} | {} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.2f} |\n", key.first,
                           key.second, g.regularise_s, g.skeleton_s, g.planning_s, g.robustness_s,
                           g.robustness_s > 0 ? g.robustness_grasps / g.robustness_s : 0.0);
    all_robustness_s += g.robustness_s;
    all_robustness_grasps += g.robustness_grasps;
  }
  md += timings;
  md += fmt::format(
      "\nBatch throughput: {:.2f} grasps evaluated for robustness per second per core.\n",
      all_robustness_s > 0 ? all_robustness_grasps / all_robustness_s : 0.0);
  if (!failures.empty()) {
    md += "\n## Failed runs\n\n";
    for (const auto& f : failures) md += "- " + f + "\n";
  }
  // Histograms: one chart per hand, skeleton vs surface, 5 % bins, fraction of grasps per bin.
  std::vector<std::string> labels;
  for (int b = 1; b <= 20; ++b) labels.push_back(fmt::format("{}%", 5 * b));
  md += "\n## Robustness histograms\n\n";
  for (const auto& hand : hands) {
    std::vector<render::BarSeries> series;
    for (const std::string planner : {"surface", "skeleton"}) {
      const auto it = groups.find({hand, planner});
      if (it == groups.end() || it->second.robustness.values.empty()) continue;
      render::BarSeries s{
          planner, planner == "skeleton" ? Rgb{70, 110, 220} : Rgb{220, 80, 70}, {}};
      for (int count : it->second.histogram)
        s.values.push_back(static_cast<double>(count) / it->second.robustness.values.size());
      series.push_back(s);
    }
    if (series.empty()) continue;
    const std::string png = "robustness_" + hand + ".png";
    render::saveBarChartPng(dir + "/" + png, "robustness r, " + hand + " (bins of 5%)", labels,
                            series, "fraction of grasps");
    md += fmt::format("![{}]({})\n", hand, png);
  }
  writeFileAtomically(dir + "/summary.csv", csv);
  writeFileAtomically(dir + "/summary.md", md);
}

void mergeBatches(const std::vector<std::string>& shard_dirs, const std::string& out_dir) {
  if (shard_dirs.empty()) throw InvalidArgument("merge: no shard directories");
  // Everything is checked before out_dir is touched.
  std::optional<nlohmann::json> options;
  std::string options_from;
  for (const auto& dir : shard_dirs) {
    if (!std::filesystem::exists(dir + "/runs.jsonl"))
      throw IoError(dir, "no runs.jsonl (not a batch output)");
    if (const auto holder = internal::lockHolder(dir)) {
      throw IoError(dir, (*holder > 0 ? "is in use by process " + std::to_string(*holder)
                                      : std::string("is in use by another process")) +
                             " (its evaluate has not finished)");
    }
    const auto shard_options = internal::readBatchOptions(dir);
    if (!shard_options) {
      log().warn("{}: no batch.json (written by an older skelgrasp): its options cannot be checked",
                 dir);
    } else if (!options) {
      options = shard_options;
      options_from = dir;
    } else if (const auto differ = internal::describeDifferences(*options, *shard_options);
               !differ.empty()) {
      throw InvalidArgument(dir + ": was run with other options than " + options_from + " (" +
                            differ + "); shards of one batch must share them");
    }
  }
  internal::BatchRecords merged;
  for (const auto& dir : shard_dirs) {
    auto shard = internal::loadBatchRecords(dir);
    for (auto& [key, run] : shard.runs) {
      if (merged.runs.count(key)) continue;  // the first shard that has a run wins
      merged.runs[key] = std::move(run);
      if (shard.results.count(key)) merged.results[key] = std::move(shard.results[key]);
    }
  }
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw IoError(out_dir, "cannot create the output directory: " + ec.message());
  const internal::DirectoryLock lock(out_dir);
  internal::writeBatchRecords(out_dir, merged);
  if (options) {
    internal::writeBatchOptions(out_dir, *options);
  } else {
    std::filesystem::remove(out_dir + "/batch.json", ec);  // not this batch's any more
  }
  writeSummary(out_dir);
}

}  // namespace skelgrasp::evaluation
