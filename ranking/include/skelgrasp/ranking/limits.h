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
// Largest friction coefficient: above it no physical contact (rubber on rubber is about 1-2).
constexpr double kMaxFriction = 10;
// Most hand closings one re-scoring of a grasps file may run (`score`, Python score_grasps):
// grasps x (1 + frictions x robustness samples). About ten hours on one core at the 3.6 ms a
// closing of the SDH hand takes; beyond it a request is a mistake (10 000 grasps at 1000 samples)
// and is refused before any work.
constexpr std::uint64_t kMaxScoreClosings = 10'000'000;

}  // namespace skelgrasp::ranking
