// Close + quality for one grasp of each hand on a YCB google_16k object (goal: <= 2 ms ARMAR-III
// and SDH, <= 6 ms Shadow on one core). Falls back to a generated bottle without ../shared/data.
// Run: build/bench/grasping_bench
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>

#include <time.h>

#include "bench_support.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/grasping/quality/quality.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"

namespace {

using namespace skelgrasp;
using namespace skelgrasp::grasping;

using bench::benchObject;

Pose sideGrasp(GraspSimulator& sim, const Preshape& preshape) {
  return bench::sideGraspPose(sim, preshape);
}

// The contacts of the hand closed from the side of the bench object in `preshape_name`: the fixed
// grasp the quality benchmarks judge.
std::vector<Contact> sideGraspContacts(const HandModel& hand, const std::string& preshape_name) {
  GraspSimulator sim(hand, benchObject());
  const auto& preshape = hand.preshape(preshape_name);
  return sim.close(sideGrasp(sim, preshape), preshape).contacts;
}

void BM_CloseAndQuality(benchmark::State& state, const std::string& hand_name) {
  setLogLevel(spdlog::level::warn);
  const HandModel hand = loadBuiltinHand(hand_name);
  GraspSimulator sim(hand, benchObject());
  const auto& preshape = hand.preshape("power");
  const Pose pose = sideGrasp(sim, preshape);
  const QualityParams params = withHandContactModel({}, hand);
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
  const auto contacts = sideGraspContacts(loadBuiltinHand(hand_name), "power");
  for (auto _ : state) benchmark::DoNotOptimize(evaluateGrasp(contacts, benchObject()));
}
// What a closing needs once per object: the FCL collision tree (the OBBRSS tree for distances is
// built on first use) and, with argument 1, the distance field of the fast closing.
void BM_GraspObjectSetup(benchmark::State& state) {
  setLogLevel(spdlog::level::warn);
  const TriangleMesh& mesh = benchObject().mesh();
  for (auto _ : state) {
    const GraspObject object(mesh);
    if (state.range(0)) benchmark::DoNotOptimize(&object.distanceField());
  }
  state.counters["triangles"] = static_cast<double>(mesh.faces.size());
}
BENCHMARK(BM_GraspObjectSetup)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

BENCHMARK_CAPTURE(BM_CloseOnly, armar3, std::string("armar3"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CloseOnly, shadow, std::string("shadow"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_QualityOnly, armar3, std::string("armar3"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_QualityOnly, shadow, std::string("shadow"))->Unit(benchmark::kMillisecond);
}  // namespace

namespace {
// Thread CPU time in seconds: unlike wall time it does not grow when other processes share the
// core, so the two sides below stay comparable on a busy machine.
double threadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Force-closure verdict only (as a robustness sample needs it), LP against hull, on the same
// closed grasp in one loop: counters hull_ms, lp_ms (mean thread CPU time per call) and their
// ratio hull_over_lp.
void BM_ForceClosureLpVsHull(benchmark::State& state, const std::string& hand_name,
                             const std::string& preshape_name) {
  setLogLevel(spdlog::level::warn);
  const HandModel hand = loadBuiltinHand(hand_name);
  const auto contacts = sideGraspContacts(hand, preshape_name);
  QualityParams hull_params = withHandContactModel({}, hand);
  hull_params.compute_volume = false;
  hull_params.compute_epsilon = false;
  QualityParams lp_params = hull_params;
  hull_params.fc_test = ForceClosureTest::kHull;
  lp_params.fc_test = ForceClosureTest::kLp;
  double hull_s = 0, lp_s = 0;
  bool hull_closure = false, lp_closure = false;
  int wrenches = 0;
  for (auto _ : state) {
    const double t0 = threadCpuSeconds();
    const auto hull = evaluateGrasp(contacts, benchObject(), hull_params);
    const double t1 = threadCpuSeconds();
    const auto lp = evaluateGrasp(contacts, benchObject(), lp_params);
    const double t2 = threadCpuSeconds();
    hull_s += t1 - t0;
    lp_s += t2 - t1;
    hull_closure = hull.force_closure;
    lp_closure = lp.force_closure;
    wrenches = lp.wrenches;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["hull_ms"] = 1e3 * hull_s / n;
  state.counters["lp_ms"] = 1e3 * lp_s / n;
  state.counters["hull_over_lp"] = lp_s > 0 ? hull_s / lp_s : 0;
  state.counters["wrenches"] = wrenches;
  state.counters["closure_hull"] = hull_closure;
  state.counters["closure_lp"] = lp_closure;
}
#define SKELGRASP_FC_BENCH(hand)                                                   \
  BENCHMARK_CAPTURE(BM_ForceClosureLpVsHull, hand##_power, std::string(#hand),     \
                    std::string("power"))                                          \
      ->Unit(benchmark::kMillisecond);                                             \
  BENCHMARK_CAPTURE(BM_ForceClosureLpVsHull, hand##_precision, std::string(#hand), \
                    std::string("precision"))                                      \
      ->Unit(benchmark::kMillisecond)
SKELGRASP_FC_BENCH(armar3);
SKELGRASP_FC_BENCH(sdh);
SKELGRASP_FC_BENCH(shadow);
SKELGRASP_FC_BENCH(parallel_gripper);

// Epsilon of one closed grasp three ways in one loop (thread CPU time per call): the whole hull
// (kHull), the whole hull with its volume (kLp + compute_volume)
// and by expansion (kLp, the default). Counters *_ms, whole_over_expansion,
// volume_over_expansion, and the largest epsilon difference seen (epsilon_gap). Only a closure
// grasp (counter closure = 1) builds hulls on the kLp paths; on the bench object that is
// ARMAR-III's.
void BM_EpsilonByExpansion(benchmark::State& state, const std::string& hand_name) {
  setLogLevel(spdlog::level::warn);
  const HandModel hand = loadBuiltinHand(hand_name);
  const auto contacts = sideGraspContacts(hand, "power");
  const QualityParams expansion = withHandContactModel({}, hand);
  QualityParams whole = expansion, with_volume = expansion;
  whole.fc_test = ForceClosureTest::kHull;
  with_volume.compute_volume = true;
  double whole_s = 0, volume_s = 0, expansion_s = 0, gap = 0;
  bool closure = false;
  for (auto _ : state) {
    const double t0 = threadCpuSeconds();
    const auto a = evaluateGrasp(contacts, benchObject(), whole);
    const double t1 = threadCpuSeconds();
    const auto b = evaluateGrasp(contacts, benchObject(), with_volume);
    const double t2 = threadCpuSeconds();
    const auto c = evaluateGrasp(contacts, benchObject(), expansion);
    const double t3 = threadCpuSeconds();
    whole_s += t1 - t0;
    volume_s += t2 - t1;
    expansion_s += t3 - t2;
    gap = std::max({gap, std::abs(a.epsilon - c.epsilon), std::abs(b.epsilon - c.epsilon)});
    closure = c.force_closure;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["whole_ms"] = 1e3 * whole_s / n;
  state.counters["volume_ms"] = 1e3 * volume_s / n;
  state.counters["expansion_ms"] = 1e3 * expansion_s / n;
  state.counters["whole_over_expansion"] = expansion_s > 0 ? whole_s / expansion_s : 0;
  state.counters["volume_over_expansion"] = expansion_s > 0 ? volume_s / expansion_s : 0;
  state.counters["epsilon_gap"] = gap;
  state.counters["closure"] = closure;
}
BENCHMARK_CAPTURE(BM_EpsilonByExpansion, armar3, std::string("armar3"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EpsilonByExpansion, sdh, std::string("sdh"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EpsilonByExpansion, shadow, std::string("shadow"))
    ->Unit(benchmark::kMillisecond);
}  // namespace
