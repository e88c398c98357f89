// Scan -> closed object mesh, stage by stage, on the PCL mug scene (307200 points, stereo) and on a
// rendered table top (no data needed). One thread throughout; the goal is <= 1.5 s per scan.
// Run: build/bench/reconstruction_bench [--benchmark_filter=...]; per-stage rows for any input:
// skelgrasp bench reconstruct INPUT...
#include <benchmark/benchmark.h>

#include <filesystem>

#include "skelgrasp/common/logging.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/perception/cloud_io.h"
#include "skelgrasp/perception/depth_camera.h"
#include "skelgrasp/pipeline/reconstruct_scan.h"

namespace {

using namespace skelgrasp;

const std::string kMugScene =
    std::string(SKELGRASP_SHARED_DATA_DIR) + "/scans/pcd/pcl_table_scene_mug_stereo_textured.pcd";

perception::Scan scanOf(const std::string& input) {
  perception::Scan scan;
  if (input == "rendered") {
    TriangleMesh table = geometry::shapes::makeBox({1.0, 0.8, 0.04}, 4);
    table.transform(Pose(Eigen::Translation3d(0, 0, -0.02)));
    TriangleMesh mug = geometry::shapes::makeNamedShape("mug");
    scan.cloud =
        perception::renderDepth({table, mug}, perception::lookAt({0.55, 0.05, 0.6}, {0, 0, 0.05}))
            .cloud;
  } else if (std::filesystem::exists(input)) {
    scan.cloud = perception::loadPointCloud(input);
  }
  return scan;
}

pipeline::ReconstructionParams oneThread() {
  pipeline::ReconstructionParams p;
  p.ingest.normals.threads = 1;
  p.meshing.poisson.threads = 1;
  return p;
}

void BM_LoadPcd(benchmark::State& state) {
  setLogLevel(spdlog::level::warn);
  if (!std::filesystem::exists(kMugScene)) return state.SkipWithError("../shared/data not found");
  for (auto _ : state) benchmark::DoNotOptimize(perception::loadPointCloud(kMugScene));
}

void BM_Ingest(benchmark::State& state, const std::string& input) {
  setLogLevel(spdlog::level::warn);
  const perception::Scan scan = scanOf(input == "mug_scene" ? kMugScene : input);
  if (scan.cloud.empty()) return state.SkipWithError("../shared/data not found");
  const auto params = oneThread();
  for (auto _ : state) benchmark::DoNotOptimize(perception::ingestScan(scan, params.ingest));
}

void BM_Reconstruct(benchmark::State& state, const std::string& input) {
  setLogLevel(spdlog::level::warn);
  const perception::Scan scan = scanOf(input == "mug_scene" ? kMugScene : input);
  if (scan.cloud.empty()) return state.SkipWithError("../shared/data not found");
  const auto params = oneThread();
  pipeline::ReconstructionResult last;
  for (auto _ : state) last = pipeline::reconstructScan(scan, params);
  if (!last.status.ok()) return state.SkipWithError(last.status.message.c_str());
  const auto& m = last.objects.at(0).meshing.report;
  state.counters["filters_s"] = last.ingest.filter_time_s;
  state.counters["scene_s"] = last.ingest.scene_time_s;
  state.counters["poisson_s"] = m.poisson_s;
  state.counters["regularise_s"] = m.regularise_s;
  state.counters["mesh_vertices"] = static_cast<double>(m.vertices);
}

BENCHMARK(BM_LoadPcd)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ingest, mug_scene, std::string("mug_scene"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ingest, rendered, std::string("rendered"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Reconstruct, mug_scene, std::string("mug_scene"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Reconstruct, rendered, std::string("rendered"))->Unit(benchmark::kMillisecond);

}  // namespace
