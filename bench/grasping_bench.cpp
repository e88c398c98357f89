// Close + quality for one grasp of each hand on a YCB google_16k object (goal: <= 2 ms ARMAR-III
// and SDH, <= 6 ms Shadow on one core). Falls back to a generated bottle without ../shared/data.
// Run: build/bench/grasping_bench
#include <benchmark/benchmark.h>

#include <filesystem>

#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/common/primitives.h"
#include "skelgrasp/grasping/grasp_simulator.h"
#include "skelgrasp/grasping/quality.h"

namespace {

using namespace skelgrasp;
using namespace skelgrasp::grasping;

const GraspObject& benchObject() {
  static const GraspObject object = [] {
    const std::string path =
        std::string(SKELGRASP_SHARED_DATA_DIR) + "/objects/ycb/006_mustard_bottle.ply";
    return GraspObject(std::filesystem::exists(path) ? loadMesh(path)
                                                     : primitives::makeNamedShape("bottle"));
  }();
  return object;
}

// A power grasp from the side at mid-height, backed off until collision-free.
Pose sideGrasp(GraspSimulator& sim, const Preshape& preshape) {
  const auto& box = benchObject().bounds();
  Pose gcp = Pose::Identity();
  gcp.linear() = frameFromZY({-1, 0, 0}, {0, 0, 1});
  for (double d = 0; d < 0.2; d += 0.001) {
    gcp.translation() = box.center() + Eigen::Vector3d(d, 0, 0);
    const Pose hand = sim.handPoseForGcp(gcp, preshape);
    if (!sim.inCollision(hand, preshape.joints)) return hand;
  }
  return sim.handPoseForGcp(gcp, preshape);
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
