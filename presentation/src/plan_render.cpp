#include "skelgrasp/presentation/plan_render.h"

#include <fmt/format.h>

#include "skelgrasp/geometry/mesh_query.h"
#include "skelgrasp/presentation/hand_render.h"
#include "skelgrasp/presentation/render.h"

namespace skelgrasp::presentation {

void renderPlanPng(const std::string& path, const TriangleMesh& object,
                   const skeleton::Skeleton* skeleton, const grasping::PlanResult& result,
                   const grasping::HandModel& hand, int panel_size) {
  TriangleMesh grey = object;
  grey.vertex_colors.clear();
  const AxisAlignedBox box = object.bounds();
  const double line_length = 0.25 * box.diagonal();
  const geometry::MeshQuery surface(object);
  std::vector<presentation::Canvas> panels;
  for (const Eigen::Vector3d& view :
       {Eigen::Vector3d(1.0, -1.2, 0.8), Eigen::Vector3d(-1.0, 1.2, -0.4)}) {
    presentation::Canvas canvas(presentation::Camera::framing(box, view, panel_size, panel_size));
    canvas.drawMesh(grey, {210, 210, 210}, false);
    if (skeleton) {
      for (const auto& e : skeleton->edges) {
        canvas.drawLine(skeleton->vertices[e[0]].position, skeleton->vertices[e[1]].position,
                        {60, 60, 60}, 2);
      }
    }
    for (const auto& g : result.grasps) {
      // Line from outside along the approach to where it enters the surface (the grasp centre
      // point projected onto the object, as the paper's Fig. 9).
      const Eigen::Vector3d approach = g.gcp_pose.rotation().col(2);
      const Eigen::Vector3d centre = g.gcp_pose.translation() + g.retreat_m * approach;
      const Eigen::Vector3d end =
          surface.firstHit(centre - box.diagonal() * approach, approach).value_or(centre);
      const Rgb colour =
          g.type == grasping::GraspType::kPower ? Rgb{30, 150, 60} : Rgb{30, 90, 200};
      canvas.drawLine(end - line_length * approach, end, colour, 1);
      canvas.drawPoint(end, {200, 30, 30}, 2);
    }
    canvas.drawText(8, 4,
                    fmt::format("{} {}: {} grasps (green power, blue precision)", hand.name(),
                                result.planner, result.grasps.size()));
    panels.push_back(std::move(canvas));
  }
  // The best grasp, hand closed.
  AxisAlignedBox wide = box;
  if (!result.grasps.empty()) {
    const grasping::Grasp& best = result.grasps.front();
    const TriangleMesh hand_mesh = handMesh(hand, best.hand_pose, best.joints);
    for (const auto& v : hand_mesh.vertices) wide.extend(v);
    const Eigen::Vector3d approach = best.gcp_pose.rotation().col(2);
    const Eigen::Vector3d side = anyPerpendicular(approach);
    presentation::Canvas canvas(presentation::Camera::framing(
        wide, side - 0.5 * approach + 0.3 * approach.cross(side), panel_size, panel_size));
    canvas.drawMesh(grey, {210, 210, 210}, false);
    canvas.drawMesh(hand_mesh, {0, 0, 0});
    drawContacts(canvas, best.contacts, 0.02);
    canvas.drawText(8, 4,
                    fmt::format("best: {} {} eps {:.3f}", grasping::toString(best.type),
                                best.strategy, best.epsilon));
    panels.push_back(std::move(canvas));
  } else {
    presentation::Canvas canvas(
        presentation::Camera::framing(box, {1, 1, 1}, panel_size, panel_size));
    canvas.drawText(8, 4, "no grasp found");
    panels.push_back(std::move(canvas));
  }
  presentation::Canvas::saveGrid({&panels[0], &panels[1], &panels[2]}, 3, path);
}

}  // namespace skelgrasp::presentation
