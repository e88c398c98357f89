#pragma once
// Nearest-neighbour queries over a fixed point set (PCL kd-tree, built once).
#include <Eigen/Core>

#include <memory>
#include <utility>
#include <vector>

namespace skelgrasp::perception {

class PointIndex {
 public:
  // Non-finite points are skipped (never returned).
  explicit PointIndex(const std::vector<Eigen::Vector3d>& points);
  ~PointIndex();
  PointIndex(const PointIndex&) = delete;
  PointIndex& operator=(const PointIndex&) = delete;

  std::size_t size() const;
  // Index (into the constructor's vector) and distance of the nearest point; {-1, inf} if empty.
  std::pair<int, double> nearest(const Eigen::Vector3d& query) const;
  // Indices of the points within `radius`.
  std::vector<int> within(const Eigen::Vector3d& query, double radius) const;
  std::size_t countWithin(const Eigen::Vector3d& query, double radius) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace skelgrasp::perception
