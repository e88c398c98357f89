#include "skelgrasp/presentation/hand_render.h"

#include "skelgrasp/geometry/shapes.h"

namespace skelgrasp::presentation {
// Hands drawn from the grasping stage's own types throughout.
using namespace grasping;

namespace {

const Rgb kFingerColours[] = {
    {214, 96, 77}, {67, 147, 195}, {90, 174, 97}, {153, 112, 171}, {240, 163, 10}};

TriangleMesh shapeMesh(const CollisionShape& shape) {
  switch (shape.type) {
    case ShapeType::kBox:
      return geometry::shapes::makeBox(shape.box_size);
    case ShapeType::kSphere:
      return geometry::shapes::makeSphere(shape.radius, 16, 8);
    case ShapeType::kCylinder:
      return geometry::shapes::makeCylinder(shape.radius, shape.length, 24, 1);
    case ShapeType::kMesh:
      return *shape.mesh;
  }
  return {};
}

}  // namespace

TriangleMesh linkMesh(const HandModel& hand, int link) {
  TriangleMesh out;
  for (const auto& shape : hand.links().at(static_cast<std::size_t>(link)).shapes) {
    TriangleMesh part = shapeMesh(shape);
    part.transform(shape.origin);
    part.vertex_colors.clear();
    if (out.vertices.empty()) {
      out = part;
    } else {
      out.append(part);
    }
  }
  return out;
}

Rgb linkColour(const HandModel& hand, int link) {
  const int finger = hand.fingerOfLink(link);
  return finger < 0 ? Rgb{150, 150, 160} : kFingerColours[finger % 5];
}

TriangleMesh handMesh(const HandModel& hand, const Pose& hand_pose, const Eigen::VectorXd& q) {
  TriangleMesh out;
  out.vertex_colors.clear();
  const auto poses = hand.linkPoses(q);
  for (std::size_t l = 0; l < hand.links().size(); ++l) {
    const int finger = hand.fingerOfLink(static_cast<int>(l));
    const Rgb colour = finger < 0 ? Rgb{150, 150, 160} : kFingerColours[finger % 5];
    for (const auto& shape : hand.links()[l].shapes) {
      TriangleMesh part = shapeMesh(shape);
      part.transform(hand_pose * poses[l] * shape.origin);
      part.vertex_colors.assign(part.numVertices(), colour);
      if (out.vertices.empty()) {
        out = part;
      } else {
        out.append(part);
      }
    }
  }
  return out;
}

void drawContacts(Canvas& canvas, const std::vector<Contact>& contacts, double normal_length_m) {
  for (const auto& c : contacts) {
    const Rgb colour = c.palm ? Rgb{255, 140, 0} : Rgb{220, 20, 60};
    canvas.drawLine(c.point, c.point + normal_length_m * c.normal, colour, 2);
    canvas.drawPoint(c.point, colour, 4);
  }
}

void renderGraspPng(const std::string& path, const TriangleMesh& object, const HandModel& hand,
                    const Pose& hand_pose, const Eigen::VectorXd& preshape_q,
                    const Eigen::VectorXd& closed_q, const std::vector<Contact>& contacts,
                    int panel_size) {
  const TriangleMesh open_hand = handMesh(hand, hand_pose, preshape_q);
  const TriangleMesh closed_hand = handMesh(hand, hand_pose, closed_q);
  AxisAlignedBox box = object.bounds();
  for (const auto& v : open_hand.vertices) box.extend(v);
  TriangleMesh grey = object;
  grey.vertex_colors.clear();
  // Views across the approach axis so the fingers are seen from the side and from the front.
  const Eigen::Vector3d approach = hand_pose.rotation() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d side = anyPerpendicular(approach);
  const std::vector<Eigen::Vector3d> views = {side + 0.3 * approach.cross(side) - 0.4 * approach,
                                              approach.cross(side) + 0.3 * side - 0.4 * approach};
  std::vector<Canvas> panels;
  for (const auto& view : views) {
    for (int closed = 0; closed < 2; ++closed) {
      Canvas canvas(Camera::framing(box, view, panel_size, panel_size));
      canvas.drawMesh(grey, {200, 200, 200}, false);
      canvas.drawMesh(closed ? closed_hand : open_hand, {0, 0, 0});
      if (closed) drawContacts(canvas, contacts, 0.02);
      canvas.drawText(8, 4, closed ? "closed, contacts (red), palm contacts (orange)" : "preshape");
      panels.push_back(std::move(canvas));
    }
  }
  Canvas::saveGrid({&panels[0], &panels[1], &panels[2], &panels[3]}, 2, path);
}

}  // namespace skelgrasp::presentation
