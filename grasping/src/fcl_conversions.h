#pragma once
// Internal: the one place where skelgrasp geometry meets FCL types.
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/collision_object.h>
#include <fcl/narrowphase/distance.h>

#include <memory>

#include "skelgrasp/grasping/grasp_object.h"
#include "skelgrasp/grasping/hand_model.h"

namespace skelgrasp::grasping {

using FclMesh = fcl::BVHModel<fcl::OBBRSSd>;

struct GraspObject::CollisionData {
  std::shared_ptr<FclMesh> bvh;
  std::unique_ptr<fcl::CollisionObjectd> object;  // at the identity (object frame)
};

namespace internal {

std::shared_ptr<FclMesh> toFclMesh(const TriangleMesh& mesh);
std::shared_ptr<fcl::CollisionGeometryd> toFclGeometry(const CollisionShape& shape);
inline fcl::Transform3d toFcl(const Pose& pose) {
  return fcl::Transform3d(pose.matrix());
}

}  // namespace internal
}  // namespace skelgrasp::grasping
