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
#include "skelgrasp/grasping/io/plan_output.h"
#include "skelgrasp/presentation/plan_render.h"
#include "skelgrasp/ranking/plan_grasps.h"

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
  checkOutputIsNotInput(args.out, {args.mesh});
  checkOutputIsNotInput(args.render, {args.mesh, args.out});
  const auto hand = args.hand.load();
  MeshLoadInfo info;
  TriangleMesh mesh = loadMesh(args.mesh, args.skeleton.loadOptions(), &info);
  const std::string name = std::filesystem::path(args.mesh).filename().string();
  ranking::PlanOptions options;
  options.planner = ranking::parsePlanner(args.planner.planner);
  options.skeleton = args.skeleton.params();
  options.skeleton_planner = args.planner.skeletonParams();
  options.surface_planner = args.planner.surfaceParams();
  // Robust ranking: the best grasps scored by r and re-ranked (docs/planning.md).
  options.ranking = args.robustness.params(args.planner.seed);
  const ranking::GraspPlan plan = ranking::planGrasps(mesh, hand, options);
  if (plan.skeleton_failed) return fail(args.mesh + ": " + plan.status.message);
  nlohmann::json document = grasping::planToJson(plan, hand, name);
  evaluation::addPlanRecords(document, plan.ranking, plan.timing);
  OutputTransaction outputs;
  if (!args.render.empty()) {
    presentation::renderPlanPng(outputs.stage(args.render), mesh,
                                plan.skeleton ? &plan.skeleton->skeleton : nullptr, plan, hand);
  }
  // The exports before grasps.json: all of them appear together or none does.
  args.exports.stage(outputs, args.out, document, hand);
  writeJsonFile(outputs.stage(args.out), document);
  outputs.commit();
  std::cout << grasping::planSummaryLine(plan, hand.name(), name);
  if (plan.ranking.scored > 0) {
    std::cout << fmt::format("; best r {:.2f} ({} of {} grasps scored, {:.2f} s)",
                             plan.grasps.front().robustness->r, plan.ranking.scored,
                             plan.grasps.size(), plan.timing.ranking_s);
  }
  std::cout << fmt::format("; {:.2f} s in all", plan.timing.total_s()) << std::endl;
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
