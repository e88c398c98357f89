#include "bullet_shapes.h"

#include <Eigen/Eigenvalues>
#include <algorithm>

#include "skelgrasp/geometry/mesh_query.h"
#include "skelgrasp/physics/physical_object.h"

namespace skelgrasp::physics::internal {
namespace {

using grasping::ShapeType;

std::unique_ptr<btCollisionShape> makeShape(const grasping::CollisionShape& shape) {
  std::unique_ptr<btCollisionShape> made;
  switch (shape.type) {
    case ShapeType::kBox:
      made = std::make_unique<btBoxShape>(toBt(0.5 * shape.box_size));
      break;
    case ShapeType::kSphere:
      made = std::make_unique<btSphereShape>(shape.radius);
      break;
    case ShapeType::kCylinder:
      made = std::make_unique<btCylinderShapeZ>(
          btVector3(shape.radius, shape.radius, 0.5 * shape.length));
      break;
    case ShapeType::kMesh: {
      // A link mesh as its convex hull (the engine's): finger shells are convex.
      auto hull = std::make_unique<btConvexHullShape>();
      for (const auto& v : shape.mesh->vertices) hull->addPoint(toBt(v), false);
      hull->recalcLocalAabb();
      made = std::move(hull);
      break;
    }
  }
  // A sphere's margin is its radius; the others' is inside their sizes (boxes, cylinders) or
  // around the hull.
  if (shape.type != ShapeType::kSphere) made->setMargin(kShapeMarginM);
  return made;
}

btTriangleIndexVertexArray* newArrays(std::vector<int>& indices, std::vector<btScalar>& vertices) {
  return new btTriangleIndexVertexArray(static_cast<int>(indices.size() / 3), indices.data(),
                                        static_cast<int>(3 * sizeof(int)),
                                        static_cast<int>(vertices.size() / 3), vertices.data(),
                                        static_cast<int>(3 * sizeof(btScalar)));
}

}  // namespace

btTransform toBt(const Pose& pose) {
  const Eigen::Quaterniond q(pose.linear());
  return btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()), toBt(pose.translation()));
}

Pose fromBt(const btTransform& transform) {
  Pose pose = Pose::Identity();
  const btMatrix3x3& basis = transform.getBasis();
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) pose.linear()(row, col) = basis[row][col];
  }
  pose.translation() = fromBt(transform.getOrigin());
  return pose;
}

Eigen::Vector3d halfExtent(const grasping::CollisionShape& shape) {
  switch (shape.type) {
    case ShapeType::kBox:
      return 0.5 * shape.box_size;
    case ShapeType::kSphere:
      return Eigen::Vector3d::Constant(shape.radius);
    case ShapeType::kCylinder:
      return Eigen::Vector3d(shape.radius, shape.radius, 0.5 * shape.length);
    case ShapeType::kMesh:
      return 0.5 * shape.mesh->bounds().extent();
  }
  return Eigen::Vector3d::Zero();
}

Eigen::Vector3d shapeCentre(const grasping::CollisionShape& shape) {
  if (shape.type == ShapeType::kMesh) return shape.origin * shape.mesh->bounds().center();
  return shape.origin.translation();
}

std::unique_ptr<btCompoundShape> linkShape(const grasping::Link& link,
                                           std::vector<std::unique_ptr<btCollisionShape>>& owned) {
  auto shape = std::make_unique<btCompoundShape>();
  for (const auto& part : link.shapes) {
    auto child = makeShape(part);
    shape->addChildShape(toBt(part.origin), child.get());
    owned.push_back(std::move(child));
  }
  return shape;
}

Pose principalFrame(const Eigen::Vector3d& center_of_mass, const Eigen::Matrix3d& inertia) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(inertia);
  Eigen::Matrix3d axes = eigen.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
  Pose frame = Pose::Identity();
  frame.linear() = axes;
  frame.translation() = center_of_mass;
  return frame;
}

SurfaceShape::SurfaceShape(const TriangleMesh& closed_surface, const Pose& body_in_object)
    : body_in_object_(body_in_object) {
  const Pose object_to_body = body_in_object.inverse();
  for (const auto& v : closed_surface.vertices) {
    vertices_.insert(vertices_.end(), {v.x(), v.y(), v.z()});
    const Eigen::Vector3d b = object_to_body * v;
    body_vertices_.insert(body_vertices_.end(), {b.x(), b.y(), b.z()});
  }
  for (const auto& f : closed_surface.faces) indices_.insert(indices_.end(), {f[0], f[1], f[2]});
  arrays_.reset(newArrays(indices_, vertices_));
  static_mesh_ = std::make_unique<btBvhTriangleMeshShape>(arrays_.get(), true);
  static_mesh_->setMargin(0.0);
}

SurfaceShape::~SurfaceShape() = default;

std::unique_ptr<SurfaceShape::BodyMesh> SurfaceShape::borrowBodyMesh() const {
  {
    const std::lock_guard<std::mutex> lock(pool_mutex_);
    if (!pool_.empty()) {
      auto mesh = std::move(pool_.back());
      pool_.pop_back();
      return mesh;
    }
  }
  auto mesh = std::make_unique<BodyMesh>();
  // The engine takes the index and vertex arrays by non-const pointer; it only reads them.
  mesh->arrays.reset(newArrays(const_cast<std::vector<int>&>(indices_),
                               const_cast<std::vector<btScalar>&>(body_vertices_)));
  mesh->shape = std::make_unique<btGImpactMeshShape>(mesh->arrays.get());
  mesh->shape->setMargin(kShapeMarginM);
  mesh->shape->updateBound();
  return mesh;
}

void SurfaceShape::giveBack(std::unique_ptr<BodyMesh> mesh) const {
  const std::lock_guard<std::mutex> lock(pool_mutex_);
  pool_.push_back(std::move(mesh));
}

std::pair<double, int> startPenetration(const grasping::HandModel& hand,
                                        const std::vector<Pose>& link_poses,
                                        const PhysicalObject& object) {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btCollisionWorld world(&dispatcher, &broadphase, &configuration);
  btCollisionObject surface;
  surface.setCollisionShape(object.surfaceShape().staticMesh());
  surface.setUserIndex(-1);
  world.addCollisionObject(&surface);
  std::vector<std::unique_ptr<btCollisionShape>> owned;
  std::vector<std::unique_ptr<btCollisionObject>> links;
  double deepest = 0;
  int deepest_link = -1;
  const auto consider = [&](double depth, int link) {
    if (depth > deepest) {
      deepest = depth;
      deepest_link = link;
    }
  };
  for (std::size_t l = 0; l < hand.links().size(); ++l) {
    const auto& link = hand.links()[l];
    if (link.shapes.empty()) continue;
    // A shape whose centre lies inside the object is at least that deep in it, whether or not it
    // crosses the surface (a link wholly inside meets no triangle).
    for (const auto& part : link.shapes) {
      const Eigen::Vector3d centre = link_poses[l] * shapeCentre(part);
      if (object.surfaceQuery().contains(centre)) {
        consider(object.surfaceQuery().distance(centre), static_cast<int>(l));
      }
    }
    owned.push_back(linkShape(link, owned));
    auto body = std::make_unique<btCollisionObject>();
    body->setCollisionShape(owned.back().get());
    body->setWorldTransform(toBt(link_poses[l]));
    body->setUserIndex(static_cast<int>(l));
    world.addCollisionObject(body.get());
    links.push_back(std::move(body));
  }
  world.performDiscreteCollisionDetection();
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
    const int a = manifold->getBody0()->getUserIndex();
    const int b = manifold->getBody1()->getUserIndex();
    if ((a < 0) == (b < 0)) continue;  // link against link
    for (int p = 0; p < manifold->getNumContacts(); ++p) {
      consider(-manifold->getContactPoint(p).getDistance(), std::max(a, b));
    }
  }
  for (auto& body : links) world.removeCollisionObject(body.get());
  world.removeCollisionObject(&surface);
  return {deepest, deepest_link};
}

}  // namespace skelgrasp::physics::internal
