// skelgrasp score GRASPS.json MESH --hand H: re-score given grasps (plan's, run's, or another
// planner's converted to our schema) in one process: close the hand at each grasp's pose, then
// force closure, margin, epsilon and robustness at one or several friction coefficients.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli.h"
#include "grasps_hand.h"
#include "option_checks.h"
#include "output_paths.h"
#include "quality_options.h"
#include "robustness_options.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/evaluation/score.h"

namespace skelgrasp::cli {
namespace {

// Most perturbed poses per grasp (as evaluate): beyond it the Wilson interval is already far
// narrower than anything the simulation can promise.
constexpr std::uint64_t kMaxScoreRobustnessSamples = 1'000'000;

// Defaults are the library's ScoreParams (never a typed copy of a number).
struct ScoreArgs {
  std::string grasps;
  std::string mesh;
  std::string hand;  // empty: the built-in hand the grasps file names
  std::string description;
  std::vector<double> mu = evaluation::ScoreParams{}.frictions;
  int samples = ranking::RobustnessParams{}.samples;
  std::string variant = ranking::toString(ranking::RobustnessParams{}.variant);
  std::uint64_t seed = ranking::RobustnessParams{}.seed;
  bool no_robustness = false;
  bool no_load_check = false;
  std::optional<std::uint64_t> object;
  std::string out = "scores.json";
  std::string closing = defaultClosingMethod();
  std::string contact_patch = defaultContactPatch();
  std::string fc_test = defaultForceClosureTest();
  bool reference_compat = false;
  std::optional<double> torsional_friction_m;  // unset: the hand's contact model
  std::string units = "auto";
};

evaluation::ScoreParams scoreParams(const ScoreArgs& a) {
  evaluation::ScoreParams p;
  p.frictions = a.mu;
  p.quality.fc_test = grasping::parseForceClosureTest(a.fc_test);
  p.quality.reference_compat = a.reference_compat;
  p.quality.torsional_friction_m = a.torsional_friction_m;
  p.closing.method = grasping::parseClosingMethod(a.closing);
  p.closing.contact_patch = grasping::contactPatchFor(a.contact_patch, a.reference_compat);
  p.compute_robustness = !a.no_robustness;
  p.robustness.samples = a.samples;
  p.robustness.variant = ranking::parseRobustnessVariant(a.variant);
  p.robustness.seed = a.seed;
  ranking::setLoadCheck(p.robustness, !a.no_load_check);
  return p;
}

int runScore(const ScoreArgs& a) {
  checkOutputFileOption(a.out);
  checkOutputIsNotInput(a.out, {a.grasps, a.mesh, a.description});
  if (a.mu.size() > evaluation::kMaxScoreFrictions) {
    throw InvalidArgument(
        fmt::format("--mu: {} values, at most {}", a.mu.size(), evaluation::kMaxScoreFrictions));
  }
  const evaluation::ScoreParams params = scoreParams(a);
  const nlohmann::json file = readJsonFile(a.grasps);
  const auto hand = handOfGraspsFile(file, a.grasps, a.hand, a.description);
  std::vector<grasping::GraspPlacement> placements;
  try {
    std::optional<long long> object;
    if (a.object) object = static_cast<long long>(*a.object);
    placements = grasping::readGraspPlacements(file, hand, object);
    // Refused before the mesh is read: the file's grasps times the samples asked for.
    evaluation::checkScoreWork(placements.size(), params);
  } catch (const InvalidArgument& e) {
    throw IoError(a.grasps, e.what());
  }
  MeshLoadOptions load;
  load.units = parseLengthUnit(a.units);
  const TriangleMesh mesh = loadMesh(a.mesh, load);
  const grasping::GraspObject object(mesh);
  const auto result = evaluation::scoreGrasps(hand, object, placements, params);
  OutputTransaction outputs;
  writeJsonFile(
      outputs.stage(a.out),
      evaluation::scoreToJson(result, params, hand,
                              std::filesystem::path(a.mesh).filename().string(), a.grasps));
  outputs.commit();
  std::cout << evaluation::scoreSummaryLine(result, params) << " -> " << a.out << std::endl;
  return kExitOk;
}

}  // namespace

void registerScoreCommand(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand(
      "score",
      "Re-score grasps (plan's, run's or converted ones): contacts, force closure, "
      "epsilon and robustness at one or several mu");
  auto a = std::make_shared<ScoreArgs>();
  cmd->add_option("GRASPS", a->grasps,
                  "grasps.json (schema skelgrasp.grasps/N of plan or skelgrasp.run/N of run)")
      ->required();
  cmd->add_option("MESH", a->mesh, "The object's mesh, in the grasps' frame (.ply .obj .off .stl)")
      ->required();
  cmd->add_option("--hand", a->hand,
                  "Built-in hand or a .urdf file (default: the built-in hand GRASPS names)");
  cmd->add_option("--grasp-description", a->description,
                  "Grasp description JSON for a .urdf hand (docs/hands.md)");
  // No shown default: CLI11 would show the list as "[0.35]", which is no number to check.
  std::string shown_default;
  for (double mu : a->mu)
    shown_default += fmt::format("{}{}", shown_default.empty() ? "" : ",", mu);
  cmd->add_option(
         "--mu", a->mu,
         "Friction coefficients, comma-separated, e.g. 0.35,0.5 (default " + shown_default + ")")
      ->delimiter(',')
      ->check(finiteIn(0, kMaxFriction));
  cmd->add_option("--robustness-samples", a->samples, "Perturbed poses per grasp and mu")
      ->transform(countIn(1, kMaxScoreRobustnessSamples))
      ->capture_default_str();
  addRobustnessVariantOption(*cmd, a->variant);
  cmd->add_option("--seed", a->seed, "Robustness seed (plan's default reproduces plan's r)")
      ->transform(countIn(0, UINT64_MAX))
      ->capture_default_str();
  cmd->add_flag("--no-robustness", a->no_robustness,
                "Force closure, margin and epsilon only (no perturbed closings)");
  cmd->add_flag("--no-load-check", a->no_load_check,
                "r counts force closure alone, not whether the grip carries the object's weight "
                "(as plan --no-load-check)");
  cmd->add_option("--object", a->object,
                  "Run files with several objects: score the grasps of this object id")
      ->transform(countIn(0, kMaxCount));
  cmd->add_option("--out", a->out, "Output scores JSON (schema skelgrasp.score/1)")
      ->capture_default_str();
  addClosingMethodOption(*cmd, a->closing);
  addContactPatchOption(*cmd, a->contact_patch);
  addForceClosureTestOption(*cmd, a->fc_test);
  addTorsionalFrictionOption(*cmd, a->torsional_friction_m);
  cmd->add_flag("--reference-compat", a->reference_compat,
                "Quality as the reference code (docs/hands.md)");
  cmd->add_option("--units", a->units, "Mesh units: auto, m or mm")->capture_default_str();
  cmd->callback([a, &action] { action = [a] { return runScore(*a); }; });
}

}  // namespace skelgrasp::cli
