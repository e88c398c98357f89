// Skeleton stage timings: regularisation and contraction on generated shapes and on a YCB mesh;
// the skeleton of a dense Poisson mesh with and without simplification first (run's setting); the
// stage's former and current defaults on YCB scans.
// Run: build/bench/skeleton_bench [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <filesystem>
#include <vector>

#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/skeleton/extraction.h"

namespace {

using namespace skelgrasp;

TriangleMesh ycbMug() {
  const std::string path = std::string(SKELGRASP_SHARED_DATA_DIR) + "/objects/ycb/025_mug.ply";
  return std::filesystem::exists(path) ? loadMesh(path) : TriangleMesh{};
}

void BM_Regularise(benchmark::State& state, const std::string& shape) {
  setLogLevel(spdlog::level::warn);
  const TriangleMesh mesh = shape == "ycb_mug" ? ycbMug() : geometry::shapes::makeNamedShape(shape);
  if (mesh.empty()) {
    state.SkipWithError("../shared/data not found");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(geometry::regularise(mesh));
}

void BM_Contract(benchmark::State& state, const std::string& shape) {
  setLogLevel(spdlog::level::warn);
  const TriangleMesh mesh = shape == "ycb_mug" ? ycbMug() : geometry::shapes::makeNamedShape(shape);
  if (mesh.empty()) {
    state.SkipWithError("../shared/data not found");
    return;
  }
  const TriangleMesh closed = geometry::regularise(mesh).mesh;
  for (auto _ : state) benchmark::DoNotOptimize(skeleton::contractMesh(closed));
  state.counters["mesh_vertices"] = static_cast<double>(closed.numVertices());
}

// Runs the old and the new skeleton parameters alternately on the same meshes, so that both face
// the same machine load; the iteration time is the new path's, counters give both and their ratio.
void compareSkeletonPaths(benchmark::State& state, const std::vector<TriangleMesh>& meshes,
                          const skeleton::SkeletonParams& old_path,
                          const skeleton::SkeletonParams& new_path) {
  double old_s = 0, new_s = 0;
  for (auto _ : state) {
    double seconds = 0;
    for (const TriangleMesh& mesh : meshes) {
      Stopwatch watch;
      benchmark::DoNotOptimize(skeleton::extractSkeleton(mesh, old_path));
      old_s += watch.seconds();
      watch.restart();
      benchmark::DoNotOptimize(skeleton::extractSkeleton(mesh, new_path));
      seconds += watch.seconds();
    }
    new_s += seconds;
    state.SetIterationTime(seconds);
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["old_ms"] = 1000 * old_s / n;
  state.counters["new_ms"] = 1000 * new_s / n;
  state.counters["old_over_new"] = old_s / new_s;
}

// The old path (the mesh as it is) and the new (simplified to run's 2000 vertices) on the paper's
// 14.5k-vertex Poisson mesh of a Pringles can (like a scan object's mesh).
void BM_DenseMeshSkeleton(benchmark::State& state) {
  setLogLevel(spdlog::level::warn);
  const std::string path = std::string(SKELGRASP_SHARED_DATA_DIR) +
                           "/objects/ycb_poisson_simox/pringles-poisson_mesh2.stl";
  if (!std::filesystem::exists(path)) {
    state.SkipWithError("../shared/data not found");
    return;
  }
  const TriangleMesh mesh = loadMesh(path);
  skeleton::SkeletonParams old_path;
  old_path.regularisation.method = geometry::RegularisationMethod::kAuto;
  old_path.regularisation.max_vertices = std::nullopt;
  skeleton::SkeletonParams new_path = old_path;
  new_path.regularisation.max_vertices = skeleton::kDefaultContractionVertices;  // run's budget
  compareSkeletonPaths(state, {mesh}, old_path, new_path);
  state.counters["mesh_vertices"] = static_cast<double>(mesh.numVertices());
}

// The skeleton stage's former default (every mesh alpha-wrapped, no budget) and the current one
// (a clean dense mesh as it is, the others wrapped, either simplified to 2000 vertices), in one
// process, on YCB scans of both kinds: the lemon, banana and spatula are used as they are, the mug,
// drill and master chef can wrapped.
void BM_YcbSkeletonDefault(benchmark::State& state) {
  setLogLevel(spdlog::level::warn);
  std::vector<TriangleMesh> meshes;
  for (const char* name : {"014_lemon", "011_banana", "033_spatula", "025_mug", "035_power_drill",
                           "002_master_chef_can"}) {
    const std::string path =
        std::string(SKELGRASP_SHARED_DATA_DIR) + "/objects/ycb/" + name + ".ply";
    if (!std::filesystem::exists(path)) {
      state.SkipWithError("../shared/data not found");
      return;
    }
    meshes.push_back(loadMesh(path));
  }
  skeleton::SkeletonParams old_path;
  old_path.regularisation.method = geometry::RegularisationMethod::kAlphaWrap;
  old_path.regularisation.max_vertices = std::nullopt;
  compareSkeletonPaths(state, meshes, old_path, skeleton::SkeletonParams{});
}

BENCHMARK(BM_DenseMeshSkeleton)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_YcbSkeletonDefault)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK_CAPTURE(BM_Regularise, mug, std::string("mug"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Regularise, hammer, std::string("hammer"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Regularise, ycb_mug, std::string("ycb_mug"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Contract, mug, std::string("mug"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Contract, hammer, std::string("hammer"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Contract, ycb_mug, std::string("ycb_mug"))->Unit(benchmark::kMillisecond);

}  // namespace
