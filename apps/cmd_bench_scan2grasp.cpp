// skelgrasp bench scan2grasp MESHES... --hands H,...: from one depth view to grasps that hold on
// the real object. Each mesh rests on a table and is seen in --views single views by the simulated
// depth camera (perception/table_view.h); the main job runs on each view as `run` would (one
// core, timed), its top grasps are mapped back into the mesh's frame with the known camera pose and
// judged on the TRUE mesh: the model's r (settled, the run's mu, the load check) and the physics
// judge's nominal execution. Per hand: views with grasps, the r the run claimed against the r on
// the true object, the hold rate, grasps starting inside the true object, claimed minus true r
// pooled and the run's time (docs/scan2grasp.md).
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <optional>

#include "cli.h"
#include "mesh_list.h"
#include "option_checks.h"
#include "output_paths.h"
#include "run_command.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/evaluation/true_object.h"
#include "skelgrasp/geometry/mesh_query.h"
#include "skelgrasp/grasping/io/plan_output.h"
#include "skelgrasp/perception/table_view.h"

namespace skelgrasp::cli {
// Named, not anonymous: the command files are compiled as one unity file.
namespace bench_scan2grasp {

struct Args {
  std::vector<std::string> inputs;
  std::string hands = "armar3,sdh,shadow,parallel_gripper";
  std::size_t limit = 0;
  int views = perception::TableViewParams{}.views;
  std::size_t grasps = 10;
  std::uint64_t scene_seed = perception::TableViewParams{}.seed;
  double noise_scale = perception::TableViewParams{}.noise_scale;
  int true_samples = evaluation::TrueObjectParams::defaultScore().robustness.samples;
  int physics_samples = 0;
  bool no_physics = false;
  int threads = 0;
  std::string json_out;
  RunOptions run;
};

nlohmann::json optionalNumber(const std::optional<double>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

std::string shown(const std::optional<double>& value, const char* format) {
  return value ? fmt::format(fmt::runtime(format), *value) : std::string("-");
}

// How far the reconstruction lies from the true surface (mesh frame): the median over its observed
// and over its filled-in vertices, in metres (NaN for an empty group), and the share of the
// vertices whose distance is within the run's error bound (NaN without bounds).
struct ReconstructionError {
  double observed = 0, filled = 0, within_bound = 0;
};

ReconstructionError reconstructionError(const pipeline::RunResult& run,
                                        const Pose& object_from_scan,
                                        const geometry::MeshQuery& truth) {
  std::vector<double> observed, filled;
  const bool bounds = run.surface_error_m.size() == run.mesh.vertices.size();
  std::size_t within = 0;
  for (std::size_t i = 0; i < run.mesh.vertices.size(); ++i) {
    const double d = truth.distance(object_from_scan * run.mesh.vertices[i]);
    (i < run.observed.size() && run.observed[i] ? observed : filled).push_back(d);
    if (bounds) within += d <= run.surface_error_m[i];
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  ReconstructionError e;
  e.observed = observed.empty() ? nan : evaluation::median(observed);
  e.filled = filled.empty() ? nan : evaluation::median(filled);
  e.within_bound = bounds && !run.mesh.vertices.empty()
                       ? static_cast<double>(within) / static_cast<double>(run.mesh.vertices.size())
                       : nan;
  return e;
}

nlohmann::json finiteOrNull(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

nlohmann::json millimetres(double metres) {
  return std::isfinite(metres) ? nlohmann::json(1000.0 * metres) : nlohmann::json(nullptr);
}

int runBench(const Args& args) {
  checkOutputFileOption(args.json_out);
  setLogLevel(spdlog::level::warn);
  auto files = collectMeshFiles(args.inputs);
  if (args.limit > 0 && files.size() > args.limit) files.resize(args.limit);
  if (files.empty()) return fail("bench scan2grasp: no mesh files in the given inputs");
  std::vector<grasping::HandModel> hands;
  for (const auto& name : splitList(args.hands)) hands.push_back(grasping::resolveHand(name));
  const pipeline::RunParams run_params = args.run.params();
  perception::TableViewParams views;
  views.views = args.views;
  views.seed = args.scene_seed;
  views.noise_scale = args.noise_scale;
  evaluation::TrueObjectParams judge;
  judge.score.frictions = {args.run.planner.mu};
  judge.score.robustness.samples = args.true_samples;
  // The run's criterion on the true object too: its variant and load check (--no-load-check).
  judge.score.robustness.variant = run_params.robust_ranking.robustness.variant;
  judge.score.robustness.load = run_params.robust_ranking.robustness.load;
  judge.simulate.samples = args.physics_samples;
  const int judge_threads = args.threads > 0 ? args.threads : hardwareThreads();

  std::map<std::string, std::vector<evaluation::ScanToGraspCase>> cases;  // per hand
  nlohmann::json case_rows = nlohmann::json::array(), grasp_rows = nlohmann::json::array();
  std::cout << fmt::format("{:<28} {:>4} {:<16} {:>5} {:>7} {:>6} {:>6} {:>6} {:>6} {:>7}\n",
                           "object", "view", "hand", "grasps", "claimed", "true", "inside", "holds",
                           "err_mm", "run_s");
  ProgressReporter progress(
      "bench scan2grasp", files.size() * static_cast<std::size_t>(args.views) * hands.size(), 30.0);
  std::size_t done = 0;
  for (const auto& file : files) {
    const std::string name = std::filesystem::path(file).stem().string();
    const TriangleMesh mesh = loadMesh(file);
    const grasping::GraspObject truth(mesh);
    const geometry::MeshQuery truth_query(mesh);
    std::optional<physics::PhysicalObject> physical;
    if (!args.no_physics) physical.emplace(mesh);
    const perception::TableViews scene = perception::renderTableViews(mesh, views);
    for (std::size_t v = 0; v < scene.views.size(); ++v) {
      const auto& view = scene.views[v];
      for (const auto& hand : hands) {
        progress.step(done++);
        pipeline::RunResult run;
        {
          const tbb::global_control one_core(tbb::global_control::max_allowed_parallelism, 1);
          run = pipeline::runPipeline(view.scan, hand, run_params);
        }
        std::vector<evaluation::ClaimedGrasp> claimed;
        for (std::size_t g = 0; g < run.ranked.size() && g < args.grasps; ++g) {
          const auto& ranked = run.ranked[g];
          evaluation::ClaimedGrasp c;
          c.placement = {nlohmann::json(static_cast<int>(g)),
                         view.object_from_scan * ranked.grasp.hand_pose, ranked.grasp.preshape};
          if (ranked.grasp.robustness) c.claimed_r = ranked.grasp.robustness->r;
          c.observed_contact_ratio = ranked.observed_contact_ratio;
          claimed.push_back(std::move(c));
        }
        evaluation::ScanToGraspCase c;
        c.object = name;
        c.view = static_cast<int>(v);
        c.hand = hand.name();
        c.status = toString(run.status.code);
        if (run.ranked.empty()) c.reason = run.status.message;
        c.returned = run.ranked.size();
        c.run_s = run.total_s;
        {
          const tbb::global_control judging(tbb::global_control::max_allowed_parallelism,
                                            static_cast<std::size_t>(judge_threads));
          c.top = evaluation::judgeOnTrueObject(hand, truth, physical ? &*physical : nullptr,
                                                claimed, judge);
        }
        const auto error = reconstructionError(run, view.object_from_scan, truth_query);
        const auto figures = evaluation::scanToGraspFigures({c});
        std::size_t holds = 0;
        for (const auto& g : c.top) holds += g.nominal_holds.value_or(false);
        std::cout
            << fmt::format(
                   "{:<28} {:>4} {:<16} {:>5} {:>7.2f} {:>6.2f} {:>6} {:>6} {:>6} {:>7.2f}{}\n",
                   name, v, hand.name(), c.returned, figures.median_claimed_r,
                   figures.median_true_r, figures.starts_inside,
                   physical ? std::to_string(holds) : std::string("-"),
                   std::isfinite(error.observed) ? fmt::format("{:.1f}", 1000 * error.observed)
                                                 : std::string("-"),
                   c.run_s, c.reason.empty() ? "" : "  (" + c.reason + ")")
            << std::flush;
        const auto& clusters = run.reconstruction.ingest.scene.clusters;
        case_rows.push_back({{"object", name},
                             {"view", v},
                             {"hand", hand.name()},
                             {"status", c.status},
                             {"reason", c.reason},
                             {"returned", c.returned},
                             {"run_s", c.run_s},
                             {"clusters", clusters.size()},
                             {"plan", grasping::planSummaryJson(run.plan.summary)},
                             {"object_pixels", view.object_pixels},
                             {"camera",
                              {{"distance_m", view.distance_m},
                               {"elevation_rad", view.elevation_rad},
                               {"azimuth_rad", view.azimuth_rad},
                               {"noise_seed", view.noise_seed}}},
                             {"reconstruction_error_mm",
                              {{"observed_median", millimetres(error.observed)},
                               {"filled_median", millimetres(error.filled)},
                               {"within_bound", finiteOrNull(error.within_bound)}}}});
        for (std::size_t g = 0; g < c.top.size(); ++g) {
          const auto& j = c.top[g];
          grasp_rows.push_back({{"object", name},
                                {"view", v},
                                {"hand", hand.name()},
                                {"rank", g},
                                {"preshape", claimed[g].placement.preshape},
                                {"hand_pose", poseToJson(claimed[g].placement.hand_pose)},
                                {"claimed_r", optionalNumber(j.claimed_r)},
                                {"observed_contact_ratio", j.observed_contact_ratio},
                                {"true_r", j.true_r},
                                {"true_force_closure", j.true_force_closure},
                                {"starts_inside", j.starts_inside},
                                {"closing_failure", j.closing_failure},
                                {"nominal_holds", j.nominal_holds ? nlohmann::json(*j.nominal_holds)
                                                                  : nlohmann::json(nullptr)},
                                {"failed_phase", j.failed_phase},
                                {"sim_r", optionalNumber(j.sim_r)}});
        }
        cases[hand.name()].push_back(std::move(c));
      }
    }
  }
  progress.finish();

  const std::string variant = ranking::toString(judge.score.robustness.variant);
  const bool load_check = judge.score.robustness.load.has_value();
  const bool clearance = run_params.surface_clearance.has_value();
  std::cout << fmt::format(
      "\n{} object(s) x {} view(s), seed {}, noise x{}, surface clearance {}; the best {} grasps "
      "of each run judged on the true mesh ({} r, mu {}, load check {}, {} samples; physics "
      "judge {})\n",
      files.size(), args.views, args.scene_seed, args.noise_scale, clearance ? "on" : "off",
      args.grasps, variant, args.run.planner.mu, load_check ? "on" : "off", args.true_samples,
      args.no_physics ? "off" : fmt::format("nominal, {} sample(s)", args.physics_samples));
  std::cout << fmt::format("{:<16} {:>12} {:>10} {:>9} {:>7} {:>6} {:>12} {:>13} {:>6}\n", "hand",
                           "objects w/ g", "views w/ g", "claimed r", "true r", "holds",
                           "start inside", "claimed-true", "run_s");
  nlohmann::json summary = nlohmann::json::array();
  for (const auto& hand : hands) {
    const auto f = evaluation::scanToGraspFigures(cases[hand.name()]);
    std::cout << fmt::format(
        "{:<16} {:>12} {:>10} {:>9.2f} {:>7.2f} {:>6} {:>12} {:>13} {:>6.2f}\n", hand.name(),
        fmt::format("{}/{}", f.objects_with_grasps, f.objects),
        fmt::format("{}/{}", f.cases_with_grasps, f.cases), f.median_claimed_r, f.median_true_r,
        f.hold_rate ? fmt::format("{:.0f}%", 100.0 * *f.hold_rate) : std::string("-"),
        fmt::format("{}/{}", f.starts_inside, f.top_grasps), shown(f.claimed_minus_true, "{:+.2f}"),
        f.median_run_s);
    summary.push_back({{"hand", hand.name()},
                       {"objects", f.objects},
                       {"objects_with_grasps", f.objects_with_grasps},
                       {"views", f.cases},
                       {"views_with_grasps", f.cases_with_grasps},
                       {"median_claimed_r", f.median_claimed_r},
                       {"median_true_r", f.median_true_r},
                       {"nominal_hold_rate", optionalNumber(f.hold_rate)},
                       {"top_grasps", f.top_grasps},
                       {"starts_inside", f.starts_inside},
                       {"claimed_minus_true_r", optionalNumber(f.claimed_minus_true)},
                       {"claimed_pairs", f.claimed_pairs},
                       {"median_run_s", f.median_run_s}});
  }
  if (!args.json_out.empty()) {
    OutputTransaction outputs;
    writeJsonFile(outputs.stage(args.json_out), {{"schema", "skelgrasp.bench_scan2grasp/1"},
                                                 {"objects", files.size()},
                                                 {"views_per_object", args.views},
                                                 {"scene_seed", args.scene_seed},
                                                 {"noise_scale", args.noise_scale},
                                                 {"grasps_per_run", args.grasps},
                                                 {"surface_clearance", clearance},
                                                 {"mu", args.run.planner.mu},
                                                 {"variant", variant},
                                                 {"load_check", load_check},
                                                 {"true_samples", args.true_samples},
                                                 {"physics", !args.no_physics},
                                                 {"physics_samples", args.physics_samples},
                                                 {"summary", summary},
                                                 {"cases", case_rows},
                                                 {"grasps", grasp_rows}});
    outputs.commit();
  }
  return kExitOk;
}

}  // namespace bench_scan2grasp

void registerBenchScanToGraspCommand(CLI::App& app, Action& action) {
  using bench_scan2grasp::Args;
  CLI::App* bench = app.get_subcommand("bench");  // created by registerBenchCommand
  auto* cmd = bench->add_subcommand(
      "scan2grasp",
      "Meshes on a table seen in single depth views, run on each view, the grasps judged on the "
      "true mesh: claimed vs true r, physics holds, starts inside, per hand");
  auto args = std::make_shared<Args>();
  cmd->add_option("inputs", args->inputs, "Mesh files or directories (metres)")->required();
  cmd->add_option("--hands", args->hands, "Comma-separated built-in hands")->capture_default_str();
  cmd->add_option("--limit", args->limit, "Only the first N meshes (0 = all)")
      ->transform(countIn(0, kMaxCount))
      ->capture_default_str();
  cmd->add_option("--views", args->views, "Single views per object, each run on its own")
      ->transform(countIn(1, 64))
      ->capture_default_str();
  cmd->add_option("--grasps", args->grasps, "The best N grasps of each run are judged")
      ->transform(countIn(1, kMaxCount))
      ->capture_default_str();
  cmd->add_option("--scene-seed", args->scene_seed,
                  "Seed of the resting pose's turn, the viewpoints and the sensor noise")
      ->transform(countIn(0, UINT64_MAX / 2000))
      ->capture_default_str();
  cmd->add_option("--noise-scale", args->noise_scale,
                  "Multiplies the sensor's axial noise (1 = the documented model)")
      ->check(finiteIn(0, 100))
      ->capture_default_str();
  cmd->add_option("--true-samples", args->true_samples,
                  "Perturbed executions per grasp for r on the true mesh")
      ->transform(countIn(1, 100000))
      ->capture_default_str();
  cmd->add_option("--physics-samples", args->physics_samples,
                  "Perturbed physics executions per grasp for sim_r (0: nominal only)")
      ->transform(countIn(0, evaluation::kMaxSimulationSamples))
      ->capture_default_str();
  cmd->add_flag("--no-physics", args->no_physics, "Judge with the model only");
  cmd->add_option("--judge-threads", args->threads,
                  "Threads of the judging on the true mesh (0 = all cores); runs use one core "
                  "(--threads: their normals and Poisson)")
      ->transform(threadCount(0))
      ->capture_default_str();
  cmd->add_option("--json", args->json_out, "Also write every view's and grasp's row");
  args->run.addTo(*cmd, false);
  cmd->callback([=, &action] { action = [=] { return bench_scan2grasp::runBench(*args); }; });
}

}  // namespace skelgrasp::cli
