// summary.csv and summary.md of a batch (docs/evaluation.md).
#include <fmt/format.h>

#include "skelgrasp/common/error.h"
#include "summary.h"

namespace skelgrasp::evaluation::internal {
namespace {

// Grasps scored for robustness per second of robustness time (0 without any time).
double robustnessThroughput(std::size_t grasps, double seconds) {
  return seconds > 0 ? grasps / seconds : 0.0;
}

// How screening chose its candidates, in words, from batch.json's "screen_by" (an older batch has
// none: the caller passes "epsilon"). A switch, so that a new order cannot go without its words.
std::string screeningWords(const std::string& screen_by) {
  grasping::ScreenCandidates candidates{};
  try {
    candidates = grasping::parseScreenCandidates(screen_by);
  } catch (const InvalidArgument&) {
    return "screened by '" + screen_by + "'";  // a batch.json from a newer build
  }
  switch (candidates) {
    case grasping::ScreenCandidates::kByPreScore:
      return "the best by epsilon";
    case grasping::ScreenCandidates::kPreshapesInTurn:
      return "each preshape's best in turn";
    case grasping::ScreenCandidates::kPreshapesInTurnByTravel:
      return "each preshape's best by finger travel in turn";
  }
  return "screened by '" + screen_by + "'";
}

// The confirmation of the screening's choice, in words, from batch.json's "confirm_samples" (an
// older batch has none: it confirmed nothing).
std::string confirmationWords(int confirm_samples, std::size_t top_k) {
  if (confirm_samples <= 0 || top_k == 0) return "";
  return fmt::format(", the best {} of them confirmed with {} more",
                     ranking::kConfirmCandidatesPerScored * top_k, confirm_samples);
}

// What every number below depends on and a reader of two summaries must tell apart: friction,
// contact model and how r was sampled. Read from batch.json's options (batch_setup.cpp); a key
// it lacks (an older batch) leaves its part out.
std::string settingsLine(const nlohmann::json& options) {
  std::vector<std::string> parts;
  if (options.contains("mu")) parts.push_back(fmt::format("μ = {}", options["mu"].get<double>()));
  const double torsion_m = options.value("/quality/torsional_friction_m"_json_pointer, 0.0);
  parts.push_back(torsion_m > 0 ? fmt::format("soft-finger contacts (torsional friction {:.1f} mm)",
                                              1000 * torsion_m)
                                : std::string("each hand's own contact model (point contacts for "
                                              "ARMAR-III, the SDH and the Shadow hand)"));
  parts.push_back(options.contains("contact_patch")
                      ? fmt::format("links touching over an area push through the patch's {}",
                                    options["contact_patch"].get<std::string>())
                      : std::string("one contact per link (the touching patch's centre)"));
  if (options.value("reference_compat", false)) parts.push_back("reference_compat quality");
  if (options.contains("robustness")) {
    const auto& r = options["robustness"];
    parts.push_back(fmt::format("robustness of sampled kept grasps: {} variant, {} samples",
                                r.value("variant", std::string("?")), r.value("samples", 0)));
  }
  if (options.contains("ranking")) {
    const auto& k = options["ranking"];
    parts.push_back(fmt::format(
        "robust ranking: {} screened ({}) with {} samples{}, the best {} scored with {}",
        k.value("screen_k", 0), screeningWords(k.value("screen_by", "epsilon")),
        k.value("screen_samples", 0),
        confirmationWords(k.value("confirm_samples", 0), k.value("top_k", std::size_t{0})),
        k.value("top_k", 0), k.value("samples", 0)));
    if (k.contains("hand_budgets") && k["hand_budgets"].is_object()) {
      // The search bar means nothing when the search is off.
      const bool searched = !k.contains("refinement") || k["refinement"].value("enabled", true);
      for (const auto& [hand, b] : k["hand_budgets"].items()) {
        std::string part = fmt::format("{}'s own ranking budget: {} screened with {} samples", hand,
                                       b.value("screen_k", 0), b.value("screen_samples", 0));
        if (b.contains("screen_by")) part += ", " + screeningWords(b.value("screen_by", ""));
        if (b.contains("confirm_samples")) {
          const int confirm_samples = b.value("confirm_samples", 0);
          part += confirm_samples > 0
                      ? confirmationWords(confirm_samples, k.value("top_k", std::size_t{0}))
                      : std::string(", no confirmation");
        }
        if (searched) part += fmt::format(", refined below r = {}", b.value("search_below_r", 0.0));
        parts.push_back(part);
      }
    }
  }
  std::string line = "Settings (batch.json): ";
  for (std::size_t i = 0; i < parts.size(); ++i) line += (i ? "; " : "") + parts[i];
  return line + ".\n\n";
}

// Why the returned grasps' perturbed executions failed, over the ranked runs that recorded it;
// empty when none did (batches from before the causes were recorded).
std::string failureTable(const BatchSummary& summary) {
  std::string md;
  for (const auto& [key, g] : summary.groups) {
    if (g.ranked_samples == 0) continue;
    const double n = static_cast<double>(g.ranked_samples);
    const std::size_t failed = g.ranked_start_collisions + g.ranked_closing_failures +
                               g.ranked_no_force_closure + g.ranked_too_weak;
    md += fmt::format("| {} | {} | {} | {:.1f}% | {:.1f}% | {:.1f}% | {:.1f}% | {:.1f}% |\n",
                      key.first, toString(key.second), g.ranked_samples, 100 * (n - failed) / n,
                      100 * g.ranked_start_collisions / n, 100 * g.ranked_closing_failures / n,
                      100 * g.ranked_no_force_closure / n, 100 * g.ranked_too_weak / n);
  }
  if (md.empty()) return md;
  return "\nThe scored grasps' perturbed executions, added up over the objects: held, and failed "
         "because the open hand started in the object, the closing ended with too few contacts, "
         "it closed without force closure (contacts that slip), or in force closure with contacts "
         "too weak to carry the object's weight (the load check).\n\n"
         "| hand | planner | samples | held | start in object | too few contacts | slipped | too "
         "weak |\n|---|---|---|---|---|---|---|---|\n" +
         md;
}

// What the refinement for robustness bought and cost: per hand and planner whose every ranked run
// recorded its share (older records did not), the top r and plan time with and without it. Empty
// when no group qualifies.
std::string refinementShareTable(const BatchSummary& summary) {
  std::string md;
  for (const auto& [key, g] : summary.groups) {
    if (g.ranked_runs == 0 || g.plan_s_unrefined.values.size() != g.ranked_runs) continue;
    md += fmt::format(
        "| {} | {} | {} | {:.1f}% ({:.1f}%) | {:.1f}% ({:.1f}%) | {:.2f} | {:.2f} |\n", key.first,
        toString(key.second), g.ranked_refined, 100 * g.ranked_r_unrefined.median(),
        100 * g.ranked_r_unrefined.mean(), 100 * g.ranked_r.median(), 100 * g.ranked_r.mean(),
        g.plan_s_unrefined.median(), g.plan_s.median());
  }
  if (md.empty()) return md;
  return "\nWhat the refinement for robustness changed (docs/planning.md, \"Refinement for "
         "robustness\"): the scored grasps it moved, top r median (mean) without it (each scored "
         "grasp's r before the refinement) and with it, and the median plan time without its time "
         "and with it. It runs after the scoring and moves only the grasps it searches, so the "
         "first columns are what the same run returns with `--no-robust-refine`.\n\n"
         "| hand | planner | grasps moved | top r without | top r with | plan s without | plan s "
         "with |\n|---|---|---|---|---|---|---|\n" +
         md;
}

// The grasps as `plan` returns them (runs with robust ranking), empty when no run was ranked.
std::string rankedTable(const BatchSummary& summary) {
  std::string md;
  for (const auto& [key, g] : summary.groups) {
    if (g.ranked_runs == 0) continue;
    md += fmt::format("| {} | {} | {} | {:.1f}% ({}) | {:.1f}% | {:.1f}% | {:.2f} |\n", key.first,
                      toString(key.second), g.ranked_runs,
                      100.0 * g.ranked_with_grasps / g.ranked_runs, g.ranked_with_grasps,
                      100 * g.ranked_r.median(), 100 * g.ranked_r.mean(), g.plan_s.median());
  }
  if (md.empty()) return md;
  md += refinementShareTable(summary);
  md += failureTable(summary);
  return "\n## Returned grasps (robust ranking)\n\n"
         "The grasps `skelgrasp plan` returns: ranked by robustness, r on the best "
         "(docs/planning.md, "
         "\"Robust ranking\"). Top r: the mean r of each object's scored grasps, median and mean "
         "over objects, an object without any grasp counted as 0. Time: median over objects of "
         "regularisation, skeleton, planning and ranking.\n\n"
         "| hand | planner | objects | with a grasp | top r, median | top r, mean | plan s, median "
         "|\n|---|---|---|---|---|---|---|\n" +
         md;
}

// The physics judge's nominal executions (runs with --judge physics), empty when none was judged.
std::string physicsTable(const BatchSummary& summary) {
  std::string md;
  for (const auto& [key, g] : summary.groups) {
    if (g.physics_runs == 0) continue;
    const double n = static_cast<double>(std::max<std::size_t>(g.physics_judged, 1));
    md += fmt::format("| {} | {} | {} | {} | {:.1f}% | {:.1f}% | {:.1f}% | {:.1f}% | {:.0f} |\n",
                      key.first, toString(key.second), g.physics_runs, g.physics_judged,
                      100 * g.physics_holds / n, 100 * g.physics_start_failures / n,
                      100 * g.physics_closing_failures / n,
                      100 * g.physics_disturbance_failures / n, 1000 * g.physics_cpu_s / n);
  }
  if (md.empty()) return md;
  return "\n## Physics judge\n\n"
         "Each run's first grasps, in the order the run returns them, executed nominally in the "
         "rigid-body simulation (docs/physics.md): held, or failed at the start (the open hand in "
         "the object), in the closing or under a disturbance. CPU: thread CPU time per "
         "execution.\n\n"
         "| hand | planner | runs | grasps executed | held | failed at start | failed closing | "
         "failed under disturbance | ms CPU per execution "
         "|\n|---|---|---|---|---|---|---|---|---|\n" +
         md;
}

}  // namespace

std::string summaryCsv(const BatchSummary& summary) {
  std::string csv =
      "hand,planner,objects,grasps,ms_per_valid_grasp,ms_per_valid_grasp_std,force_closure_rate,"
      "force_closure_rate_std,robustness,robustness_std,precision,power\n";
  for (const auto& [key, g] : summary.groups) {
    csv += fmt::format("{},{},{},{},{:.3f},{:.3f},{:.4f},{:.4f},{:.4f},{:.4f},{},{}\n", key.first,
                       toString(key.second), g.objects, g.grasps, g.ms.mean(), g.ms.std(),
                       g.fc_rate.mean(), g.fc_rate.std(), g.robustness.mean(), g.robustness.std(),
                       g.precision, g.power);
  }
  return csv;
}

std::string summaryMarkdown(const BatchSummary& summary, const std::vector<RobustnessChart>& charts,
                            const std::optional<nlohmann::json>& options) {
  std::string md = "# Evaluation summary\n\n";
  if (options && options->is_object()) md += settingsLine(*options);
  md +=
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
  for (const auto& [key, g] : summary.groups) {
    const char* planner = toString(key.second);
    md += fmt::format(
        "| {} | {} | {} | {} | {:.2f} ms ± {:.2f} | {:.2f}% ± {:.2f} | {} | {} / {} |\n", key.first,
        planner, g.objects, g.grasps, g.ms.mean(), g.ms.std(), 100 * g.fc_rate.mean(),
        100 * g.fc_rate.std(),
        g.robustness.values.empty()
            ? std::string("n/a")
            : fmt::format("{:.2f}% ± {:.2f} ({} grasps)", 100 * g.robustness.mean(),
                          100 * g.robustness.std(), g.robustness.values.size()),
        g.precision, g.power);
    timings += fmt::format("| {} | {} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.2f} |\n", key.first,
                           planner, g.regularise_s, g.skeleton_s, g.planning_s, g.robustness_s,
                           robustnessThroughput(g.robustness_grasps, g.robustness_s));
    all_robustness_s += g.robustness_s;
    all_robustness_grasps += g.robustness_grasps;
  }
  md += rankedTable(summary);
  md += physicsTable(summary);
  md += timings;
  md += fmt::format(
      "\nBatch throughput: {:.2f} grasps evaluated for robustness per second per core.\n",
      robustnessThroughput(all_robustness_grasps, all_robustness_s));
  if (!summary.failures.empty()) {
    md += "\n## Failed runs\n\n";
    for (const auto& f : summary.failures) md += "- " + f + "\n";
  }
  md += "\n## Robustness histograms\n\n";
  for (const auto& chart : charts) md += fmt::format("![{}]({})\n", chart.hand, chart.file);
  return md;
}

}  // namespace skelgrasp::evaluation::internal
