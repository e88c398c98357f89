#pragma once
// Nearest-neighbour queries over a fixed point set: the one kd-tree of the project (nanoflann,
// exact search in double precision), used by perception, reconstruction and skeleton.
#include <Eigen/Core>

#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

namespace skelgrasp::geometry {

class PointIndex {
 public:
  // Non-finite points are skipped (never returned). The points are copied.
  explicit PointIndex(const std::vector<Eigen::Vector3d>& points);
  ~PointIndex();
  PointIndex(const PointIndex&) = delete;
  PointIndex& operator=(const PointIndex&) = delete;

  // Number of indexed (finite) points.
  std::size_t size() const;
  // Index (into the constructor's vector) and distance (metres) of the nearest point; among
  // equally near points the lowest index. {-1, inf} if the index is empty or the query not finite.
  std::pair<int, double> nearest(const Eigen::Vector3d& query) const;
  // Up to k nearest points as (index, distance), by distance, then index.
  std::vector<std::pair<int, double>> nearestK(const Eigen::Vector3d& query, std::size_t k) const;
  // Indices of the points closer than `radius` (metres), by distance, then index.
  std::vector<int> within(const Eigen::Vector3d& query, double radius) const;
  std::size_t countWithin(const Eigen::Vector3d& query, double radius) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Index of the nearest `targets` point for every query (lowest index among equally near ones),
// and optionally its distance. Throws InvalidArgument when `targets` has no finite point.
std::vector<int> nearestPoints(const std::vector<Eigen::Vector3d>& targets,
                               const std::vector<Eigen::Vector3d>& queries,
                               std::vector<double>* distances = nullptr);

}  // namespace skelgrasp::geometry
