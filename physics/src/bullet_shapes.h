#pragma once
// Bullet's view of our geometry (with bullet_shapes.cpp): conversions of poses and vectors, the
// hand's link shapes, and the object's closed surface as the engine's triangle meshes. With
// bullet_scene.cpp the only files that see Bullet's types.
#include <BulletCollision/Gimpact/btGImpactShape.h>
#include <btBulletDynamicsCommon.h>

#include <memory>
#include <mutex>
#include <vector>

#include <Eigen/Core>

#include "skelgrasp/common/mesh.h"
#include "skelgrasp/common/pose.h"
#include "skelgrasp/grasping/hand/hand_model.h"

namespace skelgrasp::physics::internal {

// Collision margin of every convex shape (m). Bullet's default, 0.04, is meant for metre-sized
// bodies; a hand's links are 1-3 cm thick.
inline constexpr double kShapeMarginM = 0.0005;

inline btVector3 toBt(const Eigen::Vector3d& v) {
  return btVector3(v.x(), v.y(), v.z());
}
inline Eigen::Vector3d fromBt(const btVector3& v) {
  return Eigen::Vector3d(v.x(), v.y(), v.z());
}
btTransform toBt(const Pose& pose);
Pose fromBt(const btTransform& transform);

// A link shape's half sizes in its own frame (a mesh: its bounding box's) and its centre in the
// link frame.
Eigen::Vector3d halfExtent(const grasping::CollisionShape& shape);
Eigen::Vector3d shapeCentre(const grasping::CollisionShape& shape);

// A link's shapes as one compound in the link frame; the children go to `owned`.
std::unique_ptr<btCompoundShape> linkShape(const grasping::Link& link,
                                           std::vector<std::unique_ptr<btCollisionShape>>& owned);

// The body frame of a solid: its centre of mass and principal axes of inertia (object frame).
Pose principalFrame(const Eigen::Vector3d& center_of_mass, const Eigen::Matrix3d& inertia);

// The object's closed surface as the engine sees it: a static triangle mesh with its bounding-
// volume tree for the start test (read-only, shared), and the moving body's concave mesh
// (GImpact) in the body frame. A GImpact shape locks its mesh while the engine reads it, so each
// scene borrows one of its own from a pool.
class SurfaceShape {
 public:
  SurfaceShape(const TriangleMesh& closed_surface, const Pose& body_in_object);
  ~SurfaceShape();
  SurfaceShape(const SurfaceShape&) = delete;
  SurfaceShape& operator=(const SurfaceShape&) = delete;

  const Pose& bodyInObject() const { return body_in_object_; }
  btBvhTriangleMeshShape* staticMesh() const { return static_mesh_.get(); }

  struct BodyMesh {
    std::unique_ptr<btTriangleIndexVertexArray> arrays;
    std::unique_ptr<btGImpactMeshShape> shape;
  };
  // A body mesh no other scene uses until it is given back.
  std::unique_ptr<BodyMesh> borrowBodyMesh() const;
  void giveBack(std::unique_ptr<BodyMesh> mesh) const;

 private:
  Pose body_in_object_;
  std::vector<btScalar> vertices_, body_vertices_;
  std::vector<int> indices_;
  std::unique_ptr<btTriangleIndexVertexArray> arrays_;
  std::unique_ptr<btBvhTriangleMeshShape> static_mesh_;
  mutable std::mutex pool_mutex_;
  mutable std::vector<std::unique_ptr<BodyMesh>> pool_;
};

}  // namespace skelgrasp::physics::internal

namespace skelgrasp::physics {
class PhysicalObject;
namespace internal {

// The deepest penetration of the hand's links, at their poses `link_poses` (object frame), into
// the object's closed surface (m, >= 0) and that link (-1: none): the engine's contact depths
// against the surface's triangles, and a link whose shapes' centres lie inside counts with their
// depth below the surface.
std::pair<double, int> startPenetration(const grasping::HandModel& hand,
                                        const std::vector<Pose>& link_poses,
                                        const PhysicalObject& object);

}  // namespace internal
}  // namespace skelgrasp::physics
