#pragma once
// An object as the physics judge sees it: a rigid body with mass, centre of mass and inertia from
// its closed surface, colliding with that surface itself (the engine's concave-mesh support:
// a mug's inside stays empty; docs/physics.md, "The object").
#include <cstddef>
#include <memory>
#include <optional>

#include <Eigen/Core>

#include "skelgrasp/common/mesh.h"

namespace skelgrasp::geometry {
class MeshQuery;
}

namespace skelgrasp::physics {
namespace internal {
class SurfaceShape;  // the engine's view of the closed surface (bullet_shapes.cpp)
}

// Mass properties of a solid of uniform density bounded by a closed, outward-oriented mesh.
struct MassProperties {
  double volume_m3 = 0;
  Eigen::Vector3d center_of_mass = Eigen::Vector3d::Zero();
  // Inertia tensor about the centre of mass, per unit density (m^5): multiply by the density
  // (kg/m^3) for kg m^2.
  Eigen::Matrix3d inertia_per_density = Eigen::Matrix3d::Zero();
};

// Volume, centroid and inertia by the divergence theorem over the mesh's triangles (exact for a
// closed, consistently outward-oriented mesh; an inward one gives a negative volume). Throws
// InvalidArgument for an empty mesh.
MassProperties massProperties(const TriangleMesh& closed_mesh);

// The default mass of a judged object: the disturbance tests of the dexterous-grasping benchmarks
// (DexGraspBench, BODex) use 0.1 kg.
inline constexpr double kDefaultObjectMassKg = 0.1;
// Heaviest object the judge takes (kg): far beyond what a hand lifts.
inline constexpr double kMaxObjectMassKg = 1000;

struct PhysicalObjectParams {
  // Mass of the object (kg, > 0). Ignored when density_kg_m3 is set.
  double mass_kg = kDefaultObjectMassKg;
  // Uniform density (kg/m^3, > 0): the mass is then density x the closed surface's volume.
  std::optional<double> density_kg_m3;
  // The closed surface the engine collides with (the input as it is when it already is a closed
  // manifold, else its alpha wrap) is simplified to about this many vertices (>= 100): the
  // engine's contact work grows with the triangles under each finger. Its departure from the
  // input is measured (shapeErrorM).
  std::size_t max_vertices = 1500;
};

// The solid the engine moves: built once per object, shared by every execution on it, read-only
// afterwards (thread-safe).
class PhysicalObject {
 public:
  // `mesh` in the object frame, metres. Throws InvalidArgument for bad parameters, an empty mesh or
  // one whose closed surface encloses no volume.
  explicit PhysicalObject(const TriangleMesh& mesh, const PhysicalObjectParams& params = {});
  ~PhysicalObject();
  PhysicalObject(const PhysicalObject&) = delete;
  PhysicalObject& operator=(const PhysicalObject&) = delete;

  double massKg() const { return mass_kg_; }
  // Of the closed surface, in the object frame.
  const Eigen::Vector3d& centerOfMass() const { return mass_.center_of_mass; }
  // About the centre of mass, object-frame axes (kg m^2).
  Eigen::Matrix3d inertia() const { return mass_.inertia_per_density * density_; }
  double volumeM3() const { return mass_.volume_m3; }
  // The closed surface the engine collides with and the mass properties come from.
  const TriangleMesh& closedSurface() const { return closed_; }
  // How far the closed surface departs from the input (m): the largest and the 95th percentile,
  // over seeded samples of each, of the distance to the other (a sampled Hausdorff distance).
  double shapeErrorM() const { return shape_error_m_; }
  double shapeErrorP95M() const { return shape_error_p95_m_; }
  // Largest radius about the centre of mass: the scale of "the object turned".
  double maxRadiusM() const { return max_radius_m_; }
  double buildSeconds() const { return build_s_; }
  // Containment and distance queries on the closed surface.
  const geometry::MeshQuery& surfaceQuery() const { return *surface_query_; }
  // The closed surface as the engine's shapes.
  const internal::SurfaceShape& surfaceShape() const { return *surface_shape_; }

 private:
  TriangleMesh closed_;
  MassProperties mass_;
  double density_ = 0;
  double mass_kg_ = 0;
  double shape_error_m_ = 0;
  double shape_error_p95_m_ = 0;
  double max_radius_m_ = 0;
  double build_s_ = 0;
  std::shared_ptr<const geometry::MeshQuery> surface_query_;
  std::shared_ptr<const internal::SurfaceShape> surface_shape_;
};

}  // namespace skelgrasp::physics
