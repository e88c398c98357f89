#pragma once
// Thin triangle-mesh and bounding-box types shared across modules. Lengths are metres.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <vector>

namespace skelgrasp {

using Rgb = std::array<std::uint8_t, 3>;

struct AxisAlignedBox {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d max = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());

  bool empty() const { return (min.array() > max.array()).any(); }
  Eigen::Vector3d extent() const {
    return empty() ? Eigen::Vector3d::Zero() : Eigen::Vector3d(max - min);
  }
  Eigen::Vector3d center() const { return 0.5 * (min + max); }
  double diagonal() const { return extent().norm(); }
  void extend(const Eigen::Vector3d& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
};

// Box of the finite points (NaN or inf entries are skipped).
AxisAlignedBox boundingBox(const std::vector<Eigen::Vector3d>& points);

// An indexed triangle mesh. Faces are counter-clockwise seen from outside (outward normals) when
// the mesh is "oriented"; nothing here enforces closedness or manifoldness.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> faces;
  std::vector<Rgb> vertex_colors;  // empty, or one per vertex

  bool empty() const { return vertices.empty() || faces.empty(); }
  std::size_t numVertices() const { return vertices.size(); }
  std::size_t numFaces() const { return faces.size(); }
  AxisAlignedBox bounds() const { return boundingBox(vertices); }

  // Unit normal of face f (zero for a degenerate face).
  Eigen::Vector3d faceNormal(std::size_t f) const;
  double faceArea(std::size_t f) const;
  // Sum of face areas.
  double area() const;
  // Signed enclosed volume (divergence theorem); positive for a closed outward-oriented mesh.
  double signedVolume() const;
  // Area-weighted vertex normals (unit; zero for isolated vertices).
  std::vector<Eigen::Vector3d> vertexNormals() const;

  void transform(const Eigen::Isometry3d& pose);
  void scale(double factor);
  void flipOrientation();
  // Appends another mesh as a separate part (indices shifted).
  void append(const TriangleMesh& other);
};

}  // namespace skelgrasp
