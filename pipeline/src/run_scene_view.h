#pragma once
// The 3D view of a run's report (docs/report.md): the scan, the object(s) coloured by skeleton
// segment, the skeleton and the ranked grasps with the hand closed and their contacts.
#include "skelgrasp/pipeline/run_pipeline.h"
#include "skelgrasp/pipeline/run_scene.h"
#include "skelgrasp/presentation/scene_view.h"

namespace skelgrasp::pipeline {

struct RunSceneViewParams {
  // Scan points embedded at most (an even subset beyond): ~0.6 MB of page data, which with the
  // ~0.9 MB of three.js keeps a report near 2 MB (budget: docs/report.md).
  std::size_t max_scan_points = 60000;
  double scan_point_size_m = 0.002;
  // A scene run shows each object's best grasps only: every grasp of every object would crowd
  // the view and the page. At most max_scene_grasps in all (about 0.6 MB), at least one each.
  std::size_t grasps_per_object = 3;
  std::size_t max_scene_grasps = 150;
  // A scene's object meshes hold at most this many vertices in all (about 1.4 MB of page data);
  // beyond it each larger mesh is decimated to an equal share, no fewer than
  // min_vertices_per_object. The demo's five objects hold 27 000; a 200-object scene's made a
  // 56 MB page.
  std::size_t max_object_vertices = 30000;
  std::size_t min_vertices_per_object = 100;
};

presentation::SceneView3d runSceneView(const RunResult& r, const grasping::HandModel& hand,
                                       const perception::Scan& scan,
                                       const RunSceneViewParams& params = {});

// Every object of a scene run: its mesh by segment, its skeleton and its best grasps.
presentation::SceneView3d sceneRunView(const SceneRunResult& r, const grasping::HandModel& hand,
                                       const perception::Scan& scan,
                                       const RunSceneViewParams& params = {});

}  // namespace skelgrasp::pipeline
