// Robustness score of one grasp with 100 perturbed samples, per hand, on one core (goal: <= 0.2 s).
// The grasp is a side power grasp on a YCB google_16k object (a generated bottle without
// ../shared/data). Run: build/bench/evaluation_bench
#include <benchmark/benchmark.h>

#include "bench_support.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/evaluation/robustness.h"

namespace {

using namespace skelgrasp;
using namespace skelgrasp::grasping;

using bench::benchObject;

// A power grasp from the side at mid-height, backed off until the open hand is clear.
Grasp sideGrasp(GraspSimulator& sim, const HandModel& hand) {
  const auto& preshape = hand.preshape("power");
  Grasp grasp;
  grasp.preshape = "power";
  grasp.hand_pose = bench::sideGraspPose(sim, preshape);
  const auto closing = sim.close(grasp.hand_pose, preshape);
  grasp.joints = closing.joints;
  grasp.contacts = closing.contacts;
  return grasp;
}

void BM_Robustness(benchmark::State& state, const std::string& hand_name,
                   evaluation::RobustnessVariant variant) {
  setLogLevel(spdlog::level::warn);
  const HandModel hand = loadBuiltinHand(hand_name);
  GraspSimulator sim(hand, benchObject());
  const Grasp grasp = sideGrasp(sim, hand);
  evaluation::RobustnessParams params;
  params.samples = 100;
  params.variant = variant;
  params.quality.torsional_friction_m = hand.closingDefaults().torsional_friction_m;
  double score = 0;
  int collisions = 0;
  for (auto _ : state) {
    const auto result = evaluation::evaluateRobustness(sim, grasp, params);
    score = result.score;
    collisions = result.collisions;
    benchmark::DoNotOptimize(result.force_closure);
  }
  // As a percentage: this Google Benchmark version prints counters below 1 wrongly.
  state.counters["r_percent"] = 100 * score;
  state.counters["colliding_samples"] = collisions;
  state.counters["contacts"] = static_cast<double>(grasp.contacts.size());
}

using evaluation::RobustnessVariant;
BENCHMARK_CAPTURE(BM_Robustness, armar3, std::string("armar3"), RobustnessVariant::kPaper)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Robustness, sdh, std::string("sdh"), RobustnessVariant::kPaper)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Robustness, shadow, std::string("shadow"), RobustnessVariant::kPaper)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Robustness, armar3_reference, std::string("armar3"),
                  RobustnessVariant::kReference)
    ->Unit(benchmark::kMillisecond);

}  // namespace
