#include "fcl_conversions.h"

#include "skelgrasp/common/error.h"

namespace skelgrasp::grasping::internal {

template <typename BV>
std::shared_ptr<fcl::BVHModel<BV>> toFclBvh(const TriangleMesh& mesh) {
  std::vector<fcl::Vector3d> points(mesh.vertices.begin(), mesh.vertices.end());
  std::vector<fcl::Triangle> triangles;
  triangles.reserve(mesh.faces.size());
  for (const auto& f : mesh.faces) triangles.emplace_back(f[0], f[1], f[2]);
  auto bvh = std::make_shared<fcl::BVHModel<BV>>();
  bvh->beginModel(static_cast<int>(triangles.size()), static_cast<int>(points.size()));
  bvh->addSubModel(points, triangles);
  bvh->endModel();
  bvh->computeLocalAABB();
  return bvh;
}

template std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> toFclBvh(const TriangleMesh&);
template std::shared_ptr<fcl::BVHModel<fcl::OBBd>> toFclBvh(const TriangleMesh&);

std::shared_ptr<fcl::CollisionGeometryd> toFclGeometry(const CollisionShape& shape) {
  std::shared_ptr<fcl::CollisionGeometryd> geometry;
  switch (shape.type) {
    case ShapeType::kBox:
      geometry = std::make_shared<fcl::Boxd>(shape.box_size);
      break;
    case ShapeType::kSphere:
      geometry = std::make_shared<fcl::Sphered>(shape.radius);
      break;
    case ShapeType::kCylinder:
      geometry = std::make_shared<fcl::Cylinderd>(shape.radius, shape.length);
      break;
    case ShapeType::kMesh:
      SKELGRASP_DEMAND(shape.mesh != nullptr);
      geometry = toFclMesh(*shape.mesh);
      break;
  }
  geometry->computeLocalAABB();
  return geometry;
}

}  // namespace skelgrasp::grasping::internal
