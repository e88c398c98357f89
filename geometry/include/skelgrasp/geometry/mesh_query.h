#pragma once
// Point queries against a closed triangle mesh (AABB tree built once).
#include <memory>
#include <optional>

#include "skelgrasp/common/mesh.h"

namespace skelgrasp::geometry {

class MeshQuery {
 public:
  // The mesh must be closed for contains() to be meaningful; distances work on any mesh.
  explicit MeshQuery(const TriangleMesh& mesh);
  ~MeshQuery();
  MeshQuery(const MeshQuery&) = delete;
  MeshQuery& operator=(const MeshQuery&) = delete;

  // True if p is inside or on the surface.
  bool contains(const Eigen::Vector3d& p) const;
  // Unsigned distance to the surface.
  double distance(const Eigen::Vector3d& p) const;
  Eigen::Vector3d closestPoint(const Eigen::Vector3d& p) const;
  // First surface point hit by the ray from `origin` along `direction`, if any.
  std::optional<Eigen::Vector3d> firstHit(const Eigen::Vector3d& origin,
                                          const Eigen::Vector3d& direction) const;
  // Closest point and the index of the face it lies on.
  std::pair<Eigen::Vector3d, std::size_t> closestPointAndFace(const Eigen::Vector3d& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace skelgrasp::geometry
