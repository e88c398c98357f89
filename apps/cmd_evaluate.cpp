// skelgrasp evaluate: objects x hands x planners with robustness, the paper's table; merge: shards.
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <iostream>

#include "cli.h"
#include "help_format.h"
#include "mesh_list.h"
#include "option_checks.h"
#include "output_paths.h"
#include "planner_options.h"
#include "quality_options.h"
#include "robustness_options.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/evaluation/batch.h"
#include "skelgrasp/physics/physical_object.h"

namespace skelgrasp::cli {
namespace {

// Perturbed poses per grasp: the estimate's standard error is already below 0.1 % at a million.
constexpr std::uint64_t kMaxRobustnessSamples = 1'000'000;

std::string join(const std::vector<std::string>& items, char sep) {
  std::string text;
  for (const auto& item : items) text += (text.empty() ? "" : std::string(1, sep)) + item;
  return text;
}

std::string plannerNames(const std::vector<ranking::Planner>& planners) {
  std::vector<std::string> names;
  for (const auto planner : planners) names.push_back(ranking::toString(planner));
  return join(names, ',');
}

// Defaults are BatchParams' (never a typed copy of a number).
struct EvaluateArgs {
  std::vector<std::string> objects;
  std::string hands = join(evaluation::BatchParams{}.hands, ',');
  std::string planners = plannerNames(evaluation::BatchParams{}.planners);
  std::string out = evaluation::BatchParams{}.out_dir;
  std::string shard = "0/1";
  std::string variant = ranking::toString(ranking::RobustnessParams{}.variant);
  std::string units = "auto";
  int samples = ranking::RobustnessParams{}.samples;
  std::size_t robustness_grasps = evaluation::BatchParams{}.robustness_grasps;
  int jobs = evaluation::BatchParams{}.jobs;
  double timeout_s = evaluation::BatchParams{}.timeout_s;
  double mu = grasping::QualityParams{}.friction;
  double vertex_distance_m = evaluation::BatchParams{}.vertex_distance_m;
  bool centre_candidates = evaluation::BatchParams{}.centre_candidates;
  bool alternative_preshapes = evaluation::BatchParams{}.alternative_preshapes;
  std::size_t surface_candidates = evaluation::BatchParams{}.surface_candidates;
  std::size_t limit = evaluation::BatchParams{}.object_limit;
  std::uint64_t seed = evaluation::BatchParams{}.seed;
  bool reference_compat = false;
  std::string fc_test = defaultForceClosureTest();
  bool wrench_volume = grasping::QualityParams{}.compute_volume;
  std::optional<double> torsional_friction_m;  // unset: each hand's contact model
  std::string closing = defaultClosingMethod();
  std::string contact_patch = defaultContactPatch();
  bool restart = false;
  bool retry_failed = false;
  bool robust_ranking = evaluation::BatchParams{}.ranking.enabled;
  std::optional<std::size_t> screen_k;  // unset: each hand's ranking budget
  std::optional<int> screen_samples;
  std::optional<std::string> screen_by;  // unset: each hand's ranking budget
  std::optional<int> confirm_samples;    // unset: each hand's ranking budget
  RobustRefineOptions refine;
  bool no_load_check = false;
  std::string judge = "model";
  std::size_t physics_grasps = evaluation::PhysicsJudging{}.grasps;
  double mass_kg = evaluation::PhysicsJudging{}.mass_kg;
};

// Directories, mesh files, or .txt files listing one mesh path per line (relative to the list).
std::vector<std::string> expandObjects(const std::vector<std::string>& inputs) {
  std::vector<std::string> meshes;
  for (const auto& input : inputs) {
    if (fileExtension(input) == "txt") {
      if (std::filesystem::exists(input) && !std::filesystem::is_regular_file(input))
        throw IoError(input, "is not a regular file");
      std::ifstream in(input);
      if (!in)
        throw IoError(input,
                      std::filesystem::exists(input) ? "cannot open for reading" : "no such file");
      const auto base = std::filesystem::path(input).parent_path();
      for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        const std::filesystem::path p(line);
        const std::string mesh = p.is_absolute() ? line : (base / p).string();
        // Checked before the output directory is locked: a listed device would hang the hashing.
        if (std::filesystem::exists(mesh) && !std::filesystem::is_regular_file(mesh))
          throw IoError(mesh, "is not a regular file (listed in " + input + ")");
        meshes.push_back(mesh);
      }
    } else {
      for (auto& m : collectMeshFiles({input})) meshes.push_back(m);
    }
  }
  return meshes;
}

int runEvaluate(const EvaluateArgs& a) {
  checkOutputDirectoryOption(a.out);
  evaluation::BatchParams p;
  p.objects = expandObjects(a.objects);
  p.object_limit = a.limit;
  p.hands = splitList(a.hands);
  p.planners.clear();
  for (const auto& name : splitList(a.planners)) p.planners.push_back(ranking::parsePlanner(name));
  p.out_dir = a.out;
  p.jobs = a.jobs;
  // Whole numbers only: std::stoi alone would take "1x/4" or "-1/4".
  const auto slash = a.shard.find('/');
  const std::string index = a.shard.substr(0, slash);
  const std::string count = slash == std::string::npos ? "" : a.shard.substr(slash + 1);
  const auto whole = [](const std::string& t) {
    return !t.empty() && t.size() <= 9 && t.find_first_not_of("0123456789") == std::string::npos;
  };
  if (!whole(index) || !whole(count)) {
    throw InvalidArgument("--shard '" + a.shard + "': expected i/n, e.g. 0/4");
  }
  p.shard_index = std::stoi(index);
  p.shard_count = std::stoi(count);
  p.timeout_s = a.timeout_s;
  p.vertex_distance_m = a.vertex_distance_m;
  p.centre_candidates = a.centre_candidates;
  p.alternative_preshapes = a.alternative_preshapes;
  p.surface_candidates = a.surface_candidates;
  p.robustness_grasps = a.robustness_grasps;
  p.robustness.samples = a.samples;
  p.robustness.variant = ranking::parseRobustnessVariant(a.variant);
  p.quality.friction = a.mu;
  p.quality.reference_compat = a.reference_compat;
  p.quality.fc_test = grasping::parseForceClosureTest(a.fc_test);
  p.quality.torsional_friction_m = a.torsional_friction_m;
  p.quality.compute_volume = a.wrench_volume;
  p.robustness.closing.method = grasping::parseClosingMethod(a.closing);
  p.robustness.closing.contact_patch =
      grasping::contactPatchFor(a.contact_patch, a.reference_compat);
  p.ranking.enabled = a.robust_ranking;
  p.ranking.robustness.variant = p.robustness.variant;
  p.ranking.screen_k = a.screen_k;
  p.ranking.screen_samples = a.screen_samples;
  p.ranking.screen_candidates = screenCandidates(a.screen_by);
  p.ranking.confirm_samples = a.confirm_samples;
  a.refine.applyTo(p.ranking.refinement);
  ranking::setLoadCheck(p.ranking.robustness, !a.no_load_check);
  if (a.judge == "physics") {
    p.physics = evaluation::PhysicsJudging{a.physics_grasps, a.mass_kg};
  } else if (a.judge != "model") {
    throw InvalidArgument("--judge: '" + a.judge + "' is not model or physics");
  }
  p.load.units = parseLengthUnit(a.units);
  p.seed = a.seed;
  p.restart = a.restart;
  p.retry_failed = a.retry_failed;
  const auto stats = evaluation::runBatch(p);
  std::cout << fmt::format(
                   "evaluated {} object(s) ({} already done, {} retried, {} changed, {} in shard "
                   "{}), {} failed run(s), {:.1f} s; summary: {}/summary.md",
                   stats.objects_run, stats.objects_skipped, stats.objects_retried,
                   stats.objects_changed, stats.objects_total, a.shard, stats.runs_failed,
                   stats.time_s, a.out)
            << std::endl;
  return kExitOk;
}

}  // namespace

void registerEvaluateCommands(CLI::App& app, Action& action) {
  auto* cmd =
      app.add_subcommand("evaluate", "Plan and score grasps for many objects, hands and planners");
  auto a = std::make_shared<EvaluateArgs>();
  cmd->add_option("--objects", a->objects, "Directories, mesh files or .txt lists of mesh paths")
      ->required();
  cmd->add_option("--hands", a->hands, "Comma-separated built-in hands")->capture_default_str();
  cmd->add_option("--planners", a->planners, "Comma-separated: skeleton, surface")
      ->capture_default_str();
  cmd->add_option("--out", a->out,
                  "Output directory (resumed when it holds earlier results of the same options)")
      ->capture_default_str();
  cmd->add_option("--robustness-samples", a->samples, "Perturbed poses per grasp")
      ->transform(countIn(1, kMaxRobustnessSamples))
      ->capture_default_str();
  cmd->add_option("--robustness-grasps", a->robustness_grasps,
                  "Grasps per run scored for robustness (0 = all)")
      ->transform(countIn(0, kMaxCount))
      ->capture_default_str();
  addRobustnessVariantOption(*cmd, a->variant);
  cmd->add_option("--jobs", a->jobs, "Objects evaluated in parallel")
      ->transform(threadCount(1))
      ->capture_default_str();
  cmd->add_option("--shard", a->shard, "Run only objects k with k % n == i: i/n")
      ->capture_default_str();
  cmd->add_option("--timeout", a->timeout_s, "Per planner run, seconds (0 = none)")
      ->check(finiteIn(0, kMaxTimeoutS))
      ->capture_default_str();
  cmd->add_option("--mu", a->mu, "Friction coefficient")
      ->check(finiteIn(0, kMaxFriction))
      ->capture_default_str();
  cmd->add_flag(
      "--robust-ranking", a->robust_ranking,
      fmt::format("Also rank each run's grasps by robustness as plan does (best {} of {} screened "
                  "unless the hand's ranking budget says otherwise, {} samples each) and report "
                  "the r of the returned top grasps",
                  ranking::RobustRankingParams{}.top_k, ranking::kDefaultScreenK,
                  ranking::RobustRankingParams{}.robustness.samples));
  addScreenOption(*cmd, a->screen_k)->group(kRankingDetails);
  addScreenSamplesOption(*cmd, a->screen_samples)->group(kRankingDetails);
  addScreenByOption(*cmd, a->screen_by)->group(kRankingDetails);
  addConfirmSamplesOption(*cmd, a->confirm_samples)->group(kRankingDetails);
  a->refine.addTo(*cmd);
  cmd->add_flag("--no-load-check", a->no_load_check,
                "With --robust-ranking: r counts force closure alone, not whether the grip "
                "carries the object's weight")
      ->group(kRankingDetails);
  cmd->add_option("--judge", a->judge,
                  "model: the quality model's figures; physics: also execute each run's first "
                  "--physics-grasps grasps in the physics engine (docs/physics.md)")
      ->check(CLI::IsMember({"model", "physics"}))
      ->capture_default_str();
  cmd->add_option("--physics-grasps", a->physics_grasps,
                  "With --judge physics: grasps executed per run, in the run's order")
      ->transform(countIn(1, kMaxCount))
      ->capture_default_str();
  cmd->add_option("--mass", a->mass_kg, "With --judge physics: the object's mass (kg)")
      ->check(positiveFinite(physics::kMaxObjectMassKg))
      ->capture_default_str();
  cmd->add_flag("--reference-compat", a->reference_compat,
                "Quality as the reference code (docs/hands.md)")
      ->group(kPlannerDetails);
  addForceClosureTestOption(*cmd, a->fc_test)->group(kPlannerDetails);
  addTorsionalFrictionOption(*cmd, a->torsional_friction_m)->group(kPlannerDetails);
  addWrenchVolumeFlag(*cmd, a->wrench_volume)->group(kPlannerDetails);
  addClosingMethodOption(*cmd, a->closing)->group(kPlannerDetails);
  addContactPatchOption(*cmd, a->contact_patch)->group(kPlannerDetails);
  cmd->add_option("--vertex-distance", a->vertex_distance_m,
                  "Skeleton planner vertex distance d (m, 0 = every vertex)")
      ->check(lengthOrZero())
      ->capture_default_str()
      ->group(kPlannerDetails);
  addCentreCandidatesFlag(*cmd, a->centre_candidates)->group(kPlannerDetails);
  addAlternativePreshapesFlag(*cmd, a->alternative_preshapes)->group(kPlannerDetails);
  addSurfaceCandidatesOption(*cmd, a->surface_candidates)->group(kPlannerDetails);
  cmd->add_option("--units", a->units, "Mesh units: auto, m or mm")->capture_default_str();
  cmd->add_option("--limit", a->limit, "Only the first N objects (0 = all)")
      ->transform(countIn(0, kMaxCount))
      ->capture_default_str();
  cmd->add_option("--seed", a->seed, "Base seed")
      ->transform(countIn(0, UINT64_MAX))
      ->capture_default_str();
  cmd->add_flag("--restart", a->restart,
                "Discard the runs in --out (also when made with other options) and start afresh");
  cmd->add_flag("--retry-failed", a->retry_failed,
                "Evaluate again the objects whose runs in --out failed");
  cmd->callback([a, &action] { action = [a] { return runEvaluate(*a); }; });

  auto* merge = app.add_subcommand("merge", "Join the outputs of evaluate shards");
  auto dirs = std::make_shared<std::vector<std::string>>();
  auto out = std::make_shared<std::string>("evaluation");
  merge->add_option("DIR", *dirs, "Shard output directories")->required();
  merge->add_option("--out", *out, "Merged output directory")->capture_default_str();
  merge->callback([dirs, out, &action] {
    action = [dirs, out] {
      checkOutputDirectoryOption(*out);
      evaluation::mergeBatches(*dirs, *out);
      std::cout << "merged " << dirs->size() << " shard(s) into " << *out << "/summary.md"
                << std::endl;
      return kExitOk;
    };
  });
}

}  // namespace skelgrasp::cli
