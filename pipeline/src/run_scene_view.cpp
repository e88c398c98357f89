#include "run_scene_view.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "skelgrasp/geometry/point_index.h"
#include "skelgrasp/geometry/regularisation.h"
#include "skelgrasp/presentation/hand_render.h"
#include "skelgrasp/skeleton/output.h"

namespace skelgrasp::pipeline {
namespace {

using namespace grasping;

const Rgb kScanGrey{120, 130, 150};
const Rgb kObjectBeige{215, 200, 170};
const Rgb kSkeletonBlack{20, 20, 20};

void addScan(presentation::SceneView3d& view, const perception::Scan& scan,
             const RunSceneViewParams& params) {
  std::vector<Eigen::Vector3d> points;
  std::vector<Rgb> colours;
  const bool coloured = scan.cloud.hasColors();
  for (std::size_t i = 0; i < scan.cloud.size(); ++i) {
    if (!scan.cloud.points[i].allFinite()) continue;
    points.push_back(scan.cloud.points[i]);
    if (coloured) colours.push_back(scan.cloud.colors[i]);
  }
  view.addPoints("scan", points, colours, params.scan_point_size_m, params.max_scan_points);
}

void addSkeleton(presentation::SceneView3d& view, const skeleton::Skeleton& skel) {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments;
  for (const auto& e : skel.edges) {
    segments.emplace_back(skel.vertices[e[0]].position, skel.vertices[e[1]].position);
  }
  view.addLines("skeleton", segments, kSkeletonBlack);
}

// Each link's geometry is embedded once; a grasp is only its link poses.
std::vector<int> addHandParts(presentation::SceneView3d& view, const grasping::HandModel& hand) {
  std::vector<int> part_of_link(hand.links().size(), -1);
  for (std::size_t l = 0; l < hand.links().size(); ++l) {
    const TriangleMesh mesh = presentation::linkMesh(hand, static_cast<int>(l));
    if (!mesh.empty())
      part_of_link[l] = view.addPart(mesh, presentation::linkColour(hand, static_cast<int>(l)));
  }
  return part_of_link;
}

void addGrasps(presentation::SceneView3d& view, const std::vector<RankedGrasp>& ranked,
               std::size_t shown, const grasping::HandModel& hand,
               const std::vector<int>& part_of_link, const std::string& label_prefix) {
  for (std::size_t k = 0; k < std::min(shown, ranked.size()); ++k) {
    const Grasp& g = ranked[k].grasp;
    const auto link_poses = hand.linkPoses(g.joints);
    std::vector<std::pair<int, Pose>> parts;
    for (std::size_t l = 0; l < link_poses.size(); ++l) {
      if (part_of_link[l] >= 0) parts.emplace_back(part_of_link[l], g.hand_pose * link_poses[l]);
    }
    std::vector<presentation::SceneViewContact> contacts;
    for (const auto& c : g.contacts) contacts.push_back({c.point, c.normal});
    view.addGrasp(
        fmt::format("{}#{} {} {} — ε {:.3f}, score {:.3f}, {} contacts", label_prefix, k,
                    toString(g.type), g.strategy, g.epsilon, ranked[k].score, g.contacts.size()),
        parts, contacts);
  }
}

// `coloured` with about `max_vertices` vertices for the view (edge collapse, which keeps it
// closed), each vertex taking the colour of the nearest original one; as it is when it has no more
// or the collapse fails.
TriangleMesh decimatedForView(const TriangleMesh& coloured, std::size_t max_vertices) {
  if (coloured.numVertices() <= max_vertices) return coloured;
  geometry::RegularisationParams params;
  params.method = geometry::RegularisationMethod::kNone;
  params.max_vertices = max_vertices;
  auto result = geometry::regularise(coloured, params);
  if (!result.status.ok()) return coloured;
  TriangleMesh out = std::move(result.mesh);
  if (coloured.vertex_colors.size() == coloured.numVertices()) {
    const geometry::PointIndex original(coloured.vertices);
    out.vertex_colors.resize(out.numVertices());
    for (std::size_t v = 0; v < out.numVertices(); ++v) {
      const int nearest = original.nearest(out.vertices[v]).first;
      if (nearest >= 0) out.vertex_colors[v] = coloured.vertex_colors[nearest];
    }
  }
  return out;
}

void addObject(presentation::SceneView3d& view, const std::string& layer, const TriangleMesh& mesh,
               const std::optional<skeleton::SkeletonResult>& skeleton,
               std::size_t max_vertices = std::numeric_limits<std::size_t>::max()) {
  if (mesh.empty()) return;
  const bool segmented = skeleton && skeleton->status.ok();
  view.addMesh(
      layer,
      decimatedForView(segmented ? skeleton::colourBySegment(mesh, skeleton->skeleton) : mesh,
                       max_vertices),
      kObjectBeige);
  if (segmented) addSkeleton(view, skeleton->skeleton);
}

}  // namespace

presentation::SceneView3d runSceneView(const RunResult& r, const grasping::HandModel& hand,
                                       const perception::Scan& scan,
                                       const RunSceneViewParams& params) {
  presentation::SceneView3d view;
  addScan(view, scan, params);
  addObject(view, "object", r.mesh, r.skeleton);
  const auto parts = addHandParts(view, hand);
  addGrasps(view, r.ranked, r.ranked.size(), hand, parts, "");
  return view;
}

presentation::SceneView3d sceneRunView(const SceneRunResult& r, const grasping::HandModel& hand,
                                       const perception::Scan& scan,
                                       const RunSceneViewParams& params) {
  presentation::SceneView3d view;
  addScan(view, scan, params);
  const auto parts = addHandParts(view, hand);
  std::size_t vertices = 0, meshes = 0;
  for (const auto& object : r.objects) {
    vertices += object.mesh.numVertices();
    meshes += !object.mesh.empty();
  }
  const std::size_t share =
      vertices <= params.max_object_vertices
          ? std::numeric_limits<std::size_t>::max()
          : std::max(params.min_vertices_per_object, params.max_object_vertices / meshes);
  const std::size_t grasps_each =
      std::min(params.grasps_per_object,
               std::max<std::size_t>(
                   1, params.max_scene_grasps / std::max<std::size_t>(1, r.objects.size())));
  for (const auto& object : r.objects) {
    addObject(view, fmt::format("object {}", object.id), object.mesh, object.skeleton, share);
    addGrasps(view, object.ranked, grasps_each, hand, parts, fmt::format("object {} ", object.id));
  }
  return view;
}

}  // namespace skelgrasp::pipeline
