// PCL translation unit: support plane (RANSAC), prism over its hull; the segmentation of the
// points above it is in segmentation.cpp.
#include "skelgrasp/perception/scene.h"

#include <pcl/ModelCoefficients.h>
#include <pcl/filters/project_inliers.h>
#include <pcl/segmentation/extract_polygonal_prism_data.h>
#include <pcl/segmentation/sac_segmentation.h>
#include <pcl/surface/convex_hull.h>

#include <Eigen/Eigenvalues>
#include <algorithm>

#include "skelgrasp/common/logging.h"
#include "skelgrasp/internal/pcl_conversions.h"
#include "skelgrasp/internal/segmentation.h"
#include "skelgrasp/perception/cloud_ops.h"

namespace skelgrasp::perception {
namespace {

using XyzCloud = pcl::PointCloud<pcl::PointXYZ>;

std::vector<Eigen::Vector3d> gather(const PointCloud& cloud, const std::vector<int>& indices) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(indices.size());
  for (int i : indices) out.push_back(cloud.points[i]);
  return out;
}

// One RANSAC plane over cloud.points[indices]; inliers as indices into `cloud`.
std::optional<SupportPlane> ransacPlane(const PointCloud& cloud, const std::vector<int>& indices,
                                        const SceneParams& params, std::vector<int>& inliers_out) {
  if (indices.size() < 3) return std::nullopt;
  const auto xyz = internal::toPclXyz(gather(cloud, indices));
  pcl::SACSegmentation<pcl::PointXYZ> seg;
  seg.setOptimizeCoefficients(true);
  seg.setModelType(pcl::SACMODEL_PLANE);
  seg.setMethodType(pcl::SAC_RANSAC);
  seg.setDistanceThreshold(params.plane_distance_m);
  seg.setMaxIterations(params.plane_max_iterations);
  seg.setInputCloud(xyz);
  pcl::PointIndices inliers;
  pcl::ModelCoefficients coefficients;
  seg.segment(inliers, coefficients);
  if (coefficients.values.size() != 4 || inliers.indices.size() < 3) return std::nullopt;
  Eigen::Vector3d n(coefficients.values[0], coefficients.values[1], coefficients.values[2]);
  double d = coefficients.values[3];
  const double norm = n.norm();
  if (!(norm > 0)) return std::nullopt;
  n /= norm;
  d /= norm;
  if (n.dot(cloud.sensor_origin) + d < 0) {  // face the sensor: objects are on the positive side
    n = -n;
    d = -d;
  }
  SupportPlane plane;
  plane.normal = n;
  plane.d = d;
  plane.inliers = inliers.indices.size();
  inliers_out.clear();
  for (auto i : inliers.indices) inliers_out.push_back(indices[i]);
  return plane;
}

// Share of a plane's inliers within half the inlier distance: sensor noise on a real plane keeps
// it high, a band around a curved surface spreads the residuals evenly (about one half).
double flatness(const PointCloud& cloud, const std::vector<int>& inliers, const SupportPlane& plane,
                double distance) {
  std::size_t core = 0;
  for (int i : inliers) core += std::abs(plane.signedDistance(cloud.points[i])) <= 0.5 * distance;
  return inliers.empty() ? 0.0 : static_cast<double>(core) / static_cast<double>(inliers.size());
}

// Extracts up to params.plane_candidates large planes one after the other, keeps the flat ones
// and returns, among those nearly as large as the largest, the one nearest to the sensor.
std::optional<SupportPlane> fitPlane(const PointCloud& cloud, const std::vector<int>& indices,
                                     const SceneParams& params, std::vector<int>& inliers_out) {
  const double needed = params.min_plane_fraction * static_cast<double>(indices.size());
  std::vector<int> remaining = indices;
  struct Candidate {
    SupportPlane plane;
    std::vector<int> inliers;
    double distance;
  };
  std::vector<Candidate> flat;
  for (int k = 0; k < params.plane_candidates; ++k) {
    std::vector<int> inliers;
    const auto plane = ransacPlane(cloud, remaining, params, inliers);
    if (!plane || static_cast<double>(inliers.size()) < needed) {
      log().debug("plane candidate {}: {} points, below the {:.0f} needed", k,
                  plane ? inliers.size() : 0, needed);
      break;
    }
    const double f = flatness(cloud, inliers, *plane, params.plane_distance_m);
    const double distance = plane->signedDistance(cloud.sensor_origin);
    log().debug("plane candidate {}: {} inliers, {:.3f} m from the sensor, flatness {:.2f}", k,
                inliers.size(), distance, f);
    if (f >= params.min_plane_flatness) flat.push_back({*plane, inliers, distance});
    std::vector<char> is_inlier(cloud.size(), 0);
    for (int i : inliers) is_inlier[i] = 1;
    std::vector<int> rest;
    for (int i : remaining) {
      if (!is_inlier[i]) rest.push_back(i);
    }
    remaining.swap(rest);
  }
  if (flat.empty()) {
    log().info("support plane: no flat plane holds {:.0f} of the {} points", needed,
               indices.size());
    return std::nullopt;
  }
  std::size_t largest = 0;
  for (const auto& c : flat) largest = std::max(largest, c.inliers.size());
  const Candidate* best = nullptr;
  for (const auto& c : flat) {
    if (static_cast<double>(c.inliers.size()) < params.plane_candidate_ratio * largest) continue;
    if (!best || c.distance < best->distance) best = &c;
  }
  inliers_out = best->inliers;
  return best->plane;
}

// Indices (into `cloud`) of candidate points inside the prism over the convex hull of the plane
// inliers grown by plane_hull_margin_m, between the height limits.
std::vector<int> prismAbove(const PointCloud& cloud, const std::vector<int>& candidates,
                            const std::vector<int>& plane_inliers, const SupportPlane& plane,
                            const SceneParams& params) {
  const auto inlier_xyz = internal::toPclXyz(gather(cloud, plane_inliers));
  pcl::ModelCoefficients::Ptr coefficients(new pcl::ModelCoefficients);
  coefficients->values = {static_cast<float>(plane.normal.x()),
                          static_cast<float>(plane.normal.y()),
                          static_cast<float>(plane.normal.z()), static_cast<float>(plane.d)};
  pcl::ProjectInliers<pcl::PointXYZ> project;
  project.setModelType(pcl::SACMODEL_PLANE);
  project.setInputCloud(inlier_xyz);
  project.setModelCoefficients(coefficients);
  XyzCloud::Ptr projected(new XyzCloud);
  project.filter(*projected);

  pcl::ConvexHull<pcl::PointXYZ> hull;
  hull.setDimension(2);
  hull.setInputCloud(projected);
  XyzCloud::Ptr hull_points(new XyzCloud);
  hull.reconstruct(*hull_points);
  if (hull_points->size() < 3) return {};
  const double margin = params.plane_hull_margin_m;
  if (margin > 0) {
    // The hull grown by the margin: the hull of discs (inscribed polygons of kDiscCorners corners,
    // so at least 98 % of the margin) about its corners, i.e. its Minkowski sum with a disc.
    constexpr int kDiscCorners = 16;
    const Eigen::Vector3d n = plane.normal.normalized();
    const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
    XyzCloud::Ptr grown(new XyzCloud);
    for (const auto& corner : hull_points->points) {
      for (int k = 0; k < kDiscCorners; ++k) {
        const double angle = 2 * M_PI * k / kDiscCorners;
        const Eigen::Vector3d q = corner.getVector3fMap().cast<double>() +
                                  margin * (std::cos(angle) * u + std::sin(angle) * v);
        grown->push_back(pcl::PointXYZ(q.x(), q.y(), q.z()));
      }
    }
    hull.setInputCloud(grown);
    hull_points.reset(new XyzCloud);
    hull.reconstruct(*hull_points);
  }

  const auto candidate_xyz = internal::toPclXyz(gather(cloud, candidates));
  pcl::ExtractPolygonalPrismData<pcl::PointXYZ> prism;
  prism.setInputCloud(candidate_xyz);
  prism.setInputPlanarHull(hull_points);
  prism.setHeightLimits(params.min_height_m, params.max_height_m);
  const Eigen::Vector3f vp = cloud.sensor_origin.cast<float>();
  prism.setViewPoint(vp.x(), vp.y(), vp.z());
  pcl::PointIndices inside;
  prism.segment(inside);
  std::vector<int> out;
  out.reserve(inside.indices.size());
  for (auto i : inside.indices) out.push_back(candidates[i]);
  return out;
}

std::vector<std::size_t> selectTargets(const std::vector<ClusterInfo>& info,
                                       const TargetSpec& target) {
  std::vector<std::size_t> selected;
  if (info.empty()) return selected;
  switch (target.mode) {
    case TargetMode::kAll:
      for (std::size_t i = 0; i < info.size(); ++i) selected.push_back(i);
      break;
    case TargetMode::kLargest:
      selected.push_back(0);  // clusters are sorted by size
      break;
    case TargetMode::kNearest: {
      std::size_t best = 0;
      for (std::size_t i = 1; i < info.size(); ++i) {
        if ((info[i].centroid - target.point).norm() < (info[best].centroid - target.point).norm())
          best = i;
      }
      selected.push_back(best);
      break;
    }
    case TargetMode::kIndex:
      // Out of range selects nothing; parseScene reports it as the scene's status.
      if (target.index < info.size()) selected.push_back(target.index);
      break;
  }
  return selected;
}

// Points clearly below the plane (beyond its inlier band). Many of them mean the "support" may
// be a face of the one object a table-less cloud holds (a milk carton seen from the side): the
// object then lies behind it, and the fix is --plane none, which the message should say.
std::size_t pointsBelow(const PointCloud& cloud, const std::vector<int>& indices,
                        const SupportPlane& plane, double band_m) {
  std::size_t below = 0;
  for (int i : indices) {
    if (plane.signedDistance(cloud.points[i]) < -band_m) ++below;
  }
  return below;
}

void validate(const SceneParams& p) {
  if (!(p.plane_distance_m > 0) || p.plane_max_iterations <= 0 || p.min_plane_fraction < 0 ||
      p.min_plane_fraction > 1 || !(p.cluster_tolerance_m > 0) ||
      p.max_height_m <= p.min_height_m || p.plane_candidates < 1 || p.plane_candidate_ratio < 0 ||
      p.plane_candidate_ratio > 1 || !(p.lccp.voxel_resolution_m > 0) ||
      !(p.lccp.seed_resolution_m > p.lccp.voxel_resolution_m) ||
      !(p.lccp.concavity_tolerance_deg >= 0) || !(p.lccp.concavity_tolerance_deg < 180) ||
      !(p.lccp.color_importance >= 0) || !(p.lccp.spatial_importance >= 0) ||
      !(p.lccp.normal_importance >= 0) || !(p.lccp.smoothness_threshold >= 0) ||
      p.lccp.k_factor < 0 || !(p.lccp.part_min_lift_m >= 0) || !(p.lccp.part_max_aspect >= 0) ||
      !(p.lccp.part_max_fraction >= 0) || !(p.lccp.hidden_gap_max_m >= 0) ||
      !(p.lccp.hidden_gap_step_m > 0) || !(p.lccp.hidden_gap_ray_radius_rad >= 0) ||
      !(p.lccp.hidden_gap_min_depth_m >= 0) || !(p.lccp.hidden_gap_max_colour_distance >= 0) ||
      !(p.plane_hull_margin_m >= 0 && p.plane_hull_margin_m < 1e3)) {
    throw InvalidArgument(
        "parseScene: plane distance, iterations, plane fraction in [0, 1], candidates, cluster "
        "tolerance, height limits (max > min), hull margin in [0, 1000) m and LCCP parameters "
        "(seed "
        "resolution > voxel resolution > 0, concavity tolerance in [0, 180) degrees, importances "
        ">= 0) must be valid");
  }
}

}  // namespace

ClusterInfo describeCluster(const PointCloud& cluster, const std::optional<SupportPlane>& plane) {
  ClusterInfo info;
  info.points = cluster.size();
  if (cluster.empty()) return info;
  info.box = cluster.bounds();
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : cluster.points) mean += p;
  mean /= static_cast<double>(cluster.size());
  info.centroid = mean;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const auto& p : cluster.points) covariance += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  const Eigen::Matrix3d axes = solver.eigenvectors();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& p : cluster.points) {
    const Eigen::Vector3d q = axes.transpose() * (p - mean);
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  Eigen::Vector3d extent = hi - lo;
  std::sort(extent.data(), extent.data() + 3, std::greater<double>());
  info.extent = extent;
  if (plane) {
    for (const auto& p : cluster.points) {
      info.height_above_plane_m = std::max(info.height_above_plane_m, plane->signedDistance(p));
    }
  }
  return info;
}

SceneResult parseScene(const PointCloud& cloud, const SceneParams& params,
                       const std::vector<std::uint8_t>& object_mask) {
  validate(params);
  if (!object_mask.empty() && object_mask.size() != cloud.size()) {
    throw InvalidArgument("parseScene: object mask has " + std::to_string(object_mask.size()) +
                          " entries for " + std::to_string(cloud.size()) + " points");
  }
  SceneResult result;
  const bool masked = !object_mask.empty();
  std::vector<int> scene_indices, mask_indices;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!cloud.points[i].allFinite()) continue;
    (masked && object_mask[i] ? mask_indices : scene_indices).push_back(static_cast<int>(i));
  }
  if (scene_indices.empty() && mask_indices.empty()) {
    result.status = Status::Make(StatusCode::kInvalidInput, "the cloud has no finite points");
    return result;
  }

  Stopwatch watch;
  std::vector<int> plane_inliers;
  // With a mask the scene part may be empty (fused object-only captures): nothing to fit then.
  if ((masked && scene_indices.size() >= params.min_cluster_points) ||
      (!masked && params.plane != PlaneRequirement::kNone)) {
    result.plane = fitPlane(cloud, scene_indices, params, plane_inliers);
  }
  result.plane_time_s = watch.seconds();
  if (!result.plane && !masked && params.plane == PlaneRequirement::kRequired) {
    result.status =
        Status::Make(StatusCode::kNoResult,
                     "no support plane found (no plane holds " +
                         std::to_string(static_cast<int>(100 * params.min_plane_fraction)) +
                         " % of the points within " + std::to_string(params.plane_distance_m) +
                         " m; pass --plane optional or none for a single-object cloud)");
    return result;
  }
  if (result.plane) {
    result.plane_points = subset(cloud, plane_inliers);
    log().info("support plane: {:.3f} {:.3f} {:.3f} {:.3f}, {} inliers", result.plane->normal.x(),
               result.plane->normal.y(), result.plane->normal.z(), result.plane->d,
               plane_inliers.size());
  }

  watch.restart();
  std::vector<int> candidates;
  if (masked) {
    for (int i : mask_indices) {
      if (!result.plane ||
          result.plane->signedDistance(cloud.points[i]) > params.masked_min_height_m) {
        candidates.push_back(i);
      }
    }
  } else if (result.plane) {
    std::vector<char> is_inlier(cloud.size(), 0);
    for (int i : plane_inliers) is_inlier[i] = 1;
    std::vector<int> rest;
    for (int i : scene_indices) {
      if (!is_inlier[i]) rest.push_back(i);
    }
    if (params.restrict_to_plane_hull) {
      candidates = prismAbove(cloud, rest, plane_inliers, *result.plane, params);
    } else {
      for (int i : rest) {
        const double h = result.plane->signedDistance(cloud.points[i]);
        if (h >= params.min_height_m && h <= params.max_height_m) candidates.push_back(i);
      }
    }
  } else {
    candidates = scene_indices;
  }
  result.candidate_points = candidates.size();
  // LCCP cuts objects where they meet on a support; a mask already says what is object, and a
  // cloud without a support is one object (or nothing stands on anything).
  const bool use_lccp =
      params.segmentation == SegmentationMethod::kLccp && !masked && result.plane.has_value();
  result.segmentation = use_lccp ? SegmentationMethod::kLccp : SegmentationMethod::kEuclidean;
  internal::Segmentation segmentation =
      use_lccp ? internal::lccpSegments(cloud, candidates, params, *result.plane)
               : internal::euclideanSegments(cloud, candidates, params);
  auto clusters = std::move(segmentation.segments);
  result.dropped = std::move(segmentation.dropped);
  result.merged_fragments = segmentation.merged;
  if (masked && clusters.size() > 1) {
    for (std::size_t c = 1; c < clusters.size(); ++c) {
      clusters[0].insert(clusters[0].end(), clusters[c].begin(), clusters[c].end());
    }
    log().debug("scene: {} mask clusters kept together as one object", clusters.size());
    clusters.resize(1);
  }
  result.cluster_time_s = watch.seconds();
  if (clusters.empty()) {
    std::string message =
        "no object cluster of " + std::to_string(params.min_cluster_points) + " or more points";
    if (result.plane) {
      message = "no object above the support plane (" + std::to_string(candidates.size()) +
                " points above it, no " + toString(result.segmentation) + " segment of " +
                std::to_string(params.min_cluster_points) + " or more; " +
                std::to_string(result.dropped.size()) + " fragment(s) dropped)";
      const std::size_t below =
          pointsBelow(cloud, scene_indices, *result.plane, params.plane_distance_m);
      if (!masked && below >= params.min_cluster_points) {
        message += "; " + std::to_string(below) +
                   " points lie below it: if the cloud is one object without a table, the plane "
                   "is a face of it, pass --plane none";
      }
    }
    result.status = Status::Make(StatusCode::kNoResult, message);
    return result;
  }
  for (const auto& members : clusters) {
    result.clusters.push_back(subset(cloud, members));
    result.cluster_info.push_back(describeCluster(result.clusters.back(), result.plane));
  }
  result.selected = selectTargets(result.cluster_info, params.target);
  if (result.selected.empty()) {
    result.status =
        Status::Make(StatusCode::kNoResult,
                     "object " + params.target.toString() + " asked, the scene has " +
                         std::to_string(clusters.size()) + " object(s) (index:0 to index:" +
                         std::to_string(clusters.size() - 1) + ", largest first)");
    return result;
  }
  std::vector<char> taken(cloud.size(), 0);
  for (int i : plane_inliers) taken[i] = 1;
  for (std::size_t s : result.selected) {
    result.cluster_info[s].selected = true;
    for (int i : clusters[s]) taken[i] = 1;
  }
  // Points of the unselected clusters are "other" but not "loose".
  std::vector<char> in_cluster(cloud.size(), 0);
  for (const auto& members : clusters) {
    for (int i : members) in_cluster[i] = 1;
  }
  std::vector<int> other, loose;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (taken[i] || !cloud.points[i].allFinite()) continue;
    other.push_back(static_cast<int>(i));
    if (!in_cluster[i]) loose.push_back(static_cast<int>(i));
  }
  result.other_points = subset(cloud, other);
  result.loose_points = subset(cloud, loose);
  log().info(
      "scene: {} candidate points, {} {} segments (largest {}), {} merged, {} dropped, {} "
      "selected",
      candidates.size(), clusters.size(), toString(result.segmentation), clusters.front().size(),
      result.merged_fragments, result.dropped.size(), result.selected.size());
  return result;
}

}  // namespace skelgrasp::perception
