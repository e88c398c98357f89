#pragma once
// The 3D view of a run's report (docs/report.md): the scan, the object coloured by skeleton
// segment, the skeleton and every ranked grasp with the hand closed and its contacts.
#include "skelgrasp/common/scene_view.h"
#include "skelgrasp/pipeline/run_pipeline.h"

namespace skelgrasp::pipeline {

struct RunSceneViewParams {
  // Scan points embedded at most (an even subset beyond): ~0.6 MB of page data, which with the
  // ~0.9 MB of three.js keeps a report near 2 MB (budget: docs/report.md).
  std::size_t max_scan_points = 60000;
  double scan_point_size_m = 0.002;
};

SceneView3d runSceneView(const RunResult& r, const grasping::HandModel& hand,
                         const perception::Scan& scan, const RunSceneViewParams& params = {});

}  // namespace skelgrasp::pipeline
