#pragma once
// A planner's hypotheses closed on every core of the task arena, taken in the order one thread
// would take them (docs/planning.md, "Threads").
#include <cstddef>
#include <functional>

#include "skelgrasp/common/logging.h"
#include "skelgrasp/grasping/planning/hypothesis.h"

namespace skelgrasp::grasping::internal {

struct OrderedHypotheses {
  // Hypotheses 0..count-1; the planner stops earlier through `stop`.
  std::size_t count = 0;
  // Called on the calling thread before hypotheses [first, end) are evaluated (a planner that
  // draws its poses from a random stream draws them here, in order). May be empty.
  std::function<void(std::size_t first, std::size_t end)> prepare;
  // The outcome of hypothesis i, closed with the calling thread's own simulator. Must depend on i
  // only (not on which simulator closed what before), so that the plan is the same on any number
  // of threads.
  std::function<HypothesisOutcome(GraspSimulator& simulator, std::size_t i)> evaluate;
  // Asked on the calling thread before each hypothesis is taken, as a one-thread loop asks before
  // each hypothesis: true ends the plan (time or grasp limit reached).
  std::function<bool()> stop;
  // Counts and keeps hypothesis i's outcome, on the calling thread, in index order.
  std::function<void(std::size_t i, HypothesisOutcome&& outcome)> take;
};

// A plan's limits, as every planner asks them before each hypothesis: true once `timeout_s` has
// passed on `watch` or `result` holds `max_grasps` grasps (0 = no limit), each recorded in the
// summary (timed_out, max_grasps_reached).
bool planLimitReached(const Stopwatch& watch, double timeout_s, std::size_t max_grasps,
                      PlanResult& result);

// Runs `run` over its hypotheses. With more than one thread in the current task arena they are
// evaluated a chunk at a time (kHypothesesPerThread per thread) by one GraspSimulator per thread,
// and taken in order once the chunk is done: a stop wastes at most the rest of a chunk. With one
// thread each hypothesis is evaluated just before it is taken, exactly the sequential loop.
void evaluateInOrder(const HandModel& hand, const GraspObject& object,
                     const OrderedHypotheses& run);

}  // namespace skelgrasp::grasping::internal
