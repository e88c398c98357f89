// skelgrasp run INPUT --hand H [--out DIR]: scan of a table scene -> ranked collision-free grasps.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli.h"
#include "hand_options.h"
#include "help_format.h"
#include "option_checks.h"
#include "output_paths.h"
#include "planner_options.h"
#include "reconstruct_options.h"
#include "run_command.h"
#include "skelgrasp/common/directory_lock.h"
#include "skelgrasp/datasets/input.h"
#include "skelgrasp/pipeline/run_output.h"
#include "skelgrasp/pipeline/run_scene.h"

namespace skelgrasp::cli {

pipeline::RunParams RunOptions::params() const {
  pipeline::RunParams p;
  p.reconstruction = reconstruction.params();
  p.planner = planner.skeletonParams();
  p.scene_check = !no_scene_check;
  p.skeleton.regularisation.max_vertices.reset();
  if (max_contraction_vertices > 0)
    p.skeleton.regularisation.max_vertices = max_contraction_vertices;
  p.occupancy.resolution_m = octree_resolution_m;
  p.occupancy.unknown =
      unknown == "occupied" ? grasping::UnknownSpace::kOccupied : grasping::UnknownSpace::kFree;
  p.approach.pregrasp_distance_m = pregrasp_m;
  p.table_obstacles.target_foot_distance_m = foot_distance_m;
  p.planner.hypothesis.scene_lift_max_m = scene_lift_m;
  p.planner.fallback_strategies.top_centring_band_m = top_centring_m;
  p.observed_weight = observed_weight;
  if (surface_clearance == "off") p.surface_clearance.reset();
  p.robust_ranking = robustness.params(planner.seed);
  p.object_jobs = object_jobs;
  return p;
}

void RunOptions::addTo(CLI::App& cmd, bool single_hand) {
  if (single_hand) hand.addTo(cmd);
  // run's own planning limits (RunParams), not plan's.
  planner.timeout_s = pipeline::RunParams{}.planner.timeout_s;
  planner.max_grasps = pipeline::RunParams{}.planner.max_grasps;
  planner.addTo(cmd, false);
  robustness.addTo(cmd);
  reconstruction.addInputOptions(cmd);
  reconstruction.addIngestOptions(cmd);
  reconstruction.addMeshingOptions(cmd);
  cmd.add_option("--jobs", object_jobs,
                 "--object all: objects planned at once (0 = one per core; the grasps do not "
                 "depend on it)")
      ->transform(threadCount(0))
      ->capture_default_str();
  cmd.add_option("--octree-resolution", octree_resolution_m, "Scene occupancy voxel size (m)")
      ->check(positiveLength())
      ->capture_default_str();
  cmd.add_option("--unknown-space", unknown, "Unseen space: free or occupied")
      ->check(CLI::IsMember({"free", "occupied"}))
      ->capture_default_str();
  cmd.add_option("--pregrasp", pregrasp_m, "Approach checked from this distance (m)")
      ->check(lengthOrZero())
      ->capture_default_str();
  cmd.add_option("--foot-distance", foot_distance_m,
                 "Scan points in no object within this distance of the target's mesh are its foot, "
                 "not obstacles of its grasps (m; 0 = obstacles; docs/pipeline.md)")
      ->check(lengthOrZero())
      ->capture_default_str();
  cmd.add_option("--scene-lift", scene_lift_m,
                 "Hands coming down onto the table that hit the scene are lifted back along their "
                 "approach by up to this much (m; 0 = rejected; docs/planning.md)")
      ->check(lengthOrZero())
      ->capture_default_str();
  cmd.add_option("--top-centring", top_centring_m,
                 "Top poses are also tried centred between the faces the fingers close on, over "
                 "this band about the pose (m; 0 = at the centre of mass only; docs/planning.md)")
      ->check(lengthOrZero())
      ->capture_default_str();
  cmd.add_option("--observed-weight", observed_weight,
                 "Ranking weight of contacts on observed surface (0-1)")
      ->check(finiteIn(0, 1))
      ->capture_default_str();
  cmd.add_option("--max-vertices", max_contraction_vertices,
                 "Simplify each object's mesh by edge collapse to about this many vertices before "
                 "the skeleton's contraction (0 = never; docs/pipeline.md)")
      ->transform(vertexCountOrZero())
      ->capture_default_str();
  cmd.add_flag("--no-scene-check", no_scene_check, "Do not check grasps against the scene");
  cmd.add_option("--surface-clearance", surface_clearance,
                 "on: open hands are backed off by the reconstruction's error bound around them "
                 "(docs/pipeline.md); off: the mesh is taken as exact")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  if (single_hand) exports.addTo(cmd);
  // Tuning of the scan's processing and of the scene checks: --help-all.
  for (const char* name :
       {"--cameras", "--angle-step", "--voxel", "--outlier-k", "--plane-distance", "--hull-margin",
        "--cluster-tolerance", "--normal-radius", "--poisson-depth", "--point-weight",
        "--samples-per-node", "--trim", "--trim-fraction", "--observed-distance", "--regularise",
        "--alpha-divisor", "--offset-divisor", "--no-completion", "--max-vertices"}) {
    cmd.get_option(name)->group(kScanDetails);
  }
  for (const char* name :
       {"--octree-resolution", "--unknown-space", "--pregrasp", "--foot-distance", "--scene-lift",
        "--top-centring", "--observed-weight", "--surface-clearance"}) {
    cmd.get_option(name)->group(kSceneDetails);
  }
}

std::string nearestObjectOption(const Eigen::Vector3d& point) {
  return fmt::format("nearest:{:.4f},{:.4f},{:.4f}", point.x(), point.y(), point.z());
}

namespace {

// --export's files, written with the run's others.
pipeline::ExtraRunOutputs exportsOf(const RunOptions& options, const std::string& out_dir,
                                    const grasping::HandModel& hand) {
  return [&options, out_dir, &hand](OutputTransaction& outputs, const nlohmann::json& grasps) {
    options.exports.stage(outputs, out_dir + "/grasps.json", grasps, hand);
  };
}

// `run --object all`: every object in one process. Exit 0 when at least one object got grasps;
// when none did, the outputs (each object with its reason) are still written and one error line
// sums the reasons up.
int runOnEveryObject(const perception::Scan& scan, const std::string& name,
                     const std::string& out_dir, const RunOptions& options,
                     const grasping::HandModel& hand) {
  const auto result = pipeline::runScene(scan, hand, options.params());
  const auto& ingest = result.reconstruction.ingest;
  if (!ingest.status.ok()) return fail(scan.source + ": " + ingest.status.message);
  pipeline::writeSceneRunOutputs(out_dir, result, hand, scan, name,
                                 exportsOf(options, out_dir, hand));
  for (const auto& s : result.stages)
    std::cout << fmt::format("  {:<22} {:7.3f} s\n", s.stage, s.seconds);
  std::string reasons;
  for (const auto& o : result.objects) {
    std::cout << fmt::format("  object {:<15} {:7.3f} s  {} points, {} grasps{}\n", o.id, o.total_s,
                             o.info.points, o.ranked.size(),
                             o.reason.empty() ? "" : " (" + o.reason + ")");
    if (!o.reason.empty())
      reasons += fmt::format("{}{}: {}", reasons.empty() ? "" : "; ", o.id, o.reason);
  }
  std::cout << fmt::format("{} {}: {} of {} objects got grasps in {:.2f} s -> {}/report.html", name,
                           hand.name(), result.objectsWithGrasps(), result.objects.size(),
                           result.total_s, out_dir)
            << std::endl;
  if (result.objectsWithGrasps() == 0)
    return fail(scan.source + ": no object got a grasp (" + reasons + ")");
  return kExitOk;
}

}  // namespace

int runOnScan(const perception::Scan& scan, const std::string& name, const std::string& out_dir,
              const RunOptions& options) {
  const auto hand = options.hand.load();
  if (options.params().reconstruction.ingest.scene.target.mode == perception::TargetMode::kAll)
    return runOnEveryObject(scan, name, out_dir, options, hand);
  const auto result = pipeline::runPipeline(scan, hand, options.params());
  if (!result.reconstruction.status.ok())
    return fail(scan.source + ": " + result.reconstruction.status.message);
  pipeline::writeRunOutputs(out_dir, result, hand, scan, name, exportsOf(options, out_dir, hand));
  for (const auto& s : result.stages)
    std::cout << fmt::format("  {:<22} {:7.3f} s\n", s.stage, s.seconds);
  const auto& summary = result.plan.summary;
  std::cout << fmt::format(
                   "{} {}: {} ranked grasps ({} hypotheses, {} generated, {} force closure, {} "
                   "blocked by the "
                   "scene) in {:.2f} s -> {}/report.html",
                   name, hand.name(), result.ranked.size(), summary.hypotheses, summary.generated,
                   summary.force_closure,
                   summary.rejections.count("scene_collision")
                       ? summary.rejections.at("scene_collision")
                       : 0,
                   result.total_s, out_dir)
            << std::endl;
  if (result.ranked.empty()) std::cout << "no grasp: " << result.status.message << std::endl;
  return kExitOk;
}

void registerRunCommand(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand(
      "run", "Scan of a table scene -> ranked collision-free grasps on one or every object");
  auto input = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>("run_output");
  auto options = std::make_shared<RunOptions>();
  cmd->add_option("INPUT", *input, "PCD/PLY scan, capture description (.json) or YCB raw folder")
      ->required();
  cmd->add_option("--out", *out, "Output directory")->capture_default_str();
  options->addTo(*cmd);
  cmd->callback([=, &action] {
    action = [=] {
      checkOutputDirectoryOption(*out);
      checkOutputIsNotInput(*out, {*input});
      // One run at a time into --out; a directory made here and left empty goes again.
      const LockedOutputDirectory locked(*out);
      const auto scan = datasets::loadInput(*input, options->reconstruction.inputOptions());
      return runOnScan(scan, std::filesystem::path(*input).filename().string(), *out, *options);
    };
  });
}

}  // namespace skelgrasp::cli
