#pragma once
// Internal: the data of DistanceField, shared by its two translation units: distance_field.cpp
// (building the field, point queries) and distance_field_box.cpp (exact queries on the triangle
// grid: closest points, box gaps).
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "skelgrasp/grasping/simulation/distance_field.h"

namespace skelgrasp::grasping {

namespace distance_field_internal {

// The grid values are floats: their rounding (relative 6e-8 of at most a metre) is covered by
// this much slack in lowerBound.
constexpr double kFloatSlackM = 1e-7;
// Triangle grid cells are this many field cells wide.
constexpr int kCellsPerTriangleCell = 2;

}  // namespace distance_field_internal

struct DistanceField::Impl {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> faces;
  std::vector<Eigen::Vector3d> face_normals;
  std::vector<Eigen::Vector3d> vertex_normals;               // angle-weighted
  std::vector<std::array<Eigen::Vector3d, 3>> edge_normals;  // per face, edge k = (k, k+1)
  std::vector<Eigen::Vector3d> face_centres;                 // bounding sphere of each triangle
  std::vector<double> face_radii;
  AxisAlignedBox bounds;  // of the mesh
  bool is_signed = false;
  double band = 0;

  // Field grid.
  Eigen::Vector3d origin;
  double h = 0;
  Eigen::Vector3i dims;
  std::vector<float> values;

  // Triangle grid (same origin, cells of distance_field_internal::kCellsPerTriangleCell * h).
  double cell = 0;
  Eigen::Vector3i cell_dims;
  std::vector<std::uint32_t> cell_first;  // CSR offsets, one per cell plus one
  std::vector<std::uint32_t> cell_faces;
  // One bit per cell, set when it lists a face: the exact box gap walks thousands of mostly
  // empty cells per query, and this fits in the first-level cache where cell_first does not.
  std::vector<std::uint64_t> cell_occupied;

  bool occupied(std::size_t c) const { return (cell_occupied[c >> 6] >> (c & 63)) & 1u; }
  bool skip_empty_cells = true;  // DistanceFieldParams::skip_empty_cells

  // The first occupied cell in [c, end), or end: a row's empty runs are skipped a word (64 cells)
  // at a time, so a query's walk costs its occupied cells rather than every cell it reaches.
  std::size_t nextOccupied(std::size_t c, std::size_t end) const {
    if (!skip_empty_cells) {
      while (c < end && !occupied(c)) ++c;
      return c;
    }
    while (c < end) {
      const std::uint64_t rest = cell_occupied[c >> 6] >> (c & 63);
      if (rest != 0) return std::min(end, c + static_cast<std::size_t>(__builtin_ctzll(rest)));
      c = (c | 63) + 1;
    }
    return end;
  }

  std::size_t node(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * dims.y() + y) * dims.x() + x;
  }
  Eigen::Vector3d nodePosition(int x, int y, int z) const {
    return origin + h * Eigen::Vector3d(x, y, z);
  }
  std::size_t cellIndex(const Eigen::Vector3i& c) const {
    return (static_cast<std::size_t>(c.z()) * cell_dims.y() + c.y()) * cell_dims.x() + c.x();
  }
  Eigen::Vector3i cellOf(const Eigen::Vector3d& p) const {
    Eigen::Vector3i c;
    for (int k = 0; k < 3; ++k) {
      c[k] =
          std::clamp(static_cast<int>(std::floor((p[k] - origin[k]) / cell)), 0, cell_dims[k] - 1);
    }
    return c;
  }

  void buildNormals();
  void buildTriangleGrid();
  void rasteriseBand();
  void floodFillSign();
  double signedAt(const Eigen::Vector3d& p, std::size_t f) const;
};

}  // namespace skelgrasp::grasping
