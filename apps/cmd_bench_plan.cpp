// skelgrasp bench plan INPUT...: planners x hands over meshes; ms per valid grasp and
// force-closure rate, with the surface planner given as many pose hypotheses as the skeleton
// planner tried on the same object. One thread (the paper's timing) unless --threads; with more,
// the skeleton planner also runs on one thread in the same process, and the bench prints the
// ratio and checks that both plans are the same.
#include <fmt/format.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

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

// Exit code when the plans on one thread and on --threads differ: a failed check, not bad input.
constexpr int kExitPlansDiffer = 1;

struct BenchPlanArgs {
  std::vector<std::string> inputs;
  std::string hands = "armar3,sdh,shadow";
  std::size_t limit = 0;
  int threads = 1;
  std::string json_out;
  PlannerOptions planner;
  SkeletonOptions skeleton;
};

struct Totals {
  std::vector<double> ms, rates;
  std::size_t grasps = 0;
};

// The same plan: counts, and every grasp's pose, joints and epsilon bit for bit, in order.
bool samePlan(const grasping::PlanResult& a, const grasping::PlanResult& b) {
  const auto &x = a.summary, &y = b.summary;
  if (x.hypotheses != y.hypotheses || x.generated != y.generated ||
      x.force_closure != y.force_closure || x.rejections != y.rejections ||
      a.grasps.size() != b.grasps.size())
    return false;
  for (std::size_t i = 0; i < a.grasps.size(); ++i) {
    const auto &g = a.grasps[i], &h = b.grasps[i];
    if (g.hand_pose.matrix() != h.hand_pose.matrix() || g.joints != h.joints ||
        g.epsilon != h.epsilon)
      return false;
  }
  return true;
}

// The skeleton planner on one thread and on `threads`, alternating which goes first per object.
struct ThreadComparison {
  double one_s = 0, many_s = 0;  // summed over the plans
  std::vector<double> ratios;    // one-thread time / many-thread time, per plan
  std::size_t plans = 0, differing = 0;
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
  const int threads = args.threads == 0 ? hardwareThreads() : args.threads;
  const tbb::global_control allow(tbb::global_control::max_allowed_parallelism, threads);
  tbb::task_arena one_thread(1), many_threads(threads);
  const bool compare = threads > 1;
  ThreadComparison comparison;
  std::cout << fmt::format("{:<36} {:<16} {:<9} {:>6} {:>6} {:>6} {:>7} {:>9}{}\n", "object",
                           "hand", "planner", "poses", "gen", "fc", "fc%", "ms/valid",
                           compare ? fmt::format(" {:>8} {:>8} {:>6}", "1t s", "s", "ratio") : "");
  ProgressReporter progress("bench plan", files.size(), 10.0);
  for (std::size_t i = 0; i < files.size(); ++i) {
    const std::string name = std::filesystem::path(files[i]).filename().string();
    try {
      const TriangleMesh mesh = loadMesh(files[i], args.skeleton.loadOptions());
      const auto skel = skeleton::extractSkeleton(mesh, args.skeleton.params());
      if (!skel.status.ok()) throw Error(skel.status.message);
      const grasping::GraspObject object(mesh);
      for (const auto& hand : hands) {
        const auto planSkeleton = [&] {
          return grasping::planSkeletonGrasps(hand, object, skel.skeleton,
                                              args.planner.skeletonParams());
        };
        grasping::PlanResult s, single;
        if (compare && i % 2 == 1) single = one_thread.execute(planSkeleton);
        s = many_threads.execute(planSkeleton);
        if (compare && i % 2 == 0) single = one_thread.execute(planSkeleton);
        std::string threads_column;
        if (compare) {
          const double one_s = single.summary.planning_s, many_s = s.summary.planning_s;
          comparison.one_s += one_s;
          comparison.many_s += many_s;
          ++comparison.plans;
          if (many_s > 0) comparison.ratios.push_back(one_s / many_s);
          const bool same = samePlan(single, s);
          comparison.differing += !same;
          threads_column =
              fmt::format(" {:>8.3f} {:>8.3f} {:>5.2f}x{}", one_s, many_s,
                          many_s > 0 ? one_s / many_s : 0.0, same ? "" : "  (plans differ)");
        }
        auto surface_params = args.planner.surfaceParams();
        surface_params.max_hypotheses = std::max<std::size_t>(1, s.summary.poses);
        const auto f = many_threads.execute(
            [&] { return grasping::planSurfaceGrasps(hand, object, surface_params); });
        for (const grasping::PlanResult* r : {static_cast<const grasping::PlanResult*>(&s), &f}) {
          const auto& sum = r->summary;
          std::cout << fmt::format(
              "{:<36} {:<16} {:<9} {:>6} {:>6} {:>6} {:>6.1f}% {:>9}{}\n", name, hand.name(),
              r->planner, sum.poses, sum.generated, sum.force_closure, 100 * sum.forceClosureRate(),
              sum.force_closure ? fmt::format("{:.1f}", sum.msPerValidGrasp()) : "n/a",
              r == &s ? threads_column : "");
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
  nlohmann::json threads_json = {{"threads", threads}};
  if (compare) {
    std::cout << fmt::format(
        "\nskeleton planner, 1 thread -> {} threads: {:.2f} -> {:.2f} s summed, {:.2f}x (median "
        "per plan {:.2f}x); plans that differ: {} of {}\n",
        threads, comparison.one_s, comparison.many_s,
        comparison.many_s > 0 ? comparison.one_s / comparison.many_s : 0.0,
        median(comparison.ratios), comparison.differing, comparison.plans);
    threads_json["one_thread_s"] = comparison.one_s;
    threads_json["threads_s"] = comparison.many_s;
    threads_json["plans_differing"] = comparison.differing;
  }
  if (!args.json_out.empty())
    writeJsonFile(args.json_out, {{"rows", rows}, {"threads", threads_json}});
  return comparison.differing > 0 ? kExitPlansDiffer : kExitOk;
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
  cmd->add_option("--threads", args->threads,
                  "Threads the planners use (0 = all cores); above 1 the skeleton planner also "
                  "runs on one thread, and the ratio is printed")
      ->transform(threadCount(0))
      ->capture_default_str();
  cmd->add_option("--json", args->json_out, "Also write the rows as JSON");
  args->planner.addTo(*cmd);
  args->skeleton.addTo(*cmd, false);
  cmd->callback([args, &action] { action = [args] { return runBenchPlan(*args); }; });
}

}  // namespace skelgrasp::cli
