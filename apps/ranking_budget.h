#pragma once
// --ranking-budget small|default|thorough: presets over the robust ranking's detailed counts
// (ranking/robust_ranking.h), so that a user chooses how much work the ranking does with one
// option instead of eight. A detailed option given on the command line overrides its preset's
// value. `default` sets nothing: the library's defaults and the hand's ranking budget, as without
// the option.
#include <array>
#include <cstddef>
#include <optional>
#include <string>

#include "skelgrasp/common/error.h"
#include "skelgrasp/ranking/robust_ranking.h"

namespace skelgrasp::cli {

// What a preset sets. Unset (std::nullopt): left to the hand's ranking budget
// (grasping::RankingBudget), else the library's default.
struct RankingBudgetPreset {
  const char* name;
  std::size_t top_k;                    // --robustness-top-k: grasps scored
  int samples;                          // --robustness-samples: per scored grasp
  std::optional<std::size_t> screen_k;  // --robustness-screen: grasps screened
  std::optional<int> screen_samples;    // --robustness-screen-samples: per screened grasp
  std::optional<int> confirm_samples;   // --robustness-confirm-samples: per confirmed grasp
  std::size_t refine_grasps;            // --robust-refine-grasps: scored grasps searched
  int refine_evaluations;               // --robust-refine-evaluations: poses per search
  int refine_samples;                   // --robust-refine-samples: per pose of a search
};

// The presets, in the order --help names them. small halves the grasps and samples of default
// and drops the confirmation; thorough doubles them.
//
//   preset    top-k samples screen screen-samples confirm refine-grasps refine-evals refine-samples
//   small         5     25     30              5       0             5            2             12
//   default      10     50  hand's         hand's  hand's           10            4             12
//   thorough     20    100    120             20      20            20            8             24
//
// (hand's: the hand's ranking budget, else 60 screened with 10 samples, 10 confirming samples.)
inline const std::array<RankingBudgetPreset, 3>& rankingBudgetPresets() {
  static const ranking::RobustRankingParams library;
  static const std::array<RankingBudgetPreset, 3> presets = {{
      {"small", 5, 25, 30, 5, 0, 5, 2, 12},
      {"default", library.top_k, library.robustness.samples, std::nullopt, std::nullopt,
       std::nullopt, library.refinement.max_grasps, library.refinement.max_evaluations,
       library.refinement.samples},
      {"thorough", 20, 100, 120, 20, 20, 20, 8, 24},
  }};
  return presets;
}

inline constexpr const char* kDefaultRankingBudget = "default";

// Throws InvalidArgument for an unknown name (the option's check refuses it first).
inline const RankingBudgetPreset& rankingBudgetPreset(const std::string& name) {
  for (const auto& preset : rankingBudgetPresets()) {
    if (name == preset.name) return preset;
  }
  throw InvalidArgument("unknown ranking budget '" + name +
                        "' (expected small, default or thorough)");
}

}  // namespace skelgrasp::cli
