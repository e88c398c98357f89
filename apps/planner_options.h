#pragma once
// Command-line options of the planners, shared by the commands that plan.
#include <CLI/CLI.hpp>

#include "option_checks.h"

#include <algorithm>

#include "quality_options.h"
#include "skelgrasp/grasping/planners.h"

namespace skelgrasp::cli {

struct PlannerOptions {
  std::string planner = "skeleton";
  double timeout_s = 30;
  std::size_t max_grasps = 0;
  std::size_t surface_hypotheses = 0;  // 0: as many as the timeout allows (or 500 without one)
  std::uint64_t seed = 1;
  double min_epsilon = 0;
  double mu = 0.35;
  double vertex_distance_m = 0;
  double round_ratio = 0;
  bool reference_compat = false;
  std::string fc_test = defaultForceClosureTest();
  std::string closing = defaultClosingMethod();

  // `choice`: also --planner and --hypotheses (commands that can run either planner).
  void addTo(CLI::App& cmd, bool choice = true) {
    if (choice) {
      cmd.add_option("--planner", planner, "skeleton or surface")
          ->check(CLI::IsMember({"skeleton", "surface"}))
          ->capture_default_str();
      cmd.add_option(
             "--hypotheses", surface_hypotheses,
             "Surface planner: number of hypotheses (0 = until the timeout, 500 without one)")
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
        ->capture_default_str();
    cmd.add_option("--mu", mu, "Friction coefficient")
        ->check(finiteIn(0, kMaxFriction))
        ->capture_default_str();
    cmd.add_option("--vertex-distance", vertex_distance_m,
                   "Skeleton vertex distance d in metres (0 = every vertex)")
        ->check(lengthOrZero())
        ->capture_default_str();
    cmd.add_option("--round-ratio", round_ratio,
                   "lambda1/lambda2 below this is round (0 = the hand's, 1.2)")
        ->check(finiteIn(0, kMaxRatio))
        ->capture_default_str();
    cmd.add_flag("--reference-compat", reference_compat,
                 "Quality as the reference code (docs/hands.md)");
    addForceClosureTestOption(cmd, fc_test);
    addClosingMethodOption(cmd, closing);
  }

  grasping::HypothesisParams hypothesis() const {
    grasping::HypothesisParams h;
    h.quality.friction = mu;
    h.quality.reference_compat = reference_compat;
    h.quality.fc_test = grasping::parseForceClosureTest(fc_test);
    h.closing.method = grasping::parseClosingMethod(closing);
    return h;
  }

  grasping::SkeletonPlannerParams skeletonParams() const {
    grasping::SkeletonPlannerParams p;
    p.timeout_s = timeout_s;
    p.max_grasps = max_grasps;
    p.seed = seed;
    p.min_epsilon = min_epsilon;
    p.vertex_distance_m = vertex_distance_m;
    p.round_ratio = round_ratio;
    p.hypothesis = hypothesis();
    return p;
  }

  grasping::SurfacePlannerParams surfaceParams() const {
    grasping::SurfacePlannerParams p;
    p.timeout_s = timeout_s;
    p.max_hypotheses = surface_hypotheses > 0 ? surface_hypotheses : (timeout_s > 0 ? 0 : 500);
    p.max_grasps = max_grasps;
    p.seed = seed;
    p.min_epsilon = min_epsilon;
    p.hypothesis = hypothesis();
    return p;
  }
};

}  // namespace skelgrasp::cli
