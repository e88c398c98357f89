// Mass properties of a closed triangle mesh by the divergence theorem: each outward triangle and
// the origin span a signed tetrahedron; the integrals of 1, x and x x^T over the solid are sums of
// the tetrahedra's closed-form moments.
#include <Eigen/Dense>

#include "skelgrasp/common/error.h"
#include "skelgrasp/physics/physical_object.h"

namespace skelgrasp::physics {

MassProperties massProperties(const TriangleMesh& closed_mesh) {
  if (closed_mesh.empty()) throw InvalidArgument("massProperties: empty mesh");
  // Moments about a point near the mesh keep the sums well conditioned far from the origin.
  const Eigen::Vector3d reference = closed_mesh.bounds().center();
  double volume = 0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();  // integral of x x^T about `reference`
  for (const auto& face : closed_mesh.faces) {
    const Eigen::Vector3d a = closed_mesh.vertices[face[0]] - reference;
    const Eigen::Vector3d b = closed_mesh.vertices[face[1]] - reference;
    const Eigen::Vector3d c = closed_mesh.vertices[face[2]] - reference;
    const double v = a.dot(b.cross(c)) / 6.0;  // signed volume of (0, a, b, c)
    volume += v;
    first += v * (a + b + c) / 4.0;
    // Integral of x x^T over the tetrahedron (0, a, b, c): v/20 (sum p p^T + (sum p)(sum p)^T).
    const Eigen::Vector3d s = a + b + c;
    second +=
        v / 20.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  MassProperties result;
  result.volume_m3 = volume;
  if (volume == 0) return result;
  const Eigen::Vector3d centroid = first / volume;
  result.center_of_mass = centroid + reference;
  // Second moment about the centroid, then the inertia tensor I = tr(S) 1 - S.
  const Eigen::Matrix3d central = second - volume * centroid * centroid.transpose();
  result.inertia_per_density = central.trace() * Eigen::Matrix3d::Identity() - central;
  return result;
}

}  // namespace skelgrasp::physics
