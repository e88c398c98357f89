#pragma once
// A deterministic compass (pattern) search over N bounded moves from a seed at all-zero moves,
// shared by the local refinements (refinement.h for the closure margin, evaluation's
// robust_refinement.h for robustness). The caller judges a candidate; the search keeps the moves
// tried, the bounds and the best moves so far.
#include <array>
#include <cstddef>
#include <vector>

namespace skelgrasp::grasping {

template <std::size_t N>
class CompassSearch {
 public:
  using Moves = std::array<double, N>;

  // Moves outside [lower, upper] (with a rounding slack, so that halved steps summing to a bound
  // count as on it) are never tried.
  CompassSearch(const Moves& lower, const Moves& upper) : lower_(lower), upper_(upper) {}

  // Tries `moves` unless out of bounds or tried before: `improves(moves)` judges them and says
  // whether they beat the best so far, which they then become. Returns that verdict.
  template <class Improves>
  bool attempt(const Moves& moves, Improves&& improves) {
    for (std::size_t m = 0; m < N; ++m) {
      if (moves[m] < lower_[m] - kBoundSlack || moves[m] > upper_[m] + kBoundSlack) return false;
    }
    for (const Moves& seen : tried_) {
      if (seen == moves) return false;
    }
    tried_.push_back(moves);
    if (!improves(moves)) return false;
    best_ = moves;
    return true;
  }

  // From the best moves, +-step on each enabled move in turn, the first improvement taken; when
  // none improves all steps are halved, at most max_halvings times. Each candidate is tried only
  // while has_budget().
  template <class HasBudget, class Improves>
  void run(Moves steps, const std::array<bool, N>& enabled, int max_halvings,
           HasBudget&& has_budget, Improves&& improves) {
    int halvings = 0;
    while (has_budget()) {
      bool improved = false;
      for (std::size_t m = 0; m < N && !improved; ++m) {
        if (!enabled[m]) continue;
        for (double sign : {1.0, -1.0}) {
          if (!has_budget()) return;
          Moves candidate = best_;
          candidate[m] += sign * steps[m];
          if (attempt(candidate, improves)) {
            improved = true;
            break;
          }
        }
      }
      if (!improved) {
        if (++halvings > max_halvings) break;
        for (double& step : steps) step *= 0.5;
      }
    }
  }

  const Moves& best() const { return best_; }

 private:
  static constexpr double kBoundSlack = 1e-12;
  Moves lower_, upper_;
  Moves best_{};
  std::vector<Moves> tried_{Moves{}};  // the seed counts as tried
};

}  // namespace skelgrasp::grasping
