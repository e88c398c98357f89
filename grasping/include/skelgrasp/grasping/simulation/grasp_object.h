#pragma once
// An object to grasp: its mesh (object frame, metres), mass properties used by the quality measure,
// and its collision geometry (an FCL bounding-volume hierarchy built once and shared by every
// simulator that uses the object).
#include <memory>
#include <mutex>

#include "skelgrasp/common/mesh.h"
#include "skelgrasp/geometry/mesh_query.h"
#include "skelgrasp/geometry/principal_axes.h"
#include "skelgrasp/grasping/simulation/distance_field.h"

namespace skelgrasp::grasping {

class GraspObject {
 public:
  // `field`: the parameters of distanceField(). Throws InvalidArgument for an empty mesh or a
  // non-positive field spacing or band.
  explicit GraspObject(TriangleMesh mesh, const DistanceFieldParams& field = {});
  ~GraspObject();
  GraspObject(const GraspObject&) = delete;
  GraspObject& operator=(const GraspObject&) = delete;

  const TriangleMesh& mesh() const { return mesh_; }
  const AxisAlignedBox& bounds() const { return bounds_; }
  // Volume centroid (uniform density) when the mesh encloses a volume, else the area centroid.
  const Eigen::Vector3d& centerOfMass() const { return center_of_mass_; }
  // Mean of the mesh vertices (the reference implementation's "centre").
  const Eigen::Vector3d& vertexMean() const { return vertex_mean_; }
  // Largest distance of a vertex from the centre of mass.
  double maxRadius() const { return max_radius_; }
  // Principal axes of the surface (geometry::surfacePrincipalAxes), along which the fallback
  // strategies place the hand.
  const geometry::PrincipalAxes& principalAxes() const { return principal_axes_; }
  // Length of the mesh along its longest principal axis (geometry::principalLengthM, which says
  // how it behaves for a cube or a ball): the object's size for preshapes made for small objects
  // (Preshape::max_object_length_m).
  double principalLengthM() const { return principal_length_m_; }
  // Outward unit normal of a face (zero for degenerate faces).
  const Eigen::Vector3d& faceNormal(std::size_t face) const { return face_normals_[face]; }
  // Outward normal at a surface point found on face `face`. On an edge or a corner the point lies
  // on several faces; the one facing `towards` (e.g. the touching finger) is chosen.
  Eigen::Vector3d surfaceNormal(const Eigen::Vector3d& point, std::size_t face,
                                const Eigen::Vector3d& towards) const;

  // True when the mesh is closed (every edge shared by two faces): then inside/outside is defined.
  bool closed() const { return closed_; }
  // Closest-point queries on the surface (AABB tree, built on first use, thread-safe).
  const geometry::MeshQuery& surfaceQuery() const;

  // Signed distance field of the surface (unsigned when the mesh is open) with the constructor's
  // DistanceFieldParams, built on first use (tens of milliseconds), thread-safe.
  const DistanceField& distanceField() const;
  const DistanceFieldParams& fieldParams() const { return field_params_; }

  struct CollisionData;  // FCL geometry, defined in the FCL translation units
  const CollisionData& collisionData() const { return *collision_; }

 private:
  TriangleMesh mesh_;
  AxisAlignedBox bounds_;
  Eigen::Vector3d center_of_mass_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d vertex_mean_ = Eigen::Vector3d::Zero();
  double max_radius_ = 0;
  geometry::PrincipalAxes principal_axes_;
  double principal_length_m_ = 0;
  bool closed_ = false;
  std::vector<Eigen::Vector3d> face_normals_;
  std::vector<std::vector<int>> vertex_faces_;
  std::unique_ptr<CollisionData> collision_;
  mutable std::once_flag query_once_;
  mutable std::unique_ptr<geometry::MeshQuery> query_;
  DistanceFieldParams field_params_;
  mutable std::once_flag field_once_;
  mutable std::unique_ptr<DistanceField> field_;
};

}  // namespace skelgrasp::grasping
