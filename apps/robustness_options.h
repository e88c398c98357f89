#pragma once
// Robust ranking options (ranking/robust_ranking.h), shared by the commands that plan and rank
// (plan, run, demo, bench run).
#include <CLI/CLI.hpp>

#include <fmt/format.h>

#include <optional>
#include <string>

#include "option_checks.h"
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

// Refinement for robustness (ranking/robust_refinement.h), the same on every command that ranks.
struct RobustRefineOptions {
  bool disabled = !ranking::RobustRefinementParams{}.enabled;
  std::size_t grasps = ranking::RobustRefinementParams{}.max_grasps;
  std::optional<double> search_below_r;  // unset: the hand's ranking budget
  int evaluations = ranking::RobustRefinementParams{}.max_evaluations;
  int samples = ranking::RobustRefinementParams{}.samples;
  double max_standoff_m = ranking::RobustRefinementParams{}.max_standoff_m;
  int mean_shift_steps = ranking::RobustRefinementParams{}.mean_shift_steps;

  void addTo(CLI::App& cmd) {
    cmd.add_flag("--no-robust-refine", disabled,
                 "Return the planner's poses: no search for a more robust pose near each scored "
                 "grasp");
    cmd.add_option("--robust-refine-grasps", grasps,
                   "Most robust scored grasps searched for a more robust pose (0 = all scored)")
        ->transform(countIn(0, kMaxCount))
        ->capture_default_str();
    cmd.add_option("--robust-refine-below-r", search_below_r,
                   fmt::format("Only scored grasps whose r is below this are searched (1 = all "
                               "but those that held in every sample, 0 = none; default: the "
                               "hand's ranking budget, else {})",
                               ranking::kDefaultSearchBelowR))
        ->check(finiteIn(0, 1));
    cmd.add_option("--robust-refine-evaluations", evaluations,
                   "Poses tried near each scored grasp in the search for a more robust one")
        ->transform(countIn(0, kMaxRankingSamples))
        ->capture_default_str();
    cmd.add_option("--robust-refine-samples", samples,
                   "Perturbed executions per pose in that search")
        ->transform(countIn(1, kMaxRankingSamples))
        ->capture_default_str();
    cmd.add_option("--robust-refine-max-standoff", max_standoff_m,
                   "Farthest that search backs a grasp off (or moves it closer), in metres")
        ->check(finiteIn(0, kMaxRefineStandoffM))
        ->capture_default_str();
    cmd.add_option("--robust-refine-mean-shift", mean_shift_steps,
                   "Mean-shift steps after that search: the best pose moved towards where its "
                   "perturbed executions held, tilts included (0 = none)")
        ->transform(countIn(0, kMaxRankingSamples))
        ->capture_default_str();
  }

  void applyTo(ranking::RobustRefinementParams& p) const {
    p.enabled = !disabled;
    p.max_grasps = grasps;
    p.search_below_r = search_below_r;
    p.max_evaluations = evaluations;
    p.samples = samples;
    p.max_standoff_m = max_standoff_m;
    p.mean_shift_steps = mean_shift_steps;
  }
};

// Defaults are the library's RobustRankingParams (never a typed copy of a number).
struct RobustnessOptions {
  bool disabled = !ranking::RobustRankingParams{}.enabled;
  int samples = ranking::RobustRankingParams{}.robustness.samples;
  std::string variant = ranking::toString(ranking::RobustRankingParams{}.robustness.variant);
  std::size_t top_k = ranking::RobustRankingParams{}.top_k;
  std::optional<std::size_t> screen_k;   // unset: the hand's ranking budget
  std::optional<int> screen_samples;     // unset: the hand's ranking budget
  std::optional<std::string> screen_by;  // unset: the hand's ranking budget
  std::optional<int> confirm_samples;    // unset: the hand's ranking budget
  std::optional<double> mu;              // unset: the planner's --mu
  bool no_load_check = false;
  RobustRefineOptions refine;

  void addTo(CLI::App& cmd) {
    cmd.add_flag("--no-robustness", disabled,
                 "Rank by epsilon only; no robustness r on the grasps (faster)");
    cmd.add_option("--robustness-samples", samples, "Perturbed executions per scored grasp")
        ->transform(countIn(1, kMaxRankingSamples))
        ->capture_default_str();
    addRobustnessVariantOption(cmd, variant);
    cmd.add_option("--robustness-top-k", top_k,
                   "Grasps scored for robustness, the best by the screening (0 = all)")
        ->transform(countIn(0, kMaxCount))
        ->capture_default_str();
    addScreenOption(cmd, screen_k);
    addScreenSamplesOption(cmd, screen_samples);
    addScreenByOption(cmd, screen_by);
    addConfirmSamplesOption(cmd, confirm_samples);
    // No shown default: unset means the planner's friction.
    cmd.add_option("--robustness-mu", mu, "Friction coefficient of r (default: --mu)")
        ->check(finiteIn(0, kMaxFriction));
    cmd.add_flag("--no-load-check", no_load_check,
                 "r counts force closure alone, not whether the grip carries the object's weight "
                 "(the paper's and reference variants never check it)");
    refine.addTo(cmd);
  }

  // `seed`: the command's --seed, which also seeds the robustness samples.
  ranking::RobustRankingParams params(std::uint64_t seed) const {
    ranking::RobustRankingParams p;
    p.enabled = !disabled;
    p.top_k = top_k;
    p.screen_k = screen_k;
    p.screen_samples = screen_samples;
    p.screen_candidates = screenCandidates(screen_by);
    p.confirm_samples = confirm_samples;
    p.robustness.samples = samples;
    p.robustness.variant = ranking::parseRobustnessVariant(variant);
    p.robustness.seed = seed;
    ranking::setLoadCheck(p.robustness, !no_load_check);
    p.friction = mu;
    refine.applyTo(p.refinement);
    return p;
  }
};

}  // namespace skelgrasp::cli
