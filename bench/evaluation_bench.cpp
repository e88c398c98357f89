// Robustness score of one grasp with 100 perturbed samples, per hand, on one core (goal: <= 0.2 s).
// The grasp is a side power grasp on a YCB google_16k object (a generated bottle without
// ../shared/data). Run: build/bench/evaluation_bench
#include <benchmark/benchmark.h>

#include <filesystem>

#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/common/primitives.h"
#include "skelgrasp/evaluation/robustness.h"

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

// A power grasp from the side at mid-height, backed off until the open hand is clear.
Grasp sideGrasp(GraspSimulator& sim, const HandModel& hand) {
  const auto& preshape = hand.preshape("power");
  const auto& box = benchObject().bounds();
  Pose gcp = Pose::Identity();
  gcp.linear() = frameFromZY({-1, 0, 0}, {0, 0, 1});
  Grasp grasp;
  grasp.preshape = "power";
  for (double d = 0; d < 0.2; d += 0.001) {
    gcp.translation() = box.center() + Eigen::Vector3d(d, 0, 0);
    grasp.hand_pose = sim.handPoseForGcp(gcp, preshape);
    if (!sim.inCollision(grasp.hand_pose, preshape.joints)) break;
  }
  grasp.gcp_pose = gcp;
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
