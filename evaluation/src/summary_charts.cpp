// The robustness histograms of a batch: one chart per hand, like the paper's Figs. 11-13.
#include <fmt/format.h>

#include "skelgrasp/presentation/render.h"
#include "summary.h"

namespace skelgrasp::evaluation::internal {
namespace {

constexpr int kPercentPerBin = 100 / kRobustnessBins;

Rgb plannerColour(ranking::Planner planner) {
  return planner == ranking::Planner::kSkeleton ? Rgb{70, 110, 220} : Rgb{220, 80, 70};
}

}  // namespace

std::vector<RobustnessChart> writeRobustnessCharts(const std::string& dir,
                                                   const BatchSummary& summary) {
  std::vector<std::string> labels;
  for (int b = 1; b <= kRobustnessBins; ++b)
    labels.push_back(fmt::format("{}%", kPercentPerBin * b));
  std::vector<RobustnessChart> charts;
  for (const auto& hand : summary.hands) {
    std::vector<presentation::BarSeries> series;
    // Surface first: the baseline's bar left of the skeleton planner's in each bin, as in the
    // paper.
    for (const ranking::Planner planner :
         {ranking::Planner::kSurface, ranking::Planner::kSkeleton}) {
      const auto it = summary.groups.find({hand, planner});
      if (it == summary.groups.end() || it->second.robustness.values.empty()) continue;
      presentation::BarSeries s{toString(planner), plannerColour(planner), {}};
      for (int count : it->second.histogram)
        s.values.push_back(static_cast<double>(count) / it->second.robustness.values.size());
      series.push_back(s);
    }
    if (series.empty()) continue;
    const std::string png = "robustness_" + hand + ".png";
    presentation::saveBarChartPng(
        dir + "/" + png, fmt::format("robustness r, {} (bins of {}%)", hand, kPercentPerBin),
        labels, series, "fraction of grasps");
    charts.push_back({hand, png});
  }
  return charts;
}

}  // namespace skelgrasp::evaluation::internal
