#pragma once
// Ranges of the planning and ranking requests every front end accepts: the command line's option
// checks (apps/) and the Python module both refuse values outside them, so neither runs work the
// other would refuse.
#include <cstdint>

namespace skelgrasp::ranking {

// Most perturbed executions per grasp (robustness, screening, confirmation): a million closings
// of one grasp is hours.
constexpr std::uint64_t kMaxRobustnessSamples = 1'000'000;
// Longest planning time limit, in seconds (about eleven days).
constexpr double kMaxPlanTimeoutS = 1e6;

}  // namespace skelgrasp::ranking
