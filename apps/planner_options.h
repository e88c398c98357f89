#pragma once
// Command-line options of the planners, shared by the commands that plan.
#include <CLI/CLI.hpp>

#include "help_format.h"
#include "option_checks.h"

#include <fmt/format.h>

#include <algorithm>
#include <optional>

#include "quality_options.h"
#include "skelgrasp/grasping/planning/planners.h"
#include "skelgrasp/ranking/limits.h"

namespace skelgrasp::cli {

// --timeout and --mu take the ranges the Python module takes.
static_assert(kMaxTimeoutS == ranking::kMaxPlanTimeoutS);
static_assert(kMaxFriction == ranking::kMaxFriction);

// Planning time limit of the commands (the library's default is none: on the command line a
// forgotten limit would let a planner run for minutes on a large mesh).
constexpr double kDefaultPlanningTimeoutS = 30;
// More refinement evaluations than this per hypothesis is a typing mistake (each is a closing).
constexpr int kMaxRefineEvaluations = 1000;

// --centre-candidates / --no-centre-candidates, the same on every command that plans.
inline CLI::Option* addCentreCandidatesFlag(CLI::App& cmd, bool& centre_candidates) {
  return cmd.add_flag("--centre-candidates,!--no-centre-candidates", centre_candidates,
                      "Skeleton planner: also try power and precision grasps about the object's "
                      "centre on every object, the robust ones the ranking chooses from "
                      "(docs/planning.md)");
}

// --alternative-preshapes / --no-alternative-preshapes, the same on every command that plans.
inline CLI::Option* addAlternativePreshapesFlag(CLI::App& cmd, bool& alternative_preshapes) {
  return cmd
      .add_flag("--alternative-preshapes,!--no-alternative-preshapes", alternative_preshapes,
                "Skeleton planner: also close every pose with the hand's alternative preshapes of "
                "its grasp type (the SDH's tripods; docs/hands.md); off with "
                "--reference-compat")
      ->capture_default_str();
}

// --surface-candidates, the same on every command that plans.
inline CLI::Option* addSurfaceCandidatesOption(CLI::App& cmd, std::size_t& surface_candidates) {
  return cmd
      .add_option("--surface-candidates", surface_candidates,
                  "Skeleton planner: also try this many surface-normal hypotheses and add their "
                  "grasps to the pool the ranking chooses from (0 = none; docs/planning.md)")
      ->transform(countIn(0, kMaxCount))
      ->capture_default_str();
}

// Defaults are the library's Params (never a typed copy of a number), except the time limit.
struct PlannerOptions {
  std::string planner = "skeleton";
  double timeout_s = kDefaultPlanningTimeoutS;
  std::size_t max_grasps = grasping::SkeletonPlannerParams{}.max_grasps;
  // 0: as many as the timeout allows (or SurfacePlannerParams' count without one).
  std::size_t surface_hypotheses = 0;
  std::uint64_t seed = grasping::SkeletonPlannerParams{}.seed;
  double min_epsilon = grasping::HypothesisParams{}.min_epsilon;
  double mu = grasping::QualityParams{}.friction;
  double vertex_distance_m = grasping::SkeletonPlannerParams{}.vertex_distance_m;
  std::optional<double> round_ratio;  // unset: the hand's
  bool reference_compat = false;
  bool no_fallback = false;  // skeleton planner: the skeleton strategies only
  bool centre_candidates = grasping::SkeletonPlannerParams{}.centre_candidates;
  bool alternative_preshapes = grasping::SkeletonPlannerParams{}.alternative_preshapes;
  std::size_t surface_candidates = grasping::SkeletonPlannerParams{}.surface_candidates;
  std::string fc_test = defaultForceClosureTest();
  bool wrench_volume = grasping::QualityParams{}.compute_volume;
  std::string closing = defaultClosingMethod();
  std::string contact_patch = defaultContactPatch();
  int refine_evaluations = grasping::RefinementParams{}.max_evaluations;
  std::optional<double> torsional_friction_m;  // unset: the hand's contact model
  bool refine = grasping::RefinementParams{}.enabled;
  double precision_retreat_m = grasping::SkeletonPlannerParams{}.precision_retreat_m;

  // `choice`: also --planner and --hypotheses (commands that can run either planner). --min-epsilon
  // and the options after --mu are in kPlannerDetails (--help-all).
  void addTo(CLI::App& cmd, bool choice = true) {
    if (choice) {
      cmd.add_option("--planner", planner, "skeleton or surface")
          ->check(CLI::IsMember({"skeleton", "surface"}))
          ->capture_default_str();
      cmd.add_option("--hypotheses", surface_hypotheses,
                     fmt::format("Surface planner: number of hypotheses (0 = until the timeout, {} "
                                 "without one)",
                                 grasping::SurfacePlannerParams{}.max_hypotheses))
          ->transform(countIn(0, kMaxCount))
          ->capture_default_str();
    }
    cmd.add_option("--timeout", timeout_s, "Planning time limit in seconds (0 = none)")
        ->check(finiteIn(0, kMaxTimeoutS))
        ->capture_default_str();
    cmd.add_option("--max-grasps", max_grasps, "Stop after this many grasps (0 = no limit)")
        ->transform(countIn(0, kMaxCount))
        ->capture_default_str();
    cmd.add_option("--seed", seed, "Random seed (vertex order, surface samples)")
        ->transform(countIn(0, UINT64_MAX))
        ->capture_default_str();
    cmd.add_option("--min-epsilon", min_epsilon, "Reject grasps with a lower epsilon")
        ->check(finiteIn(0, kMaxRatio))
        ->capture_default_str()
        ->group(kPlannerDetails);
    cmd.add_option("--mu", mu, "Friction coefficient")
        ->check(finiteIn(0, kMaxFriction))
        ->capture_default_str();
    cmd.add_option("--vertex-distance", vertex_distance_m,
                   "Skeleton vertex distance d in metres (0 = every vertex)")
        ->check(lengthOrZero())
        ->capture_default_str()
        ->group(kPlannerDetails);
    // No shown default: unset means the hand's own ratio.
    cmd.add_option("--round-ratio", round_ratio,
                   fmt::format("lambda1/lambda2 below this is round (default: the hand's; {} for "
                               "the built-in hands)",
                               grasping::PlannerThresholds{}.round_ratio))
        ->check(finiteIn(0, kMaxRatio))
        ->group(kPlannerDetails);
    cmd.add_flag("--reference-compat", reference_compat,
                 "Quality as the reference code (docs/hands.md)")
        ->group(kPlannerDetails);
    cmd.add_option("--precision-retreat", precision_retreat_m,
                   "Skeleton planner: back precision grasps' open hand off this much further "
                   "than the first collision-free pose, in metres (0 = as the paper; 0.008 gave "
                   "more robust grasps, docs/planning.md)")
        ->check(lengthOrZero())
        ->capture_default_str()
        ->group(kPlannerDetails);
    cmd.add_flag("--no-fallback", no_fallback,
                 "Skeleton planner: no fallback strategies for objects whose skeleton gives few "
                 "grasps (docs/planning.md)")
        ->group(kPlannerDetails);
    addCentreCandidatesFlag(cmd, centre_candidates)->group(kPlannerDetails);
    addAlternativePreshapesFlag(cmd, alternative_preshapes)->group(kPlannerDetails);
    addSurfaceCandidatesOption(cmd, surface_candidates)->group(kPlannerDetails);
    addForceClosureTestOption(cmd, fc_test)->group(kPlannerDetails);
    addTorsionalFrictionOption(cmd, torsional_friction_m)->group(kPlannerDetails);
    addWrenchVolumeFlag(cmd, wrench_volume)->group(kPlannerDetails);
    addClosingMethodOption(cmd, closing)->group(kPlannerDetails);
    addContactPatchOption(cmd, contact_patch)->group(kPlannerDetails);
    cmd.add_option("--refine-evaluations", refine_evaluations,
                   "Skeleton planner: poses tried around each closed hypothesis by local "
                   "refinement (0 = none, but each grasp records its closure margin)")
        ->check(CLI::Range(0, kMaxRefineEvaluations))
        ->capture_default_str()
        ->group(kPlannerDetails);
    cmd.add_flag("--refine,!--no-refine", refine,
                 "Skeleton planner: local refinement of every closed hypothesis (off by default: "
                 "8-12x slower planning; docs/planning.md)")
        ->group(kPlannerDetails);
  }

  grasping::HypothesisParams hypothesis() const {
    grasping::HypothesisParams h;
    h.min_epsilon = min_epsilon;
    h.quality.friction = mu;
    h.quality.reference_compat = reference_compat;
    h.quality.fc_test = grasping::parseForceClosureTest(fc_test);
    h.quality.torsional_friction_m = torsional_friction_m;
    h.quality.compute_volume = wrench_volume;
    h.closing.method = grasping::parseClosingMethod(closing);
    h.closing.contact_patch = grasping::contactPatchFor(contact_patch, reference_compat);
    return h;
  }

  grasping::SkeletonPlannerParams skeletonParams() const {
    grasping::SkeletonPlannerParams p;
    p.timeout_s = timeout_s;
    p.max_grasps = max_grasps;
    p.seed = seed;
    p.vertex_distance_m = vertex_distance_m;
    p.round_ratio = round_ratio;
    p.fallback = !no_fallback;
    p.centre_candidates = centre_candidates;
    p.alternative_preshapes = alternative_preshapes;
    p.surface_candidates = surface_candidates;
    p.precision_retreat_m = precision_retreat_m;
    p.hypothesis = hypothesis();
    p.refinement.enabled = refine;
    p.refinement.max_evaluations = refine_evaluations;
    return p;
  }

  grasping::SurfacePlannerParams surfaceParams() const {
    grasping::SurfacePlannerParams p;
    p.timeout_s = timeout_s;
    if (surface_hypotheses > 0 || timeout_s > 0) p.max_hypotheses = surface_hypotheses;
    p.max_grasps = max_grasps;
    p.seed = seed;
    p.hypothesis = hypothesis();
    return p;
  }
};

}  // namespace skelgrasp::cli
