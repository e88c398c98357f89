// Skeleton stage timings: regularisation and contraction on generated shapes and on a YCB mesh.
// Run: build/bench/skeleton_bench [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <filesystem>

#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/common/primitives.h"
#include "skelgrasp/skeleton/extraction.h"

namespace {

using namespace skelgrasp;

TriangleMesh ycbMug() {
  const std::string path = std::string(SKELGRASP_SHARED_DATA_DIR) + "/objects/ycb/025_mug.ply";
  return std::filesystem::exists(path) ? loadMesh(path) : TriangleMesh{};
}

void BM_Regularise(benchmark::State& state, const std::string& shape) {
  setLogLevel(spdlog::level::warn);
  const TriangleMesh mesh = shape == "ycb_mug" ? ycbMug() : primitives::makeNamedShape(shape);
  if (mesh.empty()) {
    state.SkipWithError("../shared/data not found");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(geometry::regularise(mesh));
}

void BM_Contract(benchmark::State& state, const std::string& shape) {
  setLogLevel(spdlog::level::warn);
  const TriangleMesh mesh = shape == "ycb_mug" ? ycbMug() : primitives::makeNamedShape(shape);
  if (mesh.empty()) {
    state.SkipWithError("../shared/data not found");
    return;
  }
  const TriangleMesh closed = geometry::regularise(mesh).mesh;
  for (auto _ : state) benchmark::DoNotOptimize(skeleton::contractMesh(closed));
  state.counters["mesh_vertices"] = static_cast<double>(closed.numVertices());
}

BENCHMARK_CAPTURE(BM_Regularise, mug, std::string("mug"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Regularise, hammer, std::string("hammer"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Regularise, ycb_mug, std::string("ycb_mug"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Contract, mug, std::string("mug"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Contract, hammer, std::string("hammer"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Contract, ycb_mug, std::string("ycb_mug"))->Unit(benchmark::kMillisecond);

}  // namespace
