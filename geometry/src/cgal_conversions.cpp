#include "skelgrasp/internal/cgal_conversions.h"

namespace skelgrasp::internal {

void toCgalSoup(const TriangleMesh& mesh, std::vector<CgalPoint>& points,
                std::vector<std::array<std::size_t, 3>>& faces) {
  points.clear();
  faces.clear();
  points.reserve(mesh.vertices.size());
  for (const auto& v : mesh.vertices) points.push_back(toCgal(v));
  faces.reserve(mesh.faces.size());
  for (const auto& f : mesh.faces) {
    faces.push_back({static_cast<std::size_t>(f[0]), static_cast<std::size_t>(f[1]),
                     static_cast<std::size_t>(f[2])});
  }
}

bool toCgalMesh(const TriangleMesh& mesh, CgalMesh& out) {
  out.clear();
  out.reserve(static_cast<CgalMesh::size_type>(mesh.vertices.size()), 0,
              static_cast<CgalMesh::size_type>(mesh.faces.size()));
  for (const auto& v : mesh.vertices) out.add_vertex(toCgal(v));
  for (const auto& f : mesh.faces) {
    const auto face = out.add_face(CgalMesh::Vertex_index(f[0]), CgalMesh::Vertex_index(f[1]),
                                   CgalMesh::Vertex_index(f[2]));
    if (face == CgalMesh::null_face()) return false;
  }
  return true;
}

TriangleMesh fromCgalMesh(const CgalMesh& input) {
  CgalMesh mesh = input;
  if (mesh.has_garbage()) mesh.collect_garbage();
  TriangleMesh out;
  out.vertices.reserve(mesh.number_of_vertices());
  for (auto v : mesh.vertices()) out.vertices.push_back(toEigen(mesh.point(v)));
  out.faces.reserve(mesh.number_of_faces());
  for (auto f : mesh.faces()) {
    Eigen::Vector3i tri;
    int k = 0;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      if (k < 3) tri[k] = static_cast<int>(v.idx());
      ++k;
    }
    if (k == 3) out.faces.push_back(tri);
  }
  return out;
}

}  // namespace skelgrasp::internal
