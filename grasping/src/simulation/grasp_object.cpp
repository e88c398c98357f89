#include "skelgrasp/grasping/simulation/grasp_object.h"

#include "fcl_conversions.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/geometry/mesh_topology.h"

namespace skelgrasp::grasping {

namespace {

// A mesh whose |signed volume| is below this share of its bounding box's diagonal cubed is open
// or flat: the centre of mass comes from the surface instead.
constexpr double kFlatVolumeShare = 1e-6;
// An approach direction shorter than this (metres) has none: the face normal is kept.
constexpr double kZeroDirectionNorm = 1e-12;
// Normals of faces at the contact within this share of the object size (at least 1 mm) compete.
constexpr double kNormalSearchShare = 1e-6;
constexpr double kMinNormalSearchScaleM = 1e-3;
}  // namespace

GraspObject::GraspObject(TriangleMesh mesh, const DistanceFieldParams& field)
    : mesh_(std::move(mesh)), field_params_(field) {
  if (mesh_.empty()) throw InvalidArgument("GraspObject: empty mesh");
  // Checked here, not when the field is first built, so that the mistake surfaces at its cause.
  checkDistanceFieldParams(field);
  bounds_ = mesh_.bounds();
  closed_ = geometry::analyzeTopology(mesh_).closed;
  for (const auto& v : mesh_.vertices) vertex_mean_ += v;
  vertex_mean_ /= static_cast<double>(mesh_.vertices.size());
  // Centroid of the enclosed volume (signed tetrahedra from the origin); falls back to the area
  // centroid when the volume is negligible (open or flat meshes).
  double volume = 0, area = 0;
  Eigen::Vector3d volume_moment = Eigen::Vector3d::Zero(), area_moment = Eigen::Vector3d::Zero();
  face_normals_.reserve(mesh_.faces.size());
  for (std::size_t f = 0; f < mesh_.faces.size(); ++f) {
    const auto& t = mesh_.faces[f];
    const Eigen::Vector3d &a = mesh_.vertices[t[0]], &b = mesh_.vertices[t[1]],
                          &c = mesh_.vertices[t[2]];
    const double v = a.dot(b.cross(c)) / 6.0;
    volume += v;
    volume_moment += v * (a + b + c) / 4.0;
    const double s = 0.5 * (b - a).cross(c - a).norm();
    area += s;
    area_moment += s * (a + b + c) / 3.0;
    face_normals_.push_back(mesh_.faceNormal(f));
  }
  const double scale = bounds_.diagonal();
  if (std::abs(volume) > kFlatVolumeShare * scale * scale * scale) {
    center_of_mass_ = volume_moment / volume;
  } else if (area > 0) {
    center_of_mass_ = area_moment / area;
  } else {
    center_of_mass_ = vertex_mean_;
  }
  for (const auto& v : mesh_.vertices)
    max_radius_ = std::max(max_radius_, (v - center_of_mass_).norm());
  principal_axes_ = geometry::surfacePrincipalAxes(mesh_);
  principal_length_m_ = geometry::principalLengthM(mesh_, principal_axes_);
  vertex_faces_.resize(mesh_.vertices.size());
  for (std::size_t f = 0; f < mesh_.faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) vertex_faces_[mesh_.faces[f][k]].push_back(static_cast<int>(f));
  }

  collision_ = std::make_unique<CollisionData>(mesh_);
}

GraspObject::~GraspObject() = default;

const geometry::MeshQuery& GraspObject::surfaceQuery() const {
  std::call_once(query_once_, [this] { query_ = std::make_unique<geometry::MeshQuery>(mesh_); });
  return *query_;
}

const DistanceField& GraspObject::distanceField() const {
  std::call_once(field_once_, [this] {
    field_ = std::make_unique<DistanceField>(mesh_, closed_, field_params_);
  });
  return *field_;
}

Eigen::Vector3d GraspObject::surfaceNormal(const Eigen::Vector3d& point, std::size_t face,
                                           const Eigen::Vector3d& towards) const {
  Eigen::Vector3d best = face_normals_[face];
  if (towards.norm() < kZeroDirectionNorm) return best;
  const Eigen::Vector3d dir = towards.normalized();
  double best_dot = best.dot(dir);
  const double tolerance =
      kNormalSearchShare * std::max(kMinNormalSearchScaleM, bounds_.diagonal());
  for (int k = 0; k < 3; ++k) {
    for (int f : vertex_faces_[mesh_.faces[face][k]]) {
      const auto& t = mesh_.faces[f];
      const Eigen::Vector3d& a = mesh_.vertices[t[0]];
      const Eigen::Vector3d& n = face_normals_[f];
      if (n.isZero() || std::abs((point - a).dot(n)) > tolerance)
        continue;  // not on this face's plane
      // Inside the triangle (barycentric test on the plane).
      const Eigen::Vector3d &b = mesh_.vertices[t[1]], &c = mesh_.vertices[t[2]];
      const double w0 = (b - point).cross(c - point).dot(n),
                   w1 = (c - point).cross(a - point).dot(n),
                   w2 = (a - point).cross(b - point).dot(n);
      const double slack = -tolerance * bounds_.diagonal();
      if (w0 < slack || w1 < slack || w2 < slack) continue;
      if (n.dot(dir) > best_dot) {
        best_dot = n.dot(dir);
        best = n;
      }
    }
  }
  return best;
}

}  // namespace skelgrasp::grasping
