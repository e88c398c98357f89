// The object's signed distance field: exact distances in a narrow band rasterised triangle by
// triangle (sign from angle-weighted pseudo-normals, Baerentzen & Aanaes 2005), a flood fill for
// the sign beyond the band, and a uniform grid of triangles for exact queries near the surface.
#include "skelgrasp/grasping/simulation/distance_field.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <vector>

#include "distance_field_impl.h"
#include "skelgrasp/common/error.h"
#include "triangle_distance.h"

namespace skelgrasp::grasping {

using distance_field_internal::kCellsPerTriangleCell;
using distance_field_internal::kFloatSlackM;

void DistanceField::Impl::buildNormals() {
  const std::size_t nf = faces.size();
  face_normals.resize(nf);
  face_centres.resize(nf);
  face_radii.resize(nf);
  vertex_normals.assign(vertices.size(), Eigen::Vector3d::Zero());
  edge_normals.assign(nf,
                      {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()});
  std::map<std::pair<int, int>, Eigen::Vector3d> edge_sum;
  for (std::size_t f = 0; f < nf; ++f) {
    const auto& t = faces[f];
    const Eigen::Vector3d &a = vertices[t[0]], &b = vertices[t[1]], &c = vertices[t[2]];
    const Eigen::Vector3d n = (b - a).cross(c - a);
    face_normals[f] = n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::Zero();
    face_centres[f] = (a + b + c) / 3;
    face_radii[f] = std::max(
        {(a - face_centres[f]).norm(), (b - face_centres[f]).norm(), (c - face_centres[f]).norm()});
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e1 = vertices[t[(k + 1) % 3]] - vertices[t[k]];
      const Eigen::Vector3d e2 = vertices[t[(k + 2) % 3]] - vertices[t[k]];
      const double denominator = e1.norm() * e2.norm();
      if (denominator > 0) {
        const double angle = std::acos(std::clamp(e1.dot(e2) / denominator, -1.0, 1.0));
        vertex_normals[t[k]] += angle * face_normals[f];
      }
      const int u = t[k], v = t[(k + 1) % 3];
      // Not operator[]: a default-constructed Eigen vector is uninitialised.
      const auto [it, inserted] =
          edge_sum.emplace(std::make_pair(std::min(u, v), std::max(u, v)), face_normals[f]);
      if (!inserted) it->second += face_normals[f];
    }
  }
  for (std::size_t f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int u = faces[f][k], v = faces[f][(k + 1) % 3];
      edge_normals[f][k] = edge_sum.at({std::min(u, v), std::max(u, v)});
    }
  }
}

void DistanceField::Impl::buildTriangleGrid() {
  cell = kCellsPerTriangleCell * h;
  for (int k = 0; k < 3; ++k) cell_dims[k] = (dims[k] - 1) / kCellsPerTriangleCell + 1;
  const std::size_t cells = static_cast<std::size_t>(cell_dims.x()) * cell_dims.y() * cell_dims.z();
  cell_first.assign(cells + 1, 0);
  const auto forCells = [&](std::size_t f, auto&& visit) {
    Eigen::Vector3d lo = vertices[faces[f][0]], hi = lo;
    for (int k = 1; k < 3; ++k) {
      lo = lo.cwiseMin(vertices[faces[f][k]]);
      hi = hi.cwiseMax(vertices[faces[f][k]]);
    }
    const Eigen::Vector3i a = cellOf(lo), b = cellOf(hi);
    for (int z = a.z(); z <= b.z(); ++z) {
      for (int y = a.y(); y <= b.y(); ++y) {
        for (int x = a.x(); x <= b.x(); ++x) visit(cellIndex({x, y, z}));
      }
    }
  };
  for (std::size_t f = 0; f < faces.size(); ++f)
    forCells(f, [&](std::size_t c) { ++cell_first[c + 1]; });
  for (std::size_t c = 0; c < cells; ++c) cell_first[c + 1] += cell_first[c];
  cell_faces.resize(cell_first[cells]);
  std::vector<std::uint32_t> fill(cell_first.begin(), cell_first.end() - 1);
  for (std::size_t f = 0; f < faces.size(); ++f)
    forCells(f, [&](std::size_t c) { cell_faces[fill[c]++] = static_cast<std::uint32_t>(f); });
  cell_occupied.assign(cells / 64 + 1, 0);
  for (std::size_t c = 0; c < cells; ++c) {
    if (cell_first[c] != cell_first[c + 1]) cell_occupied[c >> 6] |= std::uint64_t{1} << (c & 63);
  }
}

double DistanceField::Impl::signedAt(const Eigen::Vector3d& p, std::size_t f) const {
  const auto& t = faces[f];
  const auto closest =
      internal::closestOnTriangle(p, vertices[t[0]], vertices[t[1]], vertices[t[2]]);
  const double distance = (p - closest.point).norm();
  if (!is_signed) return distance;
  const Eigen::Vector3d& normal =
      closest.feature == internal::TriangleFeature::kFace   ? face_normals[f]
      : closest.feature == internal::TriangleFeature::kEdge ? edge_normals[f][closest.index]
                                                            : vertex_normals[t[closest.index]];
  return (p - closest.point).dot(normal) < 0 ? -distance : distance;
}

void DistanceField::Impl::rasteriseBand() {
  values.assign(static_cast<std::size_t>(dims.x()) * dims.y() * dims.z(),
                std::numeric_limits<float>::infinity());
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& t = faces[f];
    Eigen::Vector3d lo = vertices[t[0]], hi = lo;
    for (int k = 1; k < 3; ++k) {
      lo = lo.cwiseMin(vertices[t[k]]);
      hi = hi.cwiseMax(vertices[t[k]]);
    }
    Eigen::Vector3i a, b;
    for (int k = 0; k < 3; ++k) {
      a[k] = std::max(0, static_cast<int>(std::ceil((lo[k] - band - origin[k]) / h)));
      b[k] = std::min(dims[k] - 1, static_cast<int>(std::floor((hi[k] + band - origin[k]) / h)));
    }
    const Eigen::Vector3d& normal = face_normals[f];
    const double plane = normal.dot(vertices[t[0]]);
    for (int z = a.z(); z <= b.z(); ++z) {
      for (int y = a.y(); y <= b.y(); ++y) {
        for (int x = a.x(); x <= b.x(); ++x) {
          const Eigen::Vector3d p = nodePosition(x, y, z);
          float& value = values[node(x, y, z)];
          // The distance to the plane bounds the distance to the triangle: most nodes of the
          // box stop here.
          const double to_plane = std::abs(normal.dot(p) - plane);
          if (to_plane > band || to_plane >= std::abs(value)) continue;
          const double d = signedAt(p, f);
          if (std::abs(d) <= band && std::abs(d) < std::abs(value)) value = static_cast<float>(d);
        }
      }
    }
  }
}

void DistanceField::Impl::floodFillSign() {
  // Nodes beyond the band: outside when connected (6-neighbours, beyond the band) to the grid's
  // border, which lies outside the object; a path between adjacent nodes that crossed the
  // surface would pass a node within spacing/2 <= band of it.
  const float outside = static_cast<float>(band);
  const float inside = -static_cast<float>(bounds.diagonal() + 2 * band + 4 * h);
  std::vector<std::size_t> stack;
  const auto visit = [&](int x, int y, int z) {
    float& v = values[node(x, y, z)];
    if (std::isinf(v)) {
      v = outside;
      stack.push_back(node(x, y, z));
    }
  };
  for (int z = 0; z < dims.z(); ++z) {
    for (int y = 0; y < dims.y(); ++y) {
      for (int x = 0; x < dims.x(); ++x) {
        if (x == 0 || y == 0 || z == 0 || x == dims.x() - 1 || y == dims.y() - 1 ||
            z == dims.z() - 1)
          visit(x, y, z);
      }
    }
  }
  while (!stack.empty()) {
    const std::size_t n = stack.back();
    stack.pop_back();
    const int x = static_cast<int>(n % dims.x());
    const int y = static_cast<int>((n / dims.x()) % dims.y());
    const int z = static_cast<int>(n / (static_cast<std::size_t>(dims.x()) * dims.y()));
    if (x > 0) visit(x - 1, y, z);
    if (x + 1 < dims.x()) visit(x + 1, y, z);
    if (y > 0) visit(x, y - 1, z);
    if (y + 1 < dims.y()) visit(x, y + 1, z);
    if (z > 0) visit(x, y, z - 1);
    if (z + 1 < dims.z()) visit(x, y, z + 1);
  }
  for (float& v : values) {
    if (std::isinf(v)) v = is_signed ? inside : outside;
  }
}

void checkDistanceFieldParams(const DistanceFieldParams& params) {
  if (!(params.spacing_m > 0) || !(params.band_m > 0))
    throw InvalidArgument("distance field: spacing and band must be positive");
}

DistanceField::DistanceField(const TriangleMesh& mesh, bool signed_field,
                             const DistanceFieldParams& params)
    : impl_(std::make_unique<Impl>()) {
  if (mesh.empty()) throw InvalidArgument("DistanceField: empty mesh");
  checkDistanceFieldParams(params);
  auto& m = *impl_;
  m.vertices = mesh.vertices;
  m.faces = mesh.faces;
  m.bounds = mesh.bounds();
  m.is_signed = signed_field;
  m.skip_empty_cells = params.skip_empty_cells;
  m.h = params.spacing_m;
  for (;;) {
    m.band = std::max(params.band_m, m.h);  // the flood fill needs a band of at least a cell
    const double margin = m.band + 2 * m.h;
    m.origin = m.bounds.min - Eigen::Vector3d::Constant(margin);
    for (int k = 0; k < 3; ++k)
      m.dims[k] = static_cast<int>(std::ceil((m.bounds.extent()[k] + 2 * margin) / m.h)) + 1;
    const double nodes = static_cast<double>(m.dims.x()) * m.dims.y() * m.dims.z();
    if (nodes <= static_cast<double>(params.max_nodes)) break;
    m.h *= std::max(1.01, std::cbrt(nodes / static_cast<double>(params.max_nodes)));
  }
  m.buildNormals();
  m.buildTriangleGrid();
  m.rasteriseBand();
  m.floodFillSign();
}

DistanceField::~DistanceField() = default;

double DistanceField::spacing() const {
  return impl_->h;
}
std::size_t DistanceField::nodeCount() const {
  return impl_->values.size();
}
bool DistanceField::isSigned() const {
  return impl_->is_signed;
}
double DistanceField::errorBound() const {
  return impl_->h * std::sqrt(3.0) / 2 + kFloatSlackM;
}

double DistanceField::value(const Eigen::Vector3d& p) const {
  const auto& m = *impl_;
  Eigen::Vector3i i;
  Eigen::Vector3d t;
  for (int k = 0; k < 3; ++k) {
    const double u = std::clamp((p[k] - m.origin[k]) / m.h, 0.0, m.dims[k] - 1.0);
    i[k] = std::min(static_cast<int>(u), m.dims[k] - 2);
    t[k] = u - i[k];
  }
  double sum = 0;
  for (int c = 0; c < 8; ++c) {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
    const double w = (dx ? t.x() : 1 - t.x()) * (dy ? t.y() : 1 - t.y()) * (dz ? t.z() : 1 - t.z());
    sum += w * m.values[m.node(i.x() + dx, i.y() + dy, i.z() + dz)];
  }
  // Beyond the grid the clamped point's value understates the distance; lowerBound is exact
  // about that.
  return sum;
}

double DistanceField::lowerBound(const Eigen::Vector3d& p) const {
  const auto& m = *impl_;
  // Beyond the mesh's box: the distance to the box bounds the distance to the surface.
  const Eigen::Vector3d outside_box = (m.bounds.min - p).cwiseMax(p - m.bounds.max).cwiseMax(0.0);
  const double box_bound = outside_box.norm();
  Eigen::Vector3i i;
  Eigen::Vector3d t;
  for (int k = 0; k < 3; ++k) {
    const double u = (p[k] - m.origin[k]) / m.h;
    if (!(u >= 0 && u <= m.dims[k] - 1.0)) return box_bound;  // beyond the margin
    i[k] = std::min(static_cast<int>(u), m.dims[k] - 2);
    t[k] = u - i[k];
  }
  // Node values v_c are at most the true distances and the distance is 1-Lipschitz, so both
  // d(p) >= v_c - |p - n_c| for every corner and d(p) >= sum w_c v_c - sum w_c |p - n_c|, where
  // the weighted mean of the corner distances is at most half the cell diagonal.
  double trilinear = 0, corner_bound = -std::numeric_limits<double>::infinity();
  for (int c = 0; c < 8; ++c) {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
    const double w = (dx ? t.x() : 1 - t.x()) * (dy ? t.y() : 1 - t.y()) * (dz ? t.z() : 1 - t.z());
    const double v = m.values[m.node(i.x() + dx, i.y() + dy, i.z() + dz)];
    trilinear += w * v;
    const Eigen::Vector3d offset =
        m.h *
        Eigen::Vector3d(dx ? 1 - t.x() : t.x(), dy ? 1 - t.y() : t.y(), dz ? 1 - t.z() : t.z());
    corner_bound = std::max(corner_bound, v - offset.norm());
  }
  double bound = std::max(trilinear - m.h * std::sqrt(3.0) / 2, corner_bound) - kFloatSlackM;
  if (box_bound > 0) bound = std::max(bound, box_bound);  // p is outside the object
  return bound;
}

double DistanceField::unsignedUpperBound(const Eigen::Vector3d& p) const {
  const auto& m = *impl_;
  Eigen::Vector3i i;
  Eigen::Vector3d t;
  for (int k = 0; k < 3; ++k) {
    const double u = (p[k] - m.origin[k]) / m.h;
    if (!(u >= 0 && u <= m.dims[k] - 1.0)) return std::numeric_limits<double>::infinity();
    i[k] = std::min(static_cast<int>(u), m.dims[k] - 2);
    t[k] = u - i[k];
  }
  // |d| is 1-Lipschitz: |d(p)| <= |d(n_c)| + |p - n_c| for every corner with an exact value
  // (strictly inside the band; beyond it the nodes hold bounds only).
  double bound = std::numeric_limits<double>::infinity();
  for (int c = 0; c < 8; ++c) {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
    const double v = std::abs(m.values[m.node(i.x() + dx, i.y() + dy, i.z() + dz)]);
    if (!(v < m.band)) continue;
    const Eigen::Vector3d offset =
        m.h *
        Eigen::Vector3d(dx ? 1 - t.x() : t.x(), dy ? 1 - t.y() : t.y(), dz ? 1 - t.z() : t.z());
    bound = std::min(bound, v + offset.norm());
  }
  return bound + kFloatSlackM;
}

}  // namespace skelgrasp::grasping
