#pragma once
// What of the scan the scene check's octree gets besides the targets (RunParams::table_obstacles):
// the table top is left to the support plane's half-space, and points at a target's foot, which
// the segmentation's plane band gave to the table or left in no cluster, are not obstacles of that
// target's own grasps.
#include <optional>

#include "skelgrasp/common/mesh.h"
#include "skelgrasp/common/point_cloud.h"
#include "skelgrasp/perception/scene.h"
#include "skelgrasp/pipeline/run_pipeline.h"

namespace skelgrasp::pipeline::internal {

// The scan's obstacle points that are no selected target, in two parts (points only: the octree
// takes nothing else).
struct ObstacleParts {
  // The clusters not selected as targets: other objects, whole, whatever they touch.
  PointCloud objects;
  // Points in no cluster higher above the support plane than the table's top (table_obstacles;
  // the plane's half-space stands for everything lower): the table's inliers, fragments too small
  // to be objects, clutter.
  PointCloud loose;
};
ObstacleParts obstacleParts(const perception::SceneResult& scene,
                            const std::optional<Eigen::Vector4d>& plane, const RunParams& params);

// `points` split by whether they lie within `distance` of `mesh` (or inside it): `near` holds a
// target's foot, `far` the rest. Points only.
struct SplitByMesh {
  PointCloud near, far;
};
SplitByMesh splitByDistanceToMesh(const PointCloud& points, const TriangleMesh& mesh,
                                  double distance);

}  // namespace skelgrasp::pipeline::internal
