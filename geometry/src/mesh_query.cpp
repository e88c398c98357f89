// CGAL translation unit: AABB-tree point queries.
#include "skelgrasp/geometry/mesh_query.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Side_of_triangle_mesh.h>

#include "skelgrasp/common/error.h"
#include "skelgrasp/internal/cgal_conversions.h"

namespace skelgrasp::geometry {

namespace {

// Ray directions shorter than this (metres) have no direction: no hit.
constexpr double kZeroDirectionNorm = 1e-15;

using internal::CgalKernel;
using internal::CgalMesh;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<CgalMesh>;
using Traits = CGAL::AABB_traits<CgalKernel, Primitive>;
using Tree = CGAL::AABB_tree<Traits>;
}  // namespace

struct MeshQuery::Impl {
  CgalMesh mesh;
  Tree tree;
  std::unique_ptr<CGAL::Side_of_triangle_mesh<CgalMesh, CgalKernel>> side;
};

MeshQuery::MeshQuery(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  if (mesh.empty()) throw InvalidArgument("MeshQuery: empty mesh");
  if (!internal::toCgalMesh(mesh, impl_->mesh)) {
    // Not an oriented manifold: keep the faces that fit so distances still work.
    impl_->mesh.clear();
    for (const auto& v : mesh.vertices) impl_->mesh.add_vertex(internal::toCgal(v));
    for (const auto& f : mesh.faces) {
      impl_->mesh.add_face(CgalMesh::Vertex_index(f[0]), CgalMesh::Vertex_index(f[1]),
                           CgalMesh::Vertex_index(f[2]));
    }
  }
  impl_->tree.insert(faces(impl_->mesh).first, faces(impl_->mesh).second, impl_->mesh);
  impl_->tree.accelerate_distance_queries();
  impl_->side = std::make_unique<CGAL::Side_of_triangle_mesh<CgalMesh, CgalKernel>>(impl_->tree);
}

MeshQuery::~MeshQuery() = default;

bool MeshQuery::contains(const Eigen::Vector3d& p) const {
  return (*impl_->side)(internal::toCgal(p)) != CGAL::ON_UNBOUNDED_SIDE;
}

double MeshQuery::distance(const Eigen::Vector3d& p) const {
  return std::sqrt(impl_->tree.squared_distance(internal::toCgal(p)));
}

Eigen::Vector3d MeshQuery::closestPoint(const Eigen::Vector3d& p) const {
  return internal::toEigen(impl_->tree.closest_point(internal::toCgal(p)));
}

std::optional<Eigen::Vector3d> MeshQuery::firstHit(const Eigen::Vector3d& origin,
                                                   const Eigen::Vector3d& direction) const {
  if (direction.norm() < kZeroDirectionNorm) return std::nullopt;
  const CgalKernel::Ray_3 ray(internal::toCgal(origin),
                              CgalKernel::Vector_3(direction.x(), direction.y(), direction.z()));
  const auto hit = impl_->tree.first_intersection(ray);
  if (!hit) return std::nullopt;
  if (const auto* point = boost::get<CgalKernel::Point_3>(&hit->first))
    return internal::toEigen(*point);
  if (const auto* segment = boost::get<CgalKernel::Segment_3>(&hit->first)) {
    return internal::toEigen(segment->source());
  }
  return std::nullopt;
}

std::pair<Eigen::Vector3d, std::size_t> MeshQuery::closestPointAndFace(
    const Eigen::Vector3d& p) const {
  const auto hit = impl_->tree.closest_point_and_primitive(internal::toCgal(p));
  return {internal::toEigen(hit.first), static_cast<std::size_t>(hit.second.idx())};
}

}  // namespace skelgrasp::geometry
