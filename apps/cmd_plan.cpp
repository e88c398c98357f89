// skelgrasp plan MESH --hand H [--planner skeleton|surface]: grasps for one object.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli.h"
#include "export_options.h"
#include "hand_options.h"
#include "output_paths.h"
#include "planner_options.h"
#include "robustness_options.h"
#include "skeleton_options.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/evaluation/plan_record.h"
#include "skelgrasp/grasping/plan_output.h"

namespace skelgrasp::cli {
namespace {

struct PlanArgs {
  std::string mesh;
  std::string out = "grasps.json";
  std::string render;
  HandOptions hand;
  PlannerOptions planner;
  RobustnessOptions robustness;
  SkeletonOptions skeleton;
  ExportOptions exports;
};

int runPlan(const PlanArgs& args) {
  checkOutputFileOption(args.out);
  checkOutputFileOption(args.render);
  const auto hand = args.hand.load();
  MeshLoadInfo info;
  TriangleMesh mesh = loadMesh(args.mesh, args.skeleton.loadOptions(), &info);
  const std::string name = std::filesystem::path(args.mesh).filename().string();
  const grasping::GraspObject object(mesh);
  grasping::PlanResult result;
  std::optional<skeleton::SkeletonResult> skel;
  if (args.planner.planner == "skeleton") {
    skel = skeleton::extractSkeleton(mesh, args.skeleton.params());
    if (!skel->status.ok()) return fail(args.mesh + ": " + skel->status.message);
    result =
        grasping::planSkeletonGrasps(hand, object, skel->skeleton, args.planner.skeletonParams());
  } else {
    result = grasping::planSurfaceGrasps(hand, object, args.planner.surfaceParams());
  }
  // Robust ranking: the best grasps scored by r and re-ranked (docs/planning.md).
  auto ranked = evaluation::rankByRobustness(hand, object, std::move(result.grasps),
                                             args.planner.hypothesis(),
                                             args.robustness.params(args.planner.seed));
  result.grasps = std::move(ranked.grasps);
  const evaluation::PlanTiming timing = evaluation::planTimingOf(
      skel ? &skel->timing : nullptr, result.summary.planning_s, ranked.time_s);
  nlohmann::json document = grasping::planToJson(result, hand, name);
  evaluation::addPlanRecords(document, ranked, timing);
  OutputTransaction outputs;
  if (!args.render.empty()) {
    grasping::renderPlanPng(outputs.stage(args.render), mesh, skel ? &skel->skeleton : nullptr,
                            result, hand);
  }
  writeJsonFile(outputs.stage(args.out), document);
  outputs.commit();
  args.exports.write(args.out, hand);
  std::cout << grasping::planSummaryLine(result, hand.name(), name);
  if (ranked.scored > 0) {
    std::cout << fmt::format("; best r {:.2f} ({} of {} grasps scored, {:.2f} s)",
                             result.grasps.front().robustness->r, ranked.scored,
                             result.grasps.size(), ranked.time_s);
  }
  std::cout << fmt::format("; {:.2f} s in all", timing.total_s()) << std::endl;
  return kExitOk;
}

}  // namespace

void registerPlanCommand(CLI::App& app, Action& action) {
  auto* cmd =
      app.add_subcommand("plan", "Plan grasps for a mesh (skeleton or surface-normal planner)");
  auto args = std::make_shared<PlanArgs>();
  cmd->add_option("MESH", args->mesh, "Object mesh (.ply .obj .off .stl)")->required();
  args->hand.addTo(*cmd);
  args->planner.addTo(*cmd);
  args->robustness.addTo(*cmd);
  cmd->add_option("--out", args->out, "Output grasps JSON (docs/planning.md)")
      ->capture_default_str();
  cmd->add_option("--render", args->render,
                  "Render object, skeleton and approach lines to this PNG");
  args->skeleton.addTo(*cmd, false);
  args->exports.addTo(*cmd);
  cmd->callback([args, &action] { action = [args] { return runPlan(*args); }; });
}

}  // namespace skelgrasp::cli
