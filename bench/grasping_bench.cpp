// Close + quality for one grasp of each hand on a YCB google_16k object (goal: <= 2 ms ARMAR-III
// and SDH, <= 6 ms Shadow on one core). Falls back to a generated bottle without ../shared/data.
// Run: build/bench/grasping_bench
#include <benchmark/benchmark.h>

#include "bench_support.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/grasping/grasp_simulator.h"
#include "skelgrasp/grasping/quality.h"

namespace {

using namespace skelgrasp;
using namespace skelgrasp::grasping;

using bench::benchObject;

Pose sideGrasp(GraspSimulator& sim, const Preshape& preshape) {
  return bench::sideGraspPose(sim, preshape);
}

void BM_CloseAndQuality(benchmark::State& state, const std::string& hand_name) {
  setLogLevel(spdlog::level::warn);
  const HandModel hand = loadBuiltinHand(hand_name);
  GraspSimulator sim(hand, benchObject());
  const auto& preshape = hand.preshape("power");
  const Pose pose = sideGrasp(sim, preshape);
  QualityParams params;
  params.torsional_friction_m = hand.closingDefaults().torsional_friction_m;
  std::size_t contacts = 0, closures = 0;
  for (auto _ : state) {
    const auto closing = sim.close(pose, preshape);
    const auto quality = evaluateGrasp(closing.contacts, benchObject(), params);
    contacts = closing.contacts.size();
    closures += quality.force_closure;
    benchmark::DoNotOptimize(quality.epsilon);
  }
  state.counters["contacts"] = static_cast<double>(contacts);
  state.counters["force_closure"] =
      static_cast<double>(closures) / static_cast<double>(state.iterations());
}

BENCHMARK_CAPTURE(BM_CloseAndQuality, armar3, std::string("armar3"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CloseAndQuality, sdh, std::string("sdh"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CloseAndQuality, shadow, std::string("shadow"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CloseAndQuality, parallel_gripper, std::string("parallel_gripper"))
    ->Unit(benchmark::kMillisecond);

}  // namespace

namespace {
void BM_CloseOnly(benchmark::State& state, const std::string& hand_name) {
  setLogLevel(spdlog::level::warn);
  const HandModel hand = loadBuiltinHand(hand_name);
  GraspSimulator sim(hand, benchObject());
  const auto& preshape = hand.preshape("power");
  const Pose pose = sideGrasp(sim, preshape);
  std::size_t queries = 0;
  for (auto _ : state) {
    const std::size_t before = sim.collisionQueries();
    benchmark::DoNotOptimize(sim.close(pose, preshape));
    queries = sim.collisionQueries() - before;
  }
  state.counters["fcl_queries"] = static_cast<double>(queries);
}
void BM_QualityOnly(benchmark::State& state, const std::string& hand_name) {
  setLogLevel(spdlog::level::warn);
  const HandModel hand = loadBuiltinHand(hand_name);
  GraspSimulator sim(hand, benchObject());
  const auto& preshape = hand.preshape("power");
  const auto closing = sim.close(sideGrasp(sim, preshape), preshape);
  for (auto _ : state) benchmark::DoNotOptimize(evaluateGrasp(closing.contacts, benchObject()));
}
BENCHMARK_CAPTURE(BM_CloseOnly, armar3, std::string("armar3"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CloseOnly, shadow, std::string("shadow"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_QualityOnly, armar3, std::string("armar3"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_QualityOnly, shadow, std::string("shadow"))->Unit(benchmark::kMillisecond);
}  // namespace
