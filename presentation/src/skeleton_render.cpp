#include "skelgrasp/presentation/skeleton_render.h"

#include <fmt/format.h>

#include "skelgrasp/presentation/render.h"
#include "skelgrasp/skeleton/output.h"

namespace skelgrasp::presentation {

void renderSkeletonPng(const TriangleMesh& input, const skeleton::Skeleton& skeleton,
                       const std::string& path, int panel_width, int panel_height) {
  const TriangleMesh coloured = skeleton::colourByVertexType(input, skeleton);
  const AxisAlignedBox box = input.bounds();
  const std::vector<Eigen::Vector3d> views = {{1.0, -1.2, 0.8}, {-1.0, 1.2, -0.5}};
  std::vector<presentation::Canvas> panels;
  for (const auto& view : views) {
    presentation::Canvas canvas(
        presentation::Camera::framing(box, view, panel_width, panel_height));
    canvas.drawMesh(coloured, {200, 200, 200});
    canvas.drawText(8, 4, "segmentation: red endpoint, yellow connecting, blue branch");
    panels.push_back(std::move(canvas));
  }
  for (const auto& view : views) {
    presentation::Canvas canvas(
        presentation::Camera::framing(box, view, panel_width, panel_height));
    TriangleMesh grey = input;
    grey.vertex_colors.clear();
    canvas.drawMesh(grey, {225, 225, 225}, false);
    for (const auto& e : skeleton.edges) {
      canvas.drawLine(skeleton.vertices[e[0]].position, skeleton.vertices[e[1]].position, {0, 0, 0},
                      2);
    }
    for (const auto& v : skeleton.vertices) {
      if (v.type == skeleton::VertexType::kEndpoint) canvas.drawPoint(v.position, {220, 30, 30}, 5);
      if (v.type == skeleton::VertexType::kBranch) canvas.drawPoint(v.position, {40, 80, 220}, 5);
    }
    canvas.drawText(
        8, 4,
        fmt::format("skeleton: {} vertices, {} segments, {} loop(s)", skeleton.vertices.size(),
                    skeleton.segments.size(), skeleton.cycleRank()));
    panels.push_back(std::move(canvas));
  }
  presentation::Canvas::saveGrid({&panels[0], &panels[1], &panels[2], &panels[3]}, 2, path);
}

}  // namespace skelgrasp::presentation
