// skelgrasp bench plan INPUT...: planners x hands over meshes; ms per valid grasp and
// force-closure rate, with the surface planner given as many pose hypotheses as the skeleton
// planner tried on the same object.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli.h"
#include "mesh_list.h"
#include "option_checks.h"
#include "output_paths.h"
#include "planner_options.h"
#include "skeleton_options.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/logging.h"

namespace skelgrasp::cli {
namespace {

struct BenchPlanArgs {
  std::vector<std::string> inputs;
  std::string hands = "armar3,sdh,shadow";
  std::size_t limit = 0;
  std::string json_out;
  PlannerOptions planner;
  SkeletonOptions skeleton;
};

struct Totals {
  std::vector<double> ms, rates;
  std::size_t grasps = 0;
};

int runBenchPlan(const BenchPlanArgs& args) {
  checkOutputFileOption(args.json_out);
  auto files = collectMeshFiles(args.inputs);
  if (args.limit > 0 && files.size() > args.limit) files.resize(args.limit);
  if (files.empty()) return fail("bench plan: no mesh files in the given inputs");
  std::vector<grasping::HandModel> hands;
  for (const auto& name : splitList(args.hands)) hands.push_back(grasping::resolveHand(name));
  std::map<std::pair<std::string, std::string>, Totals> totals;
  nlohmann::json rows = nlohmann::json::array();
  std::cout << fmt::format("{:<36} {:<16} {:<9} {:>6} {:>6} {:>6} {:>7} {:>9}\n", "object", "hand",
                           "planner", "poses", "gen", "fc", "fc%", "ms/valid");
  ProgressReporter progress("bench plan", files.size(), 10.0);
  for (std::size_t i = 0; i < files.size(); ++i) {
    const std::string name = std::filesystem::path(files[i]).filename().string();
    try {
      const TriangleMesh mesh = loadMesh(files[i], args.skeleton.loadOptions());
      const auto skel = skeleton::extractSkeleton(mesh, args.skeleton.params());
      if (!skel.status.ok()) throw Error(skel.status.message);
      const grasping::GraspObject object(mesh);
      for (const auto& hand : hands) {
        const auto s = grasping::planSkeletonGrasps(hand, object, skel.skeleton,
                                                    args.planner.skeletonParams());
        auto surface_params = args.planner.surfaceParams();
        surface_params.max_hypotheses = std::max<std::size_t>(1, s.summary.poses);
        const auto f = grasping::planSurfaceGrasps(hand, object, surface_params);
        for (const auto* r : {&s, &f}) {
          const auto& sum = r->summary;
          std::cout << fmt::format(
              "{:<36} {:<16} {:<9} {:>6} {:>6} {:>6} {:>6.1f}% {:>9}\n", name, hand.name(),
              r->planner, sum.poses, sum.generated, sum.force_closure, 100 * sum.forceClosureRate(),
              sum.force_closure ? fmt::format("{:.1f}", sum.msPerValidGrasp()) : "n/a");
          auto& t = totals[{hand.name(), r->planner}];
          if (sum.force_closure) t.ms.push_back(sum.msPerValidGrasp());
          if (sum.generated) t.rates.push_back(sum.forceClosureRate());
          t.grasps += r->grasps.size();
          rows.push_back(
              {{"object", name},
               {"hand", hand.name()},
               {"planner", r->planner},
               {"poses", sum.poses},
               {"generated", sum.generated},
               {"force_closure", sum.force_closure},
               {"force_closure_rate", sum.forceClosureRate()},
               {"planning_s", sum.planning_s},
               {"ms_per_valid_grasp", sum.force_closure ? nlohmann::json(sum.msPerValidGrasp())
                                                        : nlohmann::json(nullptr)}});
        }
      }
    } catch (const Error& e) {
      std::cout << fmt::format("{:<36} failed: {}\n", name, e.what());
    }
    progress.step(i + 1);
  }
  std::cout << fmt::format("\n{:<16} {:<9} {:>8} {:>14} {:>10} {:>8}\n", "hand", "planner",
                           "objects", "ms/valid (med)", "fc% (mean)", "grasps");
  for (const auto& [key, t] : totals) {
    double mean_rate = 0;
    for (double r : t.rates) mean_rate += r / std::max<std::size_t>(1, t.rates.size());
    std::cout << fmt::format("{:<16} {:<9} {:>8} {:>14.1f} {:>9.1f}% {:>8}\n", key.first,
                             key.second, t.rates.size(), median(t.ms), 100 * mean_rate, t.grasps);
  }
  if (!args.json_out.empty()) writeJsonFile(args.json_out, {{"rows", rows}});
  return kExitOk;
}

}  // namespace

void registerBenchPlanCommand(CLI::App& bench, Action& action) {
  auto* cmd = bench.add_subcommand(
      "plan", "Skeleton vs surface planner per hand: ms per valid grasp, FC rate");
  auto args = std::make_shared<BenchPlanArgs>();
  cmd->add_option("INPUT", args->inputs, "Mesh files or directories")->required();
  cmd->add_option("--hands", args->hands, "Comma-separated hands")->capture_default_str();
  cmd->add_option("--limit", args->limit, "Only the first N meshes (0 = all)")
      ->transform(countIn(0, kMaxCount))
      ->capture_default_str();
  cmd->add_option("--json", args->json_out, "Also write the rows as JSON");
  args->planner.addTo(*cmd);
  args->skeleton.addTo(*cmd, false);
  cmd->callback([args, &action] { action = [args] { return runBenchPlan(*args); }; });
}

}  // namespace skelgrasp::cli
