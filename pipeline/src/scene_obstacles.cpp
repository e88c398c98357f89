#include "scene_obstacles.h"

#include "skelgrasp/common/error.h"
#include "skelgrasp/geometry/mesh_query.h"

namespace skelgrasp::pipeline::internal {

namespace {

// The points higher above the plane than the table's top (without a plane: all of them). The
// plane's half-space is an obstacle everywhere below it, so lower points add nothing but cells
// standing above the table.
void appendAboveTableTop(const PointCloud& points, const std::optional<Eigen::Vector4d>& plane,
                         double top_m, PointCloud& out) {
  const Eigen::Vector3d normal =
      plane ? Eigen::Vector3d(plane->head<3>()) : Eigen::Vector3d::Zero();
  const double norm = normal.norm();
  for (const Eigen::Vector3d& p : points.points) {
    // The coefficients as given (a x + b y + c z + d): heights need the unit normal.
    if (!(norm > 0) || (normal.dot(p) + (*plane)[3]) / norm > top_m) out.points.push_back(p);
  }
}

}  // namespace

ObstacleParts obstacleParts(const perception::SceneResult& scene,
                            const std::optional<Eigen::Vector4d>& plane, const RunParams& params) {
  const double top =
      params.table_obstacles.surface_height_m.value_or(params.approach.plane_tolerance_m);
  if (!(top >= 0)) throw InvalidArgument("table obstacles: the surface height must be >= 0");
  ObstacleParts parts;
  parts.objects.sensor_origin = parts.loose.sensor_origin = scene.loose_points.sensor_origin;
  std::vector<char> selected(scene.clusters.size(), 0);
  for (std::size_t c : scene.selected) selected.at(c) = 1;
  for (std::size_t c = 0; c < scene.clusters.size(); ++c) {
    if (!selected[c]) {
      const auto& points = scene.clusters[c].points;
      parts.objects.points.insert(parts.objects.points.end(), points.begin(), points.end());
    }
  }
  appendAboveTableTop(scene.loose_points, plane, top, parts.loose);
  appendAboveTableTop(scene.plane_points, plane, top, parts.loose);
  return parts;
}

SplitByMesh splitByDistanceToMesh(const PointCloud& points, const TriangleMesh& mesh,
                                  double distance) {
  if (!(distance >= 0)) throw InvalidArgument("table obstacles: the foot distance must be >= 0");
  SplitByMesh split;
  split.near.sensor_origin = split.far.sensor_origin = points.sensor_origin;
  if (mesh.empty() || distance == 0) {
    split.far.points = points.points;
    return split;
  }
  AxisAlignedBox reach = mesh.bounds();
  reach.min.array() -= distance;
  reach.max.array() += distance;
  const geometry::MeshQuery query(mesh);
  for (const Eigen::Vector3d& p : points.points) {
    // The box test first: most points lie far from the object, and the exact query walks the
    // mesh's tree.
    const bool in_reach =
        (p.array() >= reach.min.array()).all() && (p.array() <= reach.max.array()).all();
    const bool near = in_reach && (query.distance(p) <= distance || query.contains(p));
    (near ? split.near : split.far).points.push_back(p);
  }
  return split;
}

}  // namespace skelgrasp::pipeline::internal
