#pragma once
// Internal: the one place where skelgrasp geometry meets FCL types.
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/collision_object.h>
#include <fcl/narrowphase/distance.h>

#include <memory>
#include <mutex>

#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/grasping/simulation/grasp_object.h"

namespace skelgrasp::grasping {

using FclMesh = fcl::BVHModel<fcl::OBBRSSd>;

namespace internal {
template <typename BV>
std::shared_ptr<fcl::BVHModel<BV>> toFclBvh(const TriangleMesh& mesh);
inline std::shared_ptr<FclMesh> toFclMesh(const TriangleMesh& mesh) {
  return toFclBvh<fcl::OBBRSSd>(mesh);
}
}  // namespace internal

// The object in two FCL trees. Collision tests of hand primitives use an OBB tree: against
// OBBRSS volumes FCL refits the primitive's volume (two 3x3 eigen decompositions) on every call, a
// third of a closing's collision time. Distances need RSS volumes, and FCL tests meshes only
// against meshes of the same volume type: the OBBRSS tree serves both and is built on first use,
// since the fast closing of a hand made of boxes never asks (each tree costs 40-50 ms on a
// 16k-triangle mesh).
struct GraspObject::CollisionData {
  // Both objects sit at the identity (object frame); each holds its tree.
  explicit CollisionData(const TriangleMesh& object_mesh)
      : mesh(object_mesh), obb_object(objectAtIdentity(internal::toFclBvh<fcl::OBBd>(mesh))) {}

  // For distances and hand link meshes; built on the first call.
  const fcl::CollisionObjectd& distanceObject() const {
    std::call_once(distance_once, [this] { object = objectAtIdentity(internal::toFclMesh(mesh)); });
    return *object;
  }

  const TriangleMesh& mesh;  // the owning GraspObject's (it is neither copied nor moved)
  const std::unique_ptr<fcl::CollisionObjectd> obb_object;  // for primitives' collisions

 private:
  static std::unique_ptr<fcl::CollisionObjectd> objectAtIdentity(
      std::shared_ptr<fcl::CollisionGeometryd> tree) {
    auto object = std::make_unique<fcl::CollisionObjectd>(tree, fcl::Transform3d::Identity());
    object->computeAABB();
    return object;
  }

  mutable std::once_flag distance_once;
  mutable std::unique_ptr<fcl::CollisionObjectd> object;
};

namespace internal {

std::shared_ptr<fcl::CollisionGeometryd> toFclGeometry(const CollisionShape& shape);
inline fcl::Transform3d toFcl(const Pose& pose) {
  return fcl::Transform3d(pose.matrix());
}

}  // namespace internal
}  // namespace skelgrasp::grasping
