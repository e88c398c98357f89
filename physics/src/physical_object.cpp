#include "skelgrasp/physics/physical_object.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "bullet_shapes.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/geometry/mesh_query.h"
#include "skelgrasp/geometry/regularisation.h"
#include "skelgrasp/geometry/surface_distance.h"

namespace skelgrasp::physics {
namespace {

// Surface samples behind the shape-error figures (seeded).
constexpr std::size_t kShapeErrorSamples = 4000;
// The smallest closed surface the engine is given.
constexpr std::size_t kMinVertices = 100;

// The closed surface: the input when it already is a closed manifold (simplified), else its alpha
// wrap (geometry::regularise).
TriangleMesh closedSurfaceOf(const TriangleMesh& mesh, std::size_t max_vertices) {
  geometry::RegularisationParams params;
  params.method = geometry::RegularisationMethod::kAuto;
  params.max_vertices = max_vertices;
  auto result = geometry::regularise(mesh, params);
  if (!result.status.ok()) {
    throw InvalidArgument("physics: the object's surface cannot be closed: " +
                          result.status.message);
  }
  return std::move(result.mesh);
}

}  // namespace

PhysicalObject::PhysicalObject(const TriangleMesh& mesh, const PhysicalObjectParams& params) {
  const auto start = std::chrono::steady_clock::now();
  if (!(params.mass_kg > 0) || !std::isfinite(params.mass_kg)) {
    throw InvalidArgument(fmt::format("physics: object mass {} kg: must be > 0", params.mass_kg));
  }
  if (params.density_kg_m3 &&
      (!(*params.density_kg_m3 > 0) || !std::isfinite(*params.density_kg_m3))) {
    throw InvalidArgument(
        fmt::format("physics: density {} kg/m^3: must be > 0", *params.density_kg_m3));
  }
  if (params.max_vertices < kMinVertices) {
    throw InvalidArgument(fmt::format("physics: max_vertices must be >= {}", kMinVertices));
  }
  if (mesh.empty()) throw InvalidArgument("physics: empty object mesh");
  closed_ = closedSurfaceOf(mesh, params.max_vertices);
  mass_ = massProperties(closed_);
  if (!(mass_.volume_m3 > 0)) {
    throw InvalidArgument("physics: the object's closed surface encloses no volume");
  }
  if (params.density_kg_m3) {
    density_ = *params.density_kg_m3;
    mass_kg_ = density_ * mass_.volume_m3;
  } else {
    mass_kg_ = params.mass_kg;
    density_ = mass_kg_ / mass_.volume_m3;
  }
  for (const auto& v : closed_.vertices) {
    max_radius_m_ = std::max(max_radius_m_, (v - mass_.center_of_mass).norm());
  }
  surface_query_ = std::make_shared<geometry::MeshQuery>(closed_);
  surface_shape_ = std::make_shared<internal::SurfaceShape>(
      closed_, internal::principalFrame(mass_.center_of_mass, mass_.inertia_per_density));
  const auto distance = geometry::chamferDistance(mesh, closed_, kShapeErrorSamples);
  shape_error_m_ = distance.max_m;
  shape_error_p95_m_ = std::max(distance.a_to_b_p95_m, distance.b_to_a_p95_m);
  build_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

PhysicalObject::~PhysicalObject() = default;

}  // namespace skelgrasp::physics
