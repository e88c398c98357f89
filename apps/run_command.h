#pragma once
// The `run` pipeline's options, shared by `run` and `demo`.
#include <CLI/CLI.hpp>

#include "export_options.h"
#include "hand_options.h"
#include "planner_options.h"
#include "reconstruct_options.h"
#include "robustness_options.h"
#include "skelgrasp/pipeline/run_pipeline.h"

namespace skelgrasp::cli {

struct RunOptions {
  HandOptions hand;
  PlannerOptions planner;
  RobustnessOptions robustness;
  ReconstructOptions reconstruction;
  double octree_resolution_m = grasping::SceneOccupancyParams{}.resolution_m;
  int object_jobs = pipeline::RunParams{}.object_jobs;
  std::string unknown = "free";
  double pregrasp_m = grasping::SceneCheckParams{}.pregrasp_distance_m;
  double observed_weight = pipeline::RunParams{}.observed_weight;
  bool no_scene_check = false;
  // "on": open hands keep clear of the reconstruction's error bounds
  // (RunParams::surface_clearance).
  std::string surface_clearance = pipeline::RunParams{}.surface_clearance ? "on" : "off";
  // Flat objects on a table (docs/planning.md, "The candidate pool beyond the skeleton
  // strategies").
  double foot_distance_m = pipeline::RunParams{}.table_obstacles.target_foot_distance_m;
  double scene_lift_m = grasping::HypothesisParams{}.scene_lift_max_m;
  double top_centring_m = grasping::FallbackStrategyParams{}.top_centring_band_m;
  std::size_t max_contraction_vertices =
      pipeline::RunParams{}.skeleton.regularisation.max_vertices.value_or(0);
  ExportOptions exports;

  // `single_hand`: the --hand and --export options too (run, demo, bench run); benchmarks over
  // several hands take their own list.
  void addTo(CLI::App& cmd, bool single_hand = true);
  pipeline::RunParams params() const;
};

// The --object value that picks the cluster nearest to `point` ("nearest:x,y,z", 0.1 mm).
std::string nearestObjectOption(const Eigen::Vector3d& point);

// Runs the pipeline on a loaded scan, writes DIR's files, prints the stage times and a summary.
int runOnScan(const perception::Scan& scan, const std::string& name, const std::string& out_dir,
              const RunOptions& options);

}  // namespace skelgrasp::cli
