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

#include "skelgrasp/grasping/grasp_object.h"
#include "skelgrasp/grasping/hand_model.h"

namespace skelgrasp::grasping {

using FclMesh = fcl::BVHModel<fcl::OBBRSSd>;
using FclCollisionMesh = fcl::BVHModel<fcl::OBBd>;

// The object twice: FCL's distance queries need RSS volumes, and its collision test of a primitive
// against OBBRSS volumes refits the primitive's volume (two 3x3 eigen decompositions) on every
// call, which an OBB tree does not (a third of a closing's collision time). FCL tests meshes only
// against meshes of the same volume type: hand link meshes use the OBBRSS tree.
struct GraspObject::CollisionData {
  std::shared_ptr<FclMesh> bvh;
  std::unique_ptr<fcl::CollisionObjectd> object;  // at the identity (object frame)
  std::shared_ptr<FclCollisionMesh> obb_bvh;
  std::unique_ptr<fcl::CollisionObjectd> obb_object;  // the same mesh, for primitives' collisions
};

namespace internal {

template <typename BV>
std::shared_ptr<fcl::BVHModel<BV>> toFclBvh(const TriangleMesh& mesh);
inline std::shared_ptr<FclMesh> toFclMesh(const TriangleMesh& mesh) {
  return toFclBvh<fcl::OBBRSSd>(mesh);
}
std::shared_ptr<fcl::CollisionGeometryd> toFclGeometry(const CollisionShape& shape);
inline fcl::Transform3d toFcl(const Pose& pose) {
  return fcl::Transform3d(pose.matrix());
}

}  // namespace internal
}  // namespace skelgrasp::grasping
