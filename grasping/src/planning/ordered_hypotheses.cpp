// Parallel hypothesis evaluation with a sequential, ordered take (ordered_hypotheses.h).
#include "ordered_hypotheses.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <memory>
#include <vector>

namespace skelgrasp::grasping::internal {
namespace {

// Hypotheses per thread in a chunk. A hypothesis takes 0.5-5 ms to close and judge, so a chunk of
// 8 per thread keeps the threads busy past the slow ones, and a stop (time or grasp limit)
// discards at most a few tens of milliseconds of work.
constexpr std::size_t kHypothesesPerThread = 8;

}  // namespace

bool planLimitReached(const Stopwatch& watch, double timeout_s, std::size_t max_grasps,
                      PlanResult& result) {
  PlanSummary& summary = result.summary;
  if (timeout_s > 0 && watch.seconds() > timeout_s) summary.timed_out = true;
  if (max_grasps > 0 && result.grasps.size() >= max_grasps) summary.max_grasps_reached = true;
  return summary.timed_out || summary.max_grasps_reached;
}

void evaluateInOrder(const HandModel& hand, const GraspObject& object,
                     const OrderedHypotheses& run) {
  const int threads = tbb::this_task_arena::max_concurrency();
  if (threads <= 1) {
    GraspSimulator simulator(hand, object);
    for (std::size_t i = 0; i < run.count; ++i) {
      if (run.stop()) return;
      if (run.prepare) run.prepare(i, i + 1);
      run.take(i, run.evaluate(simulator, i));
    }
    return;
  }
  // A simulator moves its hand's collision objects: one per thread, sharing hand and object.
  tbb::enumerable_thread_specific<std::unique_ptr<GraspSimulator>> simulators(
      [&] { return std::make_unique<GraspSimulator>(hand, object); });
  const std::size_t chunk = kHypothesesPerThread * static_cast<std::size_t>(threads);
  std::vector<HypothesisOutcome> outcomes;
  for (std::size_t first = 0; first < run.count; first += chunk) {
    if (run.stop()) return;
    const std::size_t end = first + std::min(chunk, run.count - first);
    if (run.prepare) run.prepare(first, end);
    outcomes.assign(end - first, HypothesisOutcome{});
    tbb::parallel_for(first, end, std::size_t{1}, [&](std::size_t i) {
      outcomes[i - first] = run.evaluate(*simulators.local(), i);
    });
    for (std::size_t i = first; i < end; ++i) {
      if (i > first && run.stop()) return;
      run.take(i, std::move(outcomes[i - first]));
    }
  }
}

}  // namespace skelgrasp::grasping::internal
