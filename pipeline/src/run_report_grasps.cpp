#include "run_report_grasps.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace skelgrasp::pipeline::internal {

namespace {
constexpr std::size_t kHistogramBins = 10;  // bins of 0.1 in r
// Chart geometry in pixels.
constexpr int kChartWidthPx = 420, kChartHeightPx = 180, kMarginPx = 30;

// What the robustness variant of the scored grasps means, for a reader of the report who does not
// know the option (docs/ranking.md, "Robustness score").
std::string variantPhrase(const std::string& variant) {
  if (variant == "settled") return "settled variant: the object free to move in the closing hand";
  if (variant == "paper") return "paper variant: the object held still";
  if (variant == "guarded") return "guarded variant: the object held still, guarded approach";
  if (variant == "reference") return "reference variant: the object moved";
  return variant + " variant";
}

}  // namespace

void addGraspTable(presentation::HtmlReport& report, const std::vector<RankedGrasp>& ranked,
                   std::size_t max_rows) {
  std::vector<std::vector<std::string>> rows;
  for (std::size_t k = 0; k < ranked.size() && k < max_rows; ++k) {
    const auto& g = ranked[k].grasp;
    const std::string r = g.robustness
                              ? fmt::format("{:.2f} [{:.2f}, {:.2f}]", g.robustness->r,
                                            g.robustness->ci95_low, g.robustness->ci95_high)
                              : "-";
    // What a user changes depends on why samples failed: clearance for starts in the object,
    // another place or more friction for slipping contacts.
    const std::string failures =
        g.robustness ? fmt::format("{} / {} / {} / {}", g.robustness->start_collisions,
                                   g.robustness->closing_failures, g.robustness->no_force_closure,
                                   g.robustness->too_weak)
                     : "-";
    rows.push_back({std::to_string(k), toString(g.type), g.strategy,
                    fmt::format("{:.4f}", g.epsilon),
                    fmt::format("{:.0f}%", 100 * ranked[k].observed_contact_ratio), r, failures,
                    fmt::format("{:.4f}", ranked[k].score)});
  }
  report.table(
      {"rank", "type", "strategy", "epsilon", "observed contacts", "r [95% interval]",
       "failed samples: start in object / too few contacts / slipped / too weak", "rank score"},
      rows);
  if (ranked.size() > rows.size()) {
    report.paragraph(
        fmt::format("The other {} ranked grasps are in grasps.json.", ranked.size() - rows.size()));
  }
}

std::string robustnessHistogramSvg(const std::vector<std::size_t>& counts) {
  const std::size_t bins = std::max<std::size_t>(1, counts.size());
  const std::size_t highest = std::max<std::size_t>(
      1, counts.empty() ? 1 : *std::max_element(counts.begin(), counts.end()));
  const double plot_w = kChartWidthPx - 2 * kMarginPx, plot_h = kChartHeightPx - 2 * kMarginPx;
  const double bar_w = plot_w / bins;
  std::string svg = fmt::format(
      "<svg class=\"robustness-histogram\" xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" "
      "height=\"{1}\" viewBox=\"0 0 {0} {1}\" font-family=\"sans-serif\" font-size=\"11\">\n",
      kChartWidthPx, kChartHeightPx);
  const double base = kMarginPx + plot_h;
  for (std::size_t b = 0; b < counts.size(); ++b) {
    const double h = plot_h * static_cast<double>(counts[b]) / highest;
    const double x = kMarginPx + b * bar_w;
    svg += fmt::format(
        "<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"#3c78c8\">"
        "<title>r in [{:.1f}, {:.1f}): {}</title></rect>\n",
        x + 1, base - h, bar_w - 2, h, double(b) / bins, double(b + 1) / bins, counts[b]);
    if (counts[b] > 0) {
      svg += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\">{}</text>\n",
                         x + bar_w / 2, base - h - 3, counts[b]);
    }
  }
  svg += fmt::format(
      "<line x1=\"{0}\" y1=\"{1:.1f}\" x2=\"{2:.1f}\" y2=\"{1:.1f}\" "
      "stroke=\"black\"/>\n",
      kMarginPx, base, kMarginPx + plot_w);
  for (int tick = 0; tick <= 10; tick += 2) {
    svg += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\">{:.1f}</text>\n",
                       kMarginPx + plot_w * tick / 10.0, base + 14, tick / 10.0);
  }
  svg += fmt::format(
      "<text x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\">robustness r (grasps per bin)</text>\n",
      kMarginPx + plot_w / 2, kChartHeightPx - 2);
  svg += "</svg>";
  return svg;
}

void addRobustnessHistogram(presentation::HtmlReport& report,
                            const std::vector<RankedGrasp>& ranked) {
  std::vector<std::size_t> counts(kHistogramBins, 0);
  std::size_t scored = 0;
  const grasping::GraspRobustness* any = nullptr;
  for (const auto& r : ranked) {
    if (!r.grasp.robustness) continue;
    any = &*r.grasp.robustness;
    const auto bin = static_cast<std::size_t>(std::floor(r.grasp.robustness->r * kHistogramBins));
    ++counts[std::min(bin, kHistogramBins - 1)];  // r = 1 goes to the last bin
    ++scored;
  }
  if (scored == 0) {
    report.paragraph("No grasp was scored for robustness.");
    return;
  }
  std::string contacts = any->torsional_friction_m > 0
                             ? fmt::format(", soft-finger contacts with {:.1f} mm torsion",
                                           1000 * any->torsional_friction_m)
                             : std::string();
  // The contact model r was judged with (docs/hands.md, "Closing"): where a link touching over an
  // area pushes.
  if (any->contact_patch == "corners") contacts += ", links on a face pushing through its corners";
  if (any->contact_patch == "centre") contacts += ", one contact per link";
  report.paragraph(fmt::format(
      "Robustness r of the {} scored grasps: the share of {} perturbed executions ({}, "
      "position sigma {:.0f} mm, orientation sigma {:.1f} deg, mu {:.2f}{}) that still reach "
      "force closure.",
      scored, any->samples, variantPhrase(any->variant), 1000 * any->sigma_m,
      any->sigma_rad * 180 / M_PI, any->mu, contacts));
  report.rawHtml(robustnessHistogramSvg(counts));
}

void addRejectionTable(presentation::HtmlReport& report, const grasping::PlanSummary& summary) {
  std::vector<std::vector<std::string>> reasons;
  for (const auto& [why, count] : summary.rejections)
    reasons.push_back({why, std::to_string(count)});
  for (const auto& [link, count] : summary.scene_collision_links) {
    reasons.push_back({"scene_collision at link " + link, std::to_string(count)});
  }
  report.table({"reason", "count"}, reasons);
  report.paragraph(fmt::format("{} hypotheses, {} generated, {} force closure ({:.1f}%).",
                               summary.hypotheses, summary.generated, summary.force_closure,
                               100 * summary.forceClosureRate()));
}

}  // namespace skelgrasp::pipeline::internal
