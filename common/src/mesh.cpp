#include "skelgrasp/common/mesh.h"

namespace skelgrasp {

AxisAlignedBox boundingBox(const std::vector<Eigen::Vector3d>& points) {
  AxisAlignedBox box;
  for (const auto& p : points) {
    if (p.allFinite()) box.extend(p);  // organised clouds hold NaN for pixels without depth
  }
  return box;
}

Eigen::Vector3d TriangleMesh::faceNormal(std::size_t f) const {
  const auto& t = faces[f];
  const Eigen::Vector3d n =
      (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]);
  const double len = n.norm();
  return len > 0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
}

double TriangleMesh::faceArea(std::size_t f) const {
  const auto& t = faces[f];
  return 0.5 * (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]).norm();
}

double TriangleMesh::area() const {
  double sum = 0;
  for (std::size_t f = 0; f < faces.size(); ++f) sum += faceArea(f);
  return sum;
}

double TriangleMesh::signedVolume() const {
  double volume = 0;
  for (const auto& t : faces) {
    volume += vertices[t[0]].dot(vertices[t[1]].cross(vertices[t[2]]));
  }
  return volume / 6.0;
}

std::vector<Eigen::Vector3d> TriangleMesh::vertexNormals() const {
  std::vector<Eigen::Vector3d> normals(vertices.size(), Eigen::Vector3d::Zero());
  for (const auto& t : faces) {
    // Unnormalised cross product = 2 * area * normal, i.e. area weighting for free.
    const Eigen::Vector3d n =
        (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]);
    for (int k = 0; k < 3; ++k) normals[t[k]] += n;
  }
  for (auto& n : normals) {
    const double len = n.norm();
    if (len > 0) n /= len;
  }
  return normals;
}

void TriangleMesh::transform(const Eigen::Isometry3d& pose) {
  for (auto& v : vertices) v = pose * v;
}

void TriangleMesh::scale(double factor) {
  for (auto& v : vertices) v *= factor;
}

void TriangleMesh::flipOrientation() {
  for (auto& t : faces) std::swap(t[1], t[2]);
}

void TriangleMesh::append(const TriangleMesh& other) {
  const int offset = static_cast<int>(vertices.size());
  const bool colors = !vertex_colors.empty() || (vertices.empty() && !other.vertex_colors.empty());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const auto& t : other.faces) faces.push_back(t + Eigen::Vector3i::Constant(offset));
  if (colors) {
    if (other.vertex_colors.empty()) {
      vertex_colors.resize(vertices.size(), Rgb{200, 200, 200});
    } else {
      vertex_colors.insert(vertex_colors.end(), other.vertex_colors.begin(),
                           other.vertex_colors.end());
    }
  }
}

}  // namespace skelgrasp
