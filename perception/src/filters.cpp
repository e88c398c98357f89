// PCL translation unit: NaN removal, crop box, voxel grid, statistical outlier removal, normals.
#include "skelgrasp/perception/filters.h"

#include <pcl/features/normal_3d_omp.h>
#include <pcl/filters/crop_box.h>
#include <pcl/filters/filter.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/kdtree/kdtree_flann.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

#include "skelgrasp/common/logging.h"
#include "skelgrasp/internal/pcl_conversions.h"
#include "skelgrasp/perception/cloud_ops.h"

namespace skelgrasp::perception {
namespace {

// Averaged normals shorter than this (unit normals, dimensionless) cancelled out: no normal.
constexpr double kCancelledNormalLength = 1e-9;

using internal::PclCloud;
using internal::PclPoint;

std::vector<int> toIntIndices(const pcl::Indices& indices) {
  return std::vector<int>(indices.begin(), indices.end());
}

// PCL's voxel grid indexes voxels with 32-bit integers and silently returns its input when the
// grid would overflow; detect that case so the report can say so.
bool voxelGridFits(const AxisAlignedBox& box, double leaf) {
  const Eigen::Vector3d cells = (box.extent() / leaf).array().floor() + 1.0;
  return cells.prod() < static_cast<double>(std::numeric_limits<std::int32_t>::max());
}

// Integer voxel coordinates as PCL's voxel grid computes them (floats, floor of p / leaf), in 64
// bits and clamped so that no coordinate of a finite point overflows the conversion.
using VoxelKey = std::array<std::int64_t, 3>;
VoxelKey voxelOf(const Eigen::Vector3d& p, float inverse_leaf) {
  constexpr float kMaxVoxelIndex = 1e18f;  // below 2^63
  constexpr double kMaxFloat = 1e38;       // below the largest float
  const auto axis = [&](double x) {
    const float cell =
        std::floor(static_cast<float>(std::clamp(x, -kMaxFloat, kMaxFloat)) * inverse_leaf);
    return static_cast<std::int64_t>(std::clamp(cell, -kMaxVoxelIndex, kMaxVoxelIndex));
  };
  return {axis(p.x()), axis(p.y()), axis(p.z())};
}

struct VoxelHash {
  std::size_t operator()(const VoxelKey& v) const {
    // Large odd multipliers spread neighbouring voxels over the buckets.
    return static_cast<std::size_t>(v[0]) * 73856093u ^ static_cast<std::size_t>(v[1]) * 19349663u ^
           static_cast<std::size_t>(v[2]) * 83492791u;
  }
};

// A voxel's label is the label of its input point nearest to its centroid: averaging labels would
// invent ids. Points find their voxel's centroid by the voxel coordinates (one pass, no search
// tree: a k-d tree over a 300k-point scan took a quarter of a second). A centroid that rounding
// left without a point of its own voxel takes the label of the nearest input point.
void assignVoxelLabels(const PointCloud& cloud, double leaf, PointCloud& voxels) {
  const float inverse_leaf = 1.0f / static_cast<float>(leaf);
  std::unordered_map<VoxelKey, std::size_t, VoxelHash> voxel_index;
  voxel_index.reserve(voxels.size());
  for (std::size_t i = 0; i < voxels.size(); ++i)
    voxel_index.emplace(voxelOf(voxels.points[i], inverse_leaf), i);
  voxels.labels.assign(voxels.size(), 0);
  std::vector<double> nearest(voxels.size(), std::numeric_limits<double>::infinity());
  for (std::size_t j = 0; j < cloud.size(); ++j) {
    const auto found = voxel_index.find(voxelOf(cloud.points[j], inverse_leaf));
    if (found == voxel_index.end()) continue;
    const std::size_t i = found->second;
    const double distance = (cloud.points[j] - voxels.points[i]).squaredNorm();
    if (distance < nearest[i]) {
      nearest[i] = distance;
      voxels.labels[i] = cloud.labels[j];
    }
  }
  std::vector<std::size_t> orphans;
  for (std::size_t i = 0; i < voxels.size(); ++i) {
    if (std::isinf(nearest[i])) orphans.push_back(i);
  }
  if (orphans.empty()) return;
  const auto xyz = internal::toPclXyz(cloud.points);
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(xyz);
  pcl::Indices index(1);
  std::vector<float> distance(1);
  for (std::size_t i : orphans) {
    const Eigen::Vector3f q = voxels.points[i].cast<float>();
    tree.nearestKSearch(pcl::PointXYZ(q.x(), q.y(), q.z()), 1, index, distance);
    voxels.labels[i] = cloud.labels[index[0]];
  }
}

PointCloud voxelDownsample(const PointCloud& cloud, double leaf) {
  const auto pcl_cloud = internal::toPcl(cloud);
  pcl::VoxelGrid<PclPoint> grid;
  grid.setInputCloud(pcl_cloud);
  const auto leaf_f = static_cast<float>(leaf);
  grid.setLeafSize(leaf_f, leaf_f, leaf_f);
  PclCloud out;
  grid.filter(out);
  PointCloud result = internal::fromPcl(out, cloud.hasNormals(), cloud.hasColors());
  result.width = result.height = 0;
  result.sensor_origin = cloud.sensor_origin;
  result.sensor_orientation = cloud.sensor_orientation;
  for (auto& n : result.normals) {
    const double norm = n.norm();
    n = norm > kCancelledNormalLength ? Eigen::Vector3d(n / norm) : Eigen::Vector3d::Zero();
  }
  if (cloud.hasLabels() && !result.empty()) assignVoxelLabels(cloud, leaf, result);
  return result;
}

}  // namespace

FilterResult filterCloud(const PointCloud& cloud, const FilterParams& params) {
  if (params.voxel_leaf_m < 0 || params.sor_mean_k < 0 || params.sor_stddev_mul <= 0) {
    throw InvalidArgument("filterCloud: voxel leaf, mean k and stddev multiplier out of range");
  }
  if (params.crop_box && params.crop_box->empty()) {
    throw InvalidArgument("filterCloud: crop box min exceeds max");
  }
  Stopwatch total;
  FilterResult result;
  auto step = [&result](const std::string& name, std::size_t in, std::size_t out, double t) {
    result.steps.push_back({name, in, out, t});
    log().debug("filter {}: {} -> {} points ({:.3f} s)", name, in, out, t);
  };
  if (cloud.empty()) {
    result.status = Status::Make(StatusCode::kInvalidInput, "the cloud has no points");
    return result;
  }

  Stopwatch watch;
  PointCloud current;
  {
    std::vector<int> finite;
    finite.reserve(cloud.size());
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      if (cloud.points[i].allFinite()) finite.push_back(static_cast<int>(i));
    }
    current = subset(cloud, finite);
    step("non_finite", cloud.size(), current.size(), watch.seconds());
  }
  if (current.empty()) {
    result.status = Status::Make(StatusCode::kInvalidInput, "all " + std::to_string(cloud.size()) +
                                                                " points are NaN or infinite");
    result.time_s = total.seconds();
    return result;
  }
  auto indexFilter = [&](const std::string& name, auto&& configure) {
    watch.restart();
    const auto pcl_cloud = internal::toPcl(current);
    pcl::Indices kept;
    configure(pcl_cloud, kept);
    const std::size_t before = current.size();
    current = subset(current, toIntIndices(kept));
    step(name, before, current.size(), watch.seconds());
  };

  if (params.crop_box) {
    indexFilter("crop_box", [&](const PclCloud::Ptr& in, pcl::Indices& kept) {
      pcl::CropBox<PclPoint> crop;
      crop.setInputCloud(in);
      const auto& box = *params.crop_box;
      crop.setMin(Eigen::Vector4f(box.min.x(), box.min.y(), box.min.z(), 1.0f));
      crop.setMax(Eigen::Vector4f(box.max.x(), box.max.y(), box.max.z(), 1.0f));
      crop.filter(kept);
    });
  }
  if (params.voxel_leaf_m > 0 && !current.empty()) {
    watch.restart();
    const std::size_t before = current.size();
    if (voxelGridFits(current.bounds(), params.voxel_leaf_m)) {
      current = voxelDownsample(current, params.voxel_leaf_m);
    } else {
      log().warn(
          "voxel grid skipped: a {:.4g} m leaf over a {:.3g} m wide cloud overflows PCL's "
          "voxel indices (crop the cloud first)",
          params.voxel_leaf_m, current.bounds().diagonal());
    }
    step("voxel_grid", before, current.size(), watch.seconds());
  }
  if (params.sor_mean_k > 0 && current.size() > static_cast<std::size_t>(params.sor_mean_k)) {
    indexFilter("outlier_removal", [&](const PclCloud::Ptr& in, pcl::Indices& kept) {
      pcl::StatisticalOutlierRemoval<PclPoint> sor;
      sor.setInputCloud(in);
      sor.setMeanK(params.sor_mean_k);
      sor.setStddevMulThresh(params.sor_stddev_mul);
      sor.filter(kept);
    });
  }
  result.cloud = std::move(current);
  result.time_s = total.seconds();
  if (result.cloud.empty()) {
    result.status = Status::Make(StatusCode::kNoResult, "no points left after filtering");
  }
  return result;
}

NormalResult estimateNormals(const PointCloud& cloud, const NormalParams& params) {
  if (params.k <= 0 && !(params.radius_m > 0)) {
    throw InvalidArgument("estimateNormals: radius_m must be positive when k is 0");
  }
  Stopwatch watch;
  NormalResult result;
  std::vector<int> finite;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.points[i].allFinite()) finite.push_back(static_cast<int>(i));
  }
  const PointCloud input = subset(cloud, finite);
  if (input.size() < 3) {
    result.status = Status::Make(StatusCode::kInvalidInput, "fewer than 3 points for normals");
    return result;
  }
  const auto pcl_cloud = internal::toPcl(input);
  pcl::NormalEstimationOMP<PclPoint, pcl::Normal> estimator;
  estimator.setNumberOfThreads(static_cast<unsigned>(std::max(0, params.threads)));
  estimator.setInputCloud(pcl_cloud);
  estimator.setSearchMethod(std::make_shared<pcl::search::KdTree<PclPoint>>());
  if (params.k > 0) {
    estimator.setKSearch(params.k);
  } else {
    estimator.setRadiusSearch(params.radius_m);
  }
  const Eigen::Vector3f vp = cloud.sensor_origin.cast<float>();
  estimator.setViewPoint(vp.x(), vp.y(), vp.z());
  pcl::PointCloud<pcl::Normal> normals;
  estimator.compute(normals);

  std::vector<int> kept;
  std::vector<Eigen::Vector3d> kept_normals;
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const auto& n = normals.points[i];
    const Eigen::Vector3d normal(n.normal_x, n.normal_y, n.normal_z);
    if (!normal.allFinite() || normal.norm() < 0.5) continue;
    kept.push_back(static_cast<int>(i));
    kept_normals.push_back(normal.normalized());
  }
  result.cloud = subset(input, kept);
  result.cloud.normals = std::move(kept_normals);
  result.dropped_points = input.size() - kept.size();
  result.time_s = watch.seconds();
  if (result.cloud.empty()) {
    result.status =
        Status::Make(StatusCode::kNoResult, "no point had enough neighbours for a normal");
  }
  return result;
}

PointCloud fuseViews(const std::vector<PointCloud>& views, const NormalParams& params) {
  PointCloud fused;
  Eigen::Vector3d origin_sum = Eigen::Vector3d::Zero();
  std::size_t used = 0;
  for (const auto& view : views) {
    const NormalResult r = estimateNormals(view, params);
    if (!r.status.ok()) continue;
    append(fused, r.cloud);
    origin_sum += view.sensor_origin;
    ++used;
  }
  if (used > 0) fused.sensor_origin = origin_sum / static_cast<double>(used);
  fused.sensor_orientation = Eigen::Quaterniond::Identity();
  return fused;
}

}  // namespace skelgrasp::perception
