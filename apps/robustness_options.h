#pragma once
// Robust ranking options (ranking/robust_ranking.h), shared by the commands that plan and rank
// (plan, run, demo, bench run).
#include <CLI/CLI.hpp>

#include <fmt/format.h>

#include <optional>
#include <string>
#include <vector>

#include "help_format.h"
#include "option_checks.h"
#include "ranking_budget.h"
#include "skelgrasp/ranking/limits.h"
#include "skelgrasp/ranking/robust_ranking.h"

namespace skelgrasp::cli {

// Most perturbed poses per grasp a command accepts, as the Python module (ranking/limits.h).
constexpr std::uint64_t kMaxRankingSamples = ranking::kMaxRobustnessSamples;
// Farthest standoff the search for a more robust pose may try (m): beyond a hand's length the
// fingers no longer reach the object.
constexpr double kMaxRefineStandoffM = 0.2;

// --robustness-variant, the same on every command that scores robustness.
inline CLI::Option* addRobustnessVariantOption(CLI::App& cmd, std::string& variant) {
  return cmd
      .add_option("--robustness-variant", variant,
                  "paper (hand moved, 10 mm / 5 deg; a start in collision fails), guarded (the "
                  "paper's samples, a start in collision backs off along the approach), settled "
                  "(guarded, and the object free to settle in the closing hand) or reference "
                  "(object moved, 5 mm / 2.5 deg)")
      ->check(CLI::IsMember({"paper", "guarded", "settled", "reference"}))
      ->capture_default_str();
}

// --robustness-screen, the same on every command that ranks by robustness. No shown default:
// unset means the hand's ranking budget.
inline CLI::Option* addScreenOption(CLI::App& cmd, std::optional<std::size_t>& screen_k) {
  return cmd
      .add_option("--robustness-screen", screen_k,
                  fmt::format("Grasps screened with a cheap r to choose those scored, which ones "
                              "as --robustness-screen-by says (0 = all; none when at most "
                              "--robustness-top-k; default: the hand's ranking budget, else {})",
                              ranking::kDefaultScreenK))
      ->transform(countIn(0, kMaxCount));
}

// --robustness-screen-samples, the same on every command that ranks by robustness.
inline CLI::Option* addScreenSamplesOption(CLI::App& cmd, std::optional<int>& screen_samples) {
  return cmd
      .add_option("--robustness-screen-samples", screen_samples,
                  fmt::format("Perturbed executions per screened grasp (default: the hand's "
                              "ranking budget, else {})",
                              ranking::kDefaultScreenSamples))
      ->transform(countIn(1, kMaxRankingSamples));
}

// --robustness-confirm-samples, the same on every command that ranks by robustness.
inline CLI::Option* addConfirmSamplesOption(CLI::App& cmd, std::optional<int>& confirm_samples) {
  return cmd
      .add_option(
          "--robustness-confirm-samples", confirm_samples,
          fmt::format("More perturbed executions for the best {} x --robustness-top-k "
                      "screened grasps before the top k are chosen (0 = none; default: "
                      "the hand's ranking budget, else {})",
                      ranking::kConfirmCandidatesPerScored, ranking::kDefaultConfirmSamples))
      ->transform(countIn(0, kMaxRankingSamples));
}

// --robustness-screen-by, the same on every command that ranks by robustness.
// No shown default: unset means the hand's ranking budget.
inline CLI::Option* addScreenByOption(CLI::App& cmd, std::optional<std::string>& screen_by) {
  return cmd
      .add_option("--robustness-screen-by", screen_by,
                  fmt::format("Which grasps are screened: preshapes (each preshape's best by "
                              "epsilon in turn, so every preshape the planner closed is screened), "
                              "travel (each preshape's in turn too, but its grasps by their least "
                              "finger travel from the preshape, the largest first) or epsilon (the "
                              "best by epsilon over all); only when screening runs (default: the "
                              "hand's ranking budget, else {})",
                              ranking::toString(ranking::kDefaultScreenCandidates)))
      ->check(CLI::IsMember(grasping::screenCandidateNames()));
}

// The option's value as the ranking's parameter (unset stays unset: the hand's).
inline std::optional<ranking::ScreenCandidates> screenCandidates(
    const std::optional<std::string>& screen_by) {
  if (!screen_by) return std::nullopt;
  return ranking::parseScreenCandidates(*screen_by);
}

// A preset's value as --help shows it.
template <typename Value>
std::string presetValueText(const Value& value) {
  return fmt::format("{}", value);
}
template <typename Value>
std::string presetValueText(const std::optional<Value>& value) {
  return value ? fmt::format("{}", *value) : std::string("the hand's");
}

// Appends the values --ranking-budget small and thorough give an option to its description.
template <typename Value>
CLI::Option* notePresets(CLI::Option* option, Value RankingBudgetPreset::*member) {
  return option->description(fmt::format("{} (--ranking-budget small: {}, thorough: {})",
                                         option->get_description(),
                                         presetValueText(rankingBudgetPreset("small").*member),
                                         presetValueText(rankingBudgetPreset("thorough").*member)));
}

// Refinement for robustness (ranking/robust_refinement.h), the same on every command that ranks.
// The counts a --ranking-budget sets are unset unless given: the preset's then (applyTo).
struct RobustRefineOptions {
  bool disabled = !ranking::RobustRefinementParams{}.enabled;
  std::optional<std::size_t> grasps;     // unset: the --ranking-budget's
  std::optional<double> search_below_r;  // unset: the hand's ranking budget
  std::optional<int> evaluations;        // unset: the --ranking-budget's
  std::optional<int> samples;            // unset: the --ranking-budget's
  double max_standoff_m = ranking::RobustRefinementParams{}.max_standoff_m;
  int mean_shift_steps = ranking::RobustRefinementParams{}.mean_shift_steps;

  // `presets`: the command has --ranking-budget, so the counts' help names its values.
  void addTo(CLI::App& cmd, bool presets = false) {
    const auto& fallback = rankingBudgetPreset(kDefaultRankingBudget);
    cmd.add_flag("--no-robust-refine", disabled,
                 "Return the planner's poses: no search for a more robust pose near each scored "
                 "grasp")
        ->group(kRankingDetails);
    auto* grasps_option =
        cmd.add_option("--robust-refine-grasps", grasps,
                       "Most robust scored grasps searched for a more robust pose (0 = all scored)")
            ->transform(countIn(0, kMaxCount))
            ->default_str(std::to_string(fallback.refine_grasps))
            ->group(kRankingDetails);
    cmd.add_option("--robust-refine-below-r", search_below_r,
                   fmt::format("Only scored grasps whose r is below this are searched (1 = all "
                               "but those that held in every sample, 0 = none; default: the "
                               "hand's ranking budget, else {})",
                               ranking::kDefaultSearchBelowR))
        ->check(finiteIn(0, 1))
        ->group(kRankingDetails);
    auto* evaluations_option =
        cmd.add_option("--robust-refine-evaluations", evaluations,
                       "Poses tried near each scored grasp in the search for a more robust one")
            ->transform(countIn(0, kMaxRankingSamples))
            ->default_str(std::to_string(fallback.refine_evaluations))
            ->group(kRankingDetails);
    auto* samples_option = cmd.add_option("--robust-refine-samples", samples,
                                          "Perturbed executions per pose in that search")
                               ->transform(countIn(1, kMaxRankingSamples))
                               ->default_str(std::to_string(fallback.refine_samples))
                               ->group(kRankingDetails);
    cmd.add_option("--robust-refine-max-standoff", max_standoff_m,
                   "Farthest that search backs a grasp off (or moves it closer), in metres")
        ->check(finiteIn(0, kMaxRefineStandoffM))
        ->capture_default_str()
        ->group(kRankingDetails);
    cmd.add_option("--robust-refine-mean-shift", mean_shift_steps,
                   "Mean-shift steps after that search: the best pose moved towards where its "
                   "perturbed executions held, tilts included (0 = none)")
        ->transform(countIn(0, kMaxRankingSamples))
        ->capture_default_str()
        ->group(kRankingDetails);
    if (!presets) return;
    notePresets(grasps_option, &RankingBudgetPreset::refine_grasps);
    notePresets(evaluations_option, &RankingBudgetPreset::refine_evaluations);
    notePresets(samples_option, &RankingBudgetPreset::refine_samples);
  }

  // `preset`: the values of the counts not given.
  void applyTo(
      ranking::RobustRefinementParams& p,
      const RankingBudgetPreset& preset = rankingBudgetPreset(kDefaultRankingBudget)) const {
    p.enabled = !disabled;
    p.max_grasps = grasps.value_or(preset.refine_grasps);
    p.search_below_r = search_below_r;
    p.max_evaluations = evaluations.value_or(preset.refine_evaluations);
    p.samples = samples.value_or(preset.refine_samples);
    p.max_standoff_m = max_standoff_m;
    p.mean_shift_steps = mean_shift_steps;
  }
};

// Defaults are the library's RobustRankingParams (never a typed copy of a number). The counts a
// --ranking-budget sets are unset unless given: the preset's then (params()).
struct RobustnessOptions {
  bool disabled = !ranking::RobustRankingParams{}.enabled;
  std::string budget = kDefaultRankingBudget;
  std::optional<int> samples;  // unset: the --ranking-budget's
  std::string variant = ranking::toString(ranking::RobustRankingParams{}.robustness.variant);
  std::optional<std::size_t> top_k;      // unset: the --ranking-budget's
  std::optional<std::size_t> screen_k;   // unset: the --ranking-budget's, else the hand's
  std::optional<int> screen_samples;     // unset: the --ranking-budget's, else the hand's
  std::optional<std::string> screen_by;  // unset: the hand's ranking budget
  std::optional<int> confirm_samples;    // unset: the --ranking-budget's, else the hand's
  std::optional<double> mu;              // unset: the planner's --mu
  bool no_load_check = false;
  RobustRefineOptions refine;

  void addTo(CLI::App& cmd) {
    const auto& fallback = rankingBudgetPreset(kDefaultRankingBudget);
    std::vector<std::string> names;
    for (const auto& preset : rankingBudgetPresets()) names.emplace_back(preset.name);
    cmd.add_option("--ranking-budget", budget,
                   "How much work the robust ranking does (small: faster, thorough: slower); "
                   "sets the counts of the --robustness-* and --robust-refine-* options, which "
                   "override it (--help-all)")
        ->check(CLI::IsMember(names))
        ->capture_default_str();
    cmd.add_flag("--no-robustness", disabled,
                 "Rank by epsilon only; no robustness r on the grasps (faster)");
    notePresets(
        cmd.add_option("--robustness-samples", samples, "Perturbed executions per scored grasp")
            ->transform(countIn(1, kMaxRankingSamples))
            ->default_str(std::to_string(fallback.samples))
            ->group(kRankingDetails),
        &RankingBudgetPreset::samples);
    addRobustnessVariantOption(cmd, variant)->group(kRankingDetails);
    notePresets(cmd.add_option("--robustness-top-k", top_k,
                               "Grasps scored for robustness, the best by the screening (0 = all)")
                    ->transform(countIn(0, kMaxCount))
                    ->default_str(std::to_string(fallback.top_k))
                    ->group(kRankingDetails),
                &RankingBudgetPreset::top_k);
    notePresets(addScreenOption(cmd, screen_k)->group(kRankingDetails),
                &RankingBudgetPreset::screen_k);
    notePresets(addScreenSamplesOption(cmd, screen_samples)->group(kRankingDetails),
                &RankingBudgetPreset::screen_samples);
    addScreenByOption(cmd, screen_by)->group(kRankingDetails);
    notePresets(addConfirmSamplesOption(cmd, confirm_samples)->group(kRankingDetails),
                &RankingBudgetPreset::confirm_samples);
    // No shown default: unset means the planner's friction.
    cmd.add_option("--robustness-mu", mu, "Friction coefficient of r (default: --mu)")
        ->check(finiteIn(0, kMaxFriction))
        ->group(kRankingDetails);
    cmd.add_flag("--no-load-check", no_load_check,
                 "r counts force closure alone, not whether the grip carries the object's weight "
                 "(the paper's and reference variants never check it)")
        ->group(kRankingDetails);
    refine.addTo(cmd, true);
  }

  // `seed`: the command's --seed, which also seeds the robustness samples.
  ranking::RobustRankingParams params(std::uint64_t seed) const {
    const RankingBudgetPreset& preset = rankingBudgetPreset(budget);
    ranking::RobustRankingParams p;
    p.enabled = !disabled;
    p.top_k = top_k.value_or(preset.top_k);
    p.screen_k = screen_k ? screen_k : preset.screen_k;
    p.screen_samples = screen_samples ? screen_samples : preset.screen_samples;
    p.screen_candidates = screenCandidates(screen_by);
    p.confirm_samples = confirm_samples ? confirm_samples : preset.confirm_samples;
    p.robustness.samples = samples.value_or(preset.samples);
    p.robustness.variant = ranking::parseRobustnessVariant(variant);
    p.robustness.seed = seed;
    ranking::setLoadCheck(p.robustness, !no_load_check);
    p.friction = mu;
    refine.applyTo(p.refinement, preset);
    return p;
  }
};

}  // namespace skelgrasp::cli
