// PCL translation unit: kd-tree nearest-neighbour queries.
#include "skelgrasp/perception/point_index.h"

#include <pcl/kdtree/kdtree_flann.h>

#include <cmath>
#include <limits>

#include "skelgrasp/internal/pcl_conversions.h"

namespace skelgrasp::perception {

struct PointIndex::Impl {
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  std::vector<int> original;  // tree index -> constructor index
  bool empty = true;
};

PointIndex::PointIndex(const std::vector<Eigen::Vector3d>& points) : impl_(new Impl) {
  std::vector<Eigen::Vector3d> finite;
  finite.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) continue;
    finite.push_back(points[i]);
    impl_->original.push_back(static_cast<int>(i));
  }
  impl_->empty = finite.empty();
  if (!impl_->empty) impl_->tree.setInputCloud(internal::toPclXyz(finite));
}

PointIndex::~PointIndex() = default;

std::size_t PointIndex::size() const {
  return impl_->original.size();
}

namespace {
pcl::PointXYZ toQuery(const Eigen::Vector3d& q) {
  return {static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z())};
}
}  // namespace

std::pair<int, double> PointIndex::nearest(const Eigen::Vector3d& query) const {
  if (impl_->empty || !query.allFinite()) return {-1, std::numeric_limits<double>::infinity()};
  pcl::Indices index(1);
  std::vector<float> squared(1);
  if (impl_->tree.nearestKSearch(toQuery(query), 1, index, squared) < 1) {
    return {-1, std::numeric_limits<double>::infinity()};
  }
  return {impl_->original[index[0]], std::sqrt(static_cast<double>(squared[0]))};
}

std::vector<int> PointIndex::within(const Eigen::Vector3d& query, double radius) const {
  std::vector<int> out;
  if (impl_->empty || !query.allFinite() || !(radius > 0)) return out;
  pcl::Indices indices;
  std::vector<float> squared;
  impl_->tree.radiusSearch(toQuery(query), radius, indices, squared);
  out.reserve(indices.size());
  for (auto i : indices) out.push_back(impl_->original[i]);
  return out;
}

std::size_t PointIndex::countWithin(const Eigen::Vector3d& query, double radius) const {
  if (impl_->empty || !query.allFinite() || !(radius > 0)) return 0;
  pcl::Indices indices;
  std::vector<float> squared;
  return static_cast<std::size_t>(
      impl_->tree.radiusSearch(toQuery(query), radius, indices, squared));
}

}  // namespace skelgrasp::perception
