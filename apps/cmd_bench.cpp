// skelgrasp bench skeleton INPUT...: per-object regularise and skeleton times and counts.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli.h"
#include "mesh_list.h"
#include "option_checks.h"
#include "output_paths.h"
#include "skeleton_options.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/geometry/mesh_query.h"

namespace skelgrasp::cli {
namespace {

struct BenchSkeletonArgs {
  std::vector<std::string> inputs;
  std::size_t limit = 0;
  std::string json_out;
  SkeletonOptions options;
};

int runBenchSkeleton(const BenchSkeletonArgs& args) {
  checkOutputFileOption(args.json_out);
  const auto files = collectMeshFiles(args.inputs);
  if (files.empty()) return fail("bench skeleton: no mesh files in the given inputs");
  const std::size_t count = args.limit > 0 ? std::min(args.limit, files.size()) : files.size();
  std::cout << fmt::format(
      "{:<44} {:>6} {:>6} {:>5} {:>4} {:>4} {:>4} {:>4} {:>5} {:>7} {:>7} {:>7} {:>7}\n", "object",
      "in_V", "reg_V", "sk_V", "br", "end", "seg", "loop", "out%", "out_mm", "reg_s", "skel_s",
      "total_s");
  nlohmann::json rows = nlohmann::json::array();
  std::vector<double> reg_times, skel_times, totals;
  ProgressReporter progress("bench skeleton", count, 10.0);
  for (std::size_t i = 0; i < count; ++i) {
    const std::string name = std::filesystem::path(files[i]).filename().string();
    try {
      const TriangleMesh mesh = loadMesh(files[i], args.options.loadOptions());
      const auto r = skeleton::extractSkeleton(mesh, args.options.params());
      if (!r.status.ok()) {
        std::cout << fmt::format("{:<44} failed: {}\n", name, r.status.message);
        rows.push_back(
            {{"object", name}, {"status", toString(r.status.code)}, {"message", r.status.message}});
        continue;
      }
      const auto& s = r.skeleton;
      const double total = r.timing.regularise_s + r.timing.skeleton_s;
      reg_times.push_back(r.timing.regularise_s);
      skel_times.push_back(r.timing.skeleton_s);
      totals.push_back(total);
      // Skeleton quality: vertices outside the regularised mesh and how far.
      const geometry::MeshQuery query(r.regularised_mesh);
      std::size_t outside = 0;
      double max_outside = 0;
      for (const auto& v : s.vertices) {
        if (!query.contains(v.position)) {
          ++outside;
          max_outside = std::max(max_outside, query.distance(v.position));
        }
      }
      const double outside_pct = 100.0 * outside / std::max<std::size_t>(1, s.vertices.size());
      std::cout << fmt::format(
          "{:<44} {:>6} {:>6} {:>5} {:>4} {:>4} {:>4} {:>4} {:>5.1f} {:>7.2f} {:>7.3f} {:>7.3f} "
          "{:>7.3f}\n",
          name, mesh.numVertices(), r.regularised_mesh.numVertices(), s.vertices.size(),
          s.countType(skeleton::VertexType::kBranch), s.countType(skeleton::VertexType::kEndpoint),
          s.segments.size(), s.cycleRank(), outside_pct, 1000 * max_outside, r.timing.regularise_s,
          r.timing.skeleton_s, total);
      rows.push_back(
          {{"object", name},
           {"status", "ok"},
           {"input_vertices", mesh.numVertices()},
           {"regularised_vertices", r.regularised_mesh.numVertices()},
           {"genus_in", r.regularisation.input.genus ? nlohmann::json(*r.regularisation.input.genus)
                                                     : nlohmann::json(nullptr)},
           {"genus_out", r.regularisation.output.genus
                             ? nlohmann::json(*r.regularisation.output.genus)
                             : nlohmann::json(nullptr)},
           {"skeleton_vertices", s.vertices.size()},
           {"branch", s.countType(skeleton::VertexType::kBranch)},
           {"endpoint", s.countType(skeleton::VertexType::kEndpoint)},
           {"segments", s.segments.size()},
           {"loops", s.cycleRank()},
           {"outside_fraction", outside_pct / 100},
           {"max_outside_m", max_outside},
           {"mean_mapping_distance_m", r.diagnostics.mean_mapping_distance_m},
           {"pruned_spurs", r.diagnostics.pruned_spurs},
           {"regularise_s", r.timing.regularise_s},
           {"skeleton_s", r.timing.skeleton_s}});
    } catch (const Error& e) {
      std::cout << fmt::format("{:<44} failed: {}\n", name, e.what());
      rows.push_back({{"object", name}, {"status", "error"}, {"message", e.what()}});
    }
    progress.step(i + 1);
  }
  std::cout << fmt::format(
      "median over {} objects: regularise {:.3f} s, skeleton {:.3f} s, total {:.3f} s\n",
      totals.size(), median(reg_times), median(skel_times), median(totals));
  if (!args.json_out.empty()) {
    writeJsonFile(args.json_out, {{"objects", rows},
                                  {"median_regularise_s", median(reg_times)},
                                  {"median_skeleton_s", median(skel_times)},
                                  {"median_total_s", median(totals)},
                                  {"alpha_divisor", args.options.alpha_divisor},
                                  {"offset_divisor", args.options.offset_divisor}});
  }
  return kExitOk;
}

}  // namespace

void registerBenchCommand(CLI::App& app, Action& action) {
  auto* bench = app.add_subcommand("bench", "Benchmarks on real data");
  bench->require_subcommand(1);
  auto* skel =
      bench->add_subcommand("skeleton", "Regularise + skeleton time per object, and medians");
  auto args = std::make_shared<BenchSkeletonArgs>();
  skel->add_option("INPUT", args->inputs, "Mesh files or directories")->required();
  skel->add_option("--limit", args->limit, "Only the first N meshes (0 = all)")
      ->transform(countIn(0, kMaxCount))
      ->capture_default_str();
  skel->add_option("--json", args->json_out, "Also write the rows as JSON");
  args->options.addTo(*skel);
  skel->callback([=, &action] { action = [=] { return runBenchSkeleton(*args); }; });
  registerBenchPlanCommand(*bench, action);
}

}  // namespace skelgrasp::cli
