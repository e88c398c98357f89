// skelgrasp bench physics INPUT... --hands H,...: the grasps `plan` returns, executed by the
// physics judge. Per object and hand, the plan's best grasps (as plan ranks them, with their r)
// are executed nominally and, with --samples, under r's pose error (sim_r); per hand the table
// gives the nominal hold rate, mean sim_r, the r the plan reported for the same grasps, and how
// well r ranks them (Spearman). A benchmark, not a test: it says how far the model's r is from
// what holds in the engine (docs/physics.md, docs/results.md).
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>

#include "cli.h"
#include "mesh_list.h"
#include "option_checks.h"
#include "output_paths.h"
#include "planner_options.h"
#include "robustness_options.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/evaluation/physics_figures.h"
#include "skelgrasp/evaluation/simulate.h"
#include "skelgrasp/grasping/quality/load_capacity.h"
#include "skelgrasp/ranking/plan_grasps.h"

namespace skelgrasp::cli {
namespace {

struct BenchPhysicsArgs {
  std::vector<std::string> inputs;
  std::string hands = "armar3,sdh,shadow";
  std::size_t limit = 0;
  std::size_t grasps = 10;
  int samples = 0;
  std::uint64_t seed = ranking::RobustnessParams{}.seed;
  int threads = 0;
  std::string json_out;
  PlannerOptions planner;
  RobustnessOptions robustness;
};

std::string figure(const std::optional<double>& value, const char* format = "{:.2f}") {
  return value ? fmt::format(fmt::runtime(format), *value) : std::string("-");
}

std::string figure(double value, const char* format = "{:.2f}") {
  return std::isfinite(value) ? fmt::format(fmt::runtime(format), value) : std::string("-");
}

nlohmann::json optionalJson(const std::optional<double>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

nlohmann::json finiteJson(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

int runBenchPhysics(const BenchPhysicsArgs& args) {
  checkOutputFileOption(args.json_out);
  setLogLevel(spdlog::level::warn);
  auto files = collectMeshFiles(args.inputs);
  if (args.limit > 0 && files.size() > args.limit) files.resize(args.limit);
  if (files.empty()) return fail("bench physics: no mesh files in the given inputs");
  std::vector<grasping::HandModel> hands;
  for (const auto& name : splitList(args.hands)) hands.push_back(grasping::resolveHand(name));
  std::optional<tbb::global_control> threads;
  if (args.threads > 0) {
    threads.emplace(tbb::global_control::max_allowed_parallelism,
                    static_cast<std::size_t>(args.threads));
  }
  ranking::PlanOptions options;
  options.skeleton_planner = args.planner.skeletonParams();
  options.surface_planner = args.planner.surfaceParams();
  options.ranking = args.robustness.params(args.planner.seed);
  evaluation::SimulateParams simulate;
  // The judge's friction is the planner's (and r's): --mu.
  simulate.frictions = {args.planner.mu};
  simulate.samples = args.samples;
  simulate.robustness.seed = args.seed;

  std::map<std::string, std::vector<evaluation::JudgedGrasp>> judged;  // per hand
  std::map<std::string, std::size_t> with_grasps;
  nlohmann::json rows = nlohmann::json::array();
  std::cout << fmt::format("{:<30} {:<16} {:>6} {:>6} {:>7} {:>7} {:>7} {:>9}\n", "object", "hand",
                           "grasps", "holds", "mean_r", "sim_r", "plan_s", "ms/exec");
  ProgressReporter progress("bench physics", files.size() * hands.size(), 30.0);
  std::size_t done = 0;
  for (const auto& file : files) {
    const std::string name = std::filesystem::path(file).stem().string();
    const TriangleMesh mesh = loadMesh(file);
    const grasping::GraspObject object(mesh);
    const physics::PhysicalObject physical(mesh);
    const auto skeleton = skeleton::extractSkeleton(mesh, options.skeleton);
    ranking::PlanInputs inputs;
    if (skeleton.status.ok()) inputs.skeleton = &skeleton;
    for (const auto& hand : hands) {
      progress.step(done++);
      std::vector<grasping::GraspPlacement> placements;
      std::vector<std::optional<double>> reported_r;
      std::vector<double> capacities;
      double plan_s = 0;
      if (skeleton.status.ok()) {
        const ranking::GraspPlan plan = ranking::planGrasps(object, hand, options, inputs);
        plan_s = plan.timing.total_s();
        for (std::size_t g = 0; g < plan.grasps.size() && g < args.grasps; ++g) {
          const auto& grasp = plan.grasps[g];
          placements.push_back(
              {nlohmann::json(static_cast<int>(g)), grasp.hand_pose, grasp.preshape});
          reported_r.push_back(grasp.robustness ? std::optional<double>(grasp.robustness->r)
                                                : std::nullopt);
          capacities.push_back(
              grasping::loadCapacity(
                  hand, grasp.hand_pose, grasp.joints, grasp.contacts, physical.centerOfMass(),
                  grasping::withHandContactModel(options.hypothesis().quality, hand))
                  .min);
        }
      }
      if (!placements.empty()) ++with_grasps[hand.name()];
      const auto result = evaluation::simulateGrasps(hand, object, physical, placements, simulate);
      double mean_r = 0, mean_sim = 0;
      std::size_t holds = 0, scored = 0, sampled = 0;
      for (std::size_t g = 0; g < result.grasps.size(); ++g) {
        const auto& at = result.grasps[g].by_friction.front();
        evaluation::JudgedGrasp row;
        row.object = name;
        row.hand = hand.name();
        row.rank = static_cast<int>(g);
        row.r = reported_r[g];
        row.nominal_holds = at.nominal.holds;
        if (!at.nominal.holds) row.failed_phase = physics::toString(at.nominal.failed_phase);
        if (at.robustness) row.sim_r = at.robustness->sim_r;
        row.cpu_s = result.grasps[g].cpu_s;
        row.executions = 1 + args.samples;
        holds += row.nominal_holds;
        if (row.r) {
          mean_r += *row.r;
          ++scored;
        }
        if (row.sim_r) {
          mean_sim += *row.sim_r;
          ++sampled;
        }
        nlohmann::json failed = nlohmann::json::array();
        for (const auto& d : at.nominal.disturbances) {
          if (!d.held) failed.push_back(toJson(d.direction));
        }
        rows.push_back({{"object", name},
                        {"hand", hand.name()},
                        {"rank", g},
                        {"preshape", placements[g].preshape},
                        {"r", optionalJson(row.r)},
                        {"load_capacity", capacities[g]},
                        {"nominal_holds", row.nominal_holds},
                        {"failed_phase", row.failed_phase},
                        {"reason", at.nominal.reason},
                        {"failed_directions", failed},
                        {"closing_displacement_m", at.nominal.closing_displacement_m},
                        {"touching_links", at.nominal.touching_links},
                        {"sim_r", optionalJson(row.sim_r)},
                        {"cpu_s", row.cpu_s},
                        {"plan_s", plan_s}});
        judged[hand.name()].push_back(std::move(row));
      }
      const double ms = result.executions ? 1000.0 * result.execution_cpu_s /
                                                static_cast<double>(result.executions)
                                          : 0.0;
      std::cout << fmt::format(
                       "{:<30} {:<16} {:>6} {:>6} {:>7} {:>7} {:>7.2f} {:>9.1f}\n", name,
                       hand.name(), placements.size(), holds,
                       scored ? fmt::format("{:.2f}", mean_r / static_cast<double>(scored)) : "-",
                       sampled ? fmt::format("{:.2f}", mean_sim / static_cast<double>(sampled))
                               : "-",
                       plan_s, ms)
                << std::flush;
    }
  }
  std::cout << fmt::format(
      "\nmu {}, {} sample(s) per grasp for sim_r, the best {} grasps of each plan\n",
      args.planner.mu, args.samples, args.grasps);
  std::cout << fmt::format("{:<16} {:>8} {:>7} {:>7} {:>7} {:>7} {:>8} {:>9} {:>9} {:>8}\n", "hand",
                           "objects", "grasps", "holds", "sim_r", "r", "r-sim_r", "rho(r,sr)",
                           "rho(r,h)", "ms/exec");
  nlohmann::json summary = nlohmann::json::array();
  for (const auto& hand : hands) {
    const auto& rows_of_hand = judged[hand.name()];
    const auto f = evaluation::physicsFigures(rows_of_hand, files.size(), with_grasps[hand.name()]);
    std::cout << fmt::format("{:<16} {:>8} {:>7} {:>7} {:>7} {:>7} {:>8} {:>9} {:>9} {:>8.1f}\n",
                             hand.name(), fmt::format("{}/{}", f.objects_with_grasps, f.objects),
                             f.grasps, fmt::format("{:.0f}%", 100.0 * f.nominal_hold_rate),
                             figure(f.mean_sim_r), figure(f.mean_r),
                             figure(f.mean_r_minus_sim_r, "{:+.2f}"), figure(f.spearman_r_sim_r),
                             figure(f.spearman_r_nominal), f.ms_cpu_per_execution);
    summary.push_back({{"hand", hand.name()},
                       {"objects", f.objects},
                       {"objects_with_grasps", f.objects_with_grasps},
                       {"grasps", f.grasps},
                       {"nominal_hold_rate", f.nominal_hold_rate},
                       {"mean_sim_r", optionalJson(f.mean_sim_r)},
                       {"mean_r", optionalJson(f.mean_r)},
                       {"mean_r_minus_sim_r", optionalJson(f.mean_r_minus_sim_r)},
                       {"spearman_r_sim_r", finiteJson(f.spearman_r_sim_r)},
                       {"spearman_r_nominal", finiteJson(f.spearman_r_nominal)},
                       {"ms_cpu_per_execution", f.ms_cpu_per_execution}});
  }
  if (!args.json_out.empty()) {
    OutputTransaction outputs;
    writeJsonFile(outputs.stage(args.json_out), {{"schema", "skelgrasp.bench_physics/1"},
                                                 {"mu", args.planner.mu},
                                                 {"samples", args.samples},
                                                 {"grasps_per_plan", args.grasps},
                                                 {"summary", summary},
                                                 {"grasps", rows}});
    outputs.commit();
  }
  return kExitOk;
}

}  // namespace

void registerBenchPhysicsCommand(CLI::App& app, Action& action) {
  CLI::App* bench = app.get_subcommand("bench");  // created by registerBenchCommand
  auto* cmd = bench->add_subcommand(
      "physics",
      "The grasps plan returns, executed by the physics judge: hold rate, sim_r, reported r "
      "and their rank correlation per hand");
  auto args = std::make_shared<BenchPhysicsArgs>();
  cmd->add_option("inputs", args->inputs, "Mesh files or directories")->required();
  cmd->add_option("--hands", args->hands, "Comma-separated built-in hands")->capture_default_str();
  cmd->add_option("--limit", args->limit, "Only the first N meshes (0 = all)")
      ->transform(countIn(0, kMaxCount))
      ->capture_default_str();
  cmd->add_option("--grasps", args->grasps, "The best N grasps of each plan are executed")
      ->transform(countIn(1, kMaxCount))
      ->capture_default_str();
  cmd->add_option("--samples", args->samples,
                  "Perturbed executions per grasp for sim_r (r's pose error; 0: nominal only)")
      ->transform(countIn(0, evaluation::kMaxSimulationSamples))
      ->capture_default_str();
  cmd->add_option("--sim-seed", args->seed, "Seed of sim_r's pose errors (r's by default)")
      ->transform(countIn(0, UINT64_MAX))
      ->capture_default_str();
  cmd->add_option("--threads", args->threads, "Threads (0 = all cores)")
      ->transform(threadCount(0))
      ->capture_default_str();
  cmd->add_option("--json", args->json_out, "Also write every grasp's row and the summary");
  args->planner.addTo(*cmd);
  args->robustness.addTo(*cmd);
  cmd->callback([=, &action] { action = [=] { return runBenchPhysics(*args); }; });
}

}  // namespace skelgrasp::cli
