// nanoflann translation unit: the project's one kd-tree (exact search in double precision).
#include "skelgrasp/geometry/point_index.h"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "skelgrasp/common/error.h"

namespace skelgrasp::geometry {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Points per kd-tree leaf: nanoflann's default, a good balance of build and query time for 3D.
constexpr std::size_t kLeafMaxPoints = 10;

// nanoflann's dataset interface over the finite points.
struct Cloud {
  std::vector<Eigen::Vector3d> points;
  std::size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(std::uint32_t i, std::size_t dim) const { return points[i][dim]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;  // let nanoflann compute it
  }
};

using Tree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 3>;
using Candidate = std::pair<double, std::uint32_t>;  // squared distance, tree index

// The k nearest by (squared distance, index). nanoflann offers a leaf point only when it is
// strictly nearer than worstDist(); reporting the k-th distance's successor lets equally near
// points through, so ties go to the lower index whatever the tree's visiting order.
class OrderedNearest {
 public:
  explicit OrderedNearest(std::size_t k) : k_(k) { items_.reserve(k); }
  bool full() const { return items_.size() == k_; }
  double worstDist() const {
    return full() ? std::nextafter(items_.back().first, kInfinity) : kInfinity;
  }
  bool addPoint(double squared, std::uint32_t index) {
    const Candidate item{squared, index};
    const auto at = static_cast<std::size_t>(std::upper_bound(items_.begin(), items_.end(), item) -
                                             items_.begin());
    if (at == k_) return true;
    if (full()) items_.pop_back();
    items_.insert(items_.begin() + static_cast<std::ptrdiff_t>(at), item);
    return true;
  }
  const std::vector<Candidate>& items() const { return items_; }

 private:
  std::size_t k_;
  std::vector<Candidate> items_;
};

// Every point strictly closer than the radius (squared distances).
class WithinRadius {
 public:
  explicit WithinRadius(double squared_radius) : squared_radius_(squared_radius) {}
  bool full() const { return true; }
  double worstDist() const { return squared_radius_; }
  bool addPoint(double squared, std::uint32_t index) {
    if (squared < squared_radius_) items_.emplace_back(squared, index);
    return true;
  }
  std::vector<Candidate>& items() { return items_; }

 private:
  double squared_radius_;
  std::vector<Candidate> items_;
};

}  // namespace

struct PointIndex::Impl {
  Cloud cloud;                // the tree keeps a reference: declared (and built) first
  std::vector<int> original;  // tree index -> constructor index
  std::unique_ptr<Tree> tree;

  template <class ResultSet>
  void search(ResultSet& result, const Eigen::Vector3d& query) const {
    const double q[3] = {query.x(), query.y(), query.z()};
    tree->findNeighbors(result, q, nanoflann::SearchParams());
  }
};

PointIndex::PointIndex(const std::vector<Eigen::Vector3d>& points) : impl_(new Impl) {
  impl_->cloud.points.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) continue;
    impl_->cloud.points.push_back(points[i]);
    impl_->original.push_back(static_cast<int>(i));
  }
  if (!impl_->cloud.points.empty()) {
    impl_->tree = std::make_unique<Tree>(3, impl_->cloud,
                                         nanoflann::KDTreeSingleIndexAdaptorParams(kLeafMaxPoints));
  }
}

PointIndex::~PointIndex() = default;

std::size_t PointIndex::size() const {
  return impl_->original.size();
}

std::pair<int, double> PointIndex::nearest(const Eigen::Vector3d& query) const {
  const auto found = nearestK(query, 1);
  if (found.empty()) return {-1, kInfinity};
  return found.front();
}

std::vector<std::pair<int, double>> PointIndex::nearestK(const Eigen::Vector3d& query,
                                                         std::size_t k) const {
  std::vector<std::pair<int, double>> out;
  if (!impl_->tree || !query.allFinite() || k == 0) return out;
  OrderedNearest result(std::min(k, size()));
  impl_->search(result, query);
  out.reserve(result.items().size());
  for (const auto& [squared, index] : result.items())
    out.emplace_back(impl_->original[index], std::sqrt(squared));
  return out;
}

std::vector<int> PointIndex::within(const Eigen::Vector3d& query, double radius) const {
  std::vector<int> out;
  if (!impl_->tree || !query.allFinite() || !(radius > 0)) return out;
  WithinRadius result(radius * radius);
  impl_->search(result, query);
  std::sort(result.items().begin(), result.items().end());
  out.reserve(result.items().size());
  for (const auto& item : result.items()) out.push_back(impl_->original[item.second]);
  return out;
}

std::size_t PointIndex::countWithin(const Eigen::Vector3d& query, double radius) const {
  if (!impl_->tree || !query.allFinite() || !(radius > 0)) return 0;
  WithinRadius result(radius * radius);
  impl_->search(result, query);
  return result.items().size();
}

std::vector<int> nearestPoints(const std::vector<Eigen::Vector3d>& targets,
                               const std::vector<Eigen::Vector3d>& queries,
                               std::vector<double>* distances) {
  const PointIndex index(targets);
  if (index.size() == 0) throw InvalidArgument("nearestPoints: no target points");
  std::vector<int> nearest(queries.size());
  if (distances) distances->resize(queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const auto [target, distance] = index.nearest(queries[i]);
    nearest[i] = target;
    if (distances) (*distances)[i] = distance;
  }
  return nearest;
}

}  // namespace skelgrasp::geometry
