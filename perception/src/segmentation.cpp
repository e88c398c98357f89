// PCL translation unit: the segmentations of the points above the support, Euclidean clusters and
// supervoxels + LCCP (locally convex connected patches).
#include "skelgrasp/internal/segmentation.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/segmentation/extract_clusters.h>
#include <pcl/segmentation/lccp_segmentation.h>
#include <pcl/segmentation/supervoxel_clustering.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "skelgrasp/common/logging.h"
#include "skelgrasp/internal/pcl_conversions.h"

namespace skelgrasp::internal {
namespace {

using perception::DroppedFragment;
using perception::SceneParams;
using SvPoint = pcl::PointXYZRGBA;

DroppedFragment fragment(const PointCloud& cloud, const std::vector<int>& members,
                         const std::string& reason) {
  DroppedFragment f;
  f.points = members.size();
  for (int i : members) f.centroid += cloud.points[i];
  if (!members.empty()) f.centroid /= static_cast<double>(members.size());
  f.reason = reason;
  log().debug("scene: dropped {} points near ({:.3f}, {:.3f}, {:.3f}): {}", f.points,
              f.centroid.x(), f.centroid.y(), f.centroid.z(), reason);
  return f;
}

// Keeps segments within the size limits (largest first); the others are recorded as dropped.
void keepBySize(const PointCloud& cloud, std::vector<std::vector<int>> found,
                const SceneParams& params, Segmentation& out) {
  for (auto& members : found) {
    if (members.size() < params.min_cluster_points) {
      out.dropped.push_back(fragment(cloud, members, "below_min_points"));
    } else if (params.max_cluster_points > 0 && members.size() > params.max_cluster_points) {
      out.dropped.push_back(fragment(cloud, members, "above_max_points"));
    } else {
      out.segments.push_back(std::move(members));
    }
  }
  std::stable_sort(out.segments.begin(), out.segments.end(),
                   [](const auto& a, const auto& b) { return a.size() > b.size(); });
}

pcl::PointCloud<SvPoint>::Ptr toSupervoxelInput(const PointCloud& cloud,
                                                const std::vector<int>& candidates) {
  auto out = std::make_shared<pcl::PointCloud<SvPoint>>();
  out->points.resize(candidates.size());
  const bool colors = cloud.hasColors();
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const auto& p = cloud.points[candidates[k]];
    SvPoint& q = out->points[k];
    q.x = static_cast<float>(p.x());
    q.y = static_cast<float>(p.y());
    q.z = static_cast<float>(p.z());
    q.r = colors ? cloud.colors[candidates[k]][0] : 0;
    q.g = colors ? cloud.colors[candidates[k]][1] : 0;
    q.b = colors ? cloud.colors[candidates[k]][2] : 0;
    q.a = 255;
  }
  out->width = static_cast<std::uint32_t>(out->points.size());
  out->height = 1;
  out->is_dense = true;
  return out;
}

// Segment label per candidate point after LCCP; 0 = the point got no supervoxel.
std::vector<std::uint32_t> pointSegments(const pcl::PointCloud<pcl::PointXYZL>& sv_labels,
                                         const std::map<std::uint32_t, std::uint32_t>& sv_to_seg) {
  std::vector<std::uint32_t> seg(sv_labels.size(), 0);
  for (std::size_t k = 0; k < sv_labels.size(); ++k) {
    const auto it = sv_to_seg.find(sv_labels.points[k].label);
    if (sv_labels.points[k].label != 0 && it != sv_to_seg.end()) seg[k] = it->second + 1;
  }
  return seg;
}

// Points the supervoxels left out (voxels without a seed nearby) join the segment of the nearest
// labelled point within one seed resolution; the rest stay 0.
void adoptOrphans(const pcl::PointCloud<SvPoint>& input, std::vector<std::uint32_t>& seg,
                  double radius_m) {
  std::vector<int> labelled;
  for (std::size_t k = 0; k < seg.size(); ++k) {
    if (seg[k] != 0) labelled.push_back(static_cast<int>(k));
  }
  if (labelled.empty() || labelled.size() == seg.size()) return;
  auto reference = std::make_shared<pcl::PointCloud<SvPoint>>(input, labelled);
  pcl::KdTreeFLANN<SvPoint> tree;
  tree.setInputCloud(reference);
  std::vector<int> nearest(1);
  std::vector<float> distance2(1);
  const std::vector<std::uint32_t> before = seg;
  for (std::size_t k = 0; k < seg.size(); ++k) {
    if (before[k] != 0) continue;
    if (tree.nearestKSearch(input.points[k], 1, nearest, distance2) == 1 &&
        distance2[0] <= radius_m * radius_m) {
      seg[k] = before[labelled[nearest[0]]];
    }
  }
}

}  // namespace

Segmentation euclideanSegments(const PointCloud& cloud, const std::vector<int>& candidates,
                               const SceneParams& params) {
  Segmentation out;
  if (candidates.empty()) return out;
  std::vector<Eigen::Vector3d> points;
  points.reserve(candidates.size());
  for (int i : candidates) points.push_back(cloud.points[i]);
  const auto xyz = toPclXyz(points);
  auto tree = std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
  tree->setInputCloud(xyz);
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> extraction;
  extraction.setClusterTolerance(params.cluster_tolerance_m);
  // Every cluster comes back so that the size limits below can record what they drop.
  extraction.setMinClusterSize(1);
  extraction.setMaxClusterSize(std::numeric_limits<int>::max());
  extraction.setSearchMethod(tree);
  extraction.setInputCloud(xyz);
  std::vector<pcl::PointIndices> found;
  extraction.extract(found);
  std::vector<std::vector<int>> clusters;
  for (const auto& c : found) {
    std::vector<int> members;
    members.reserve(c.indices.size());
    for (auto i : c.indices) members.push_back(candidates[i]);
    clusters.push_back(std::move(members));
  }
  keepBySize(cloud, std::move(clusters), params, out);
  return out;
}

Segmentation lccpSegments(const PointCloud& cloud, const std::vector<int>& candidates,
                          const SceneParams& params, const perception::SupportPlane& plane) {
  Segmentation out;
  if (candidates.empty()) return out;
  const auto& lp = params.lccp;
  const auto input = toSupervoxelInput(cloud, candidates);

  pcl::SupervoxelClustering<SvPoint> supervoxels(static_cast<float>(lp.voxel_resolution_m),
                                                 static_cast<float>(lp.seed_resolution_m));
  // The candidates are an unorganised subset: no single-camera depth transform.
  supervoxels.setUseSingleCameraTransform(false);
  supervoxels.setInputCloud(input);
  supervoxels.setColorImportance(cloud.hasColors() ? static_cast<float>(lp.color_importance) : 0);
  supervoxels.setSpatialImportance(static_cast<float>(lp.spatial_importance));
  supervoxels.setNormalImportance(static_cast<float>(lp.normal_importance));
  std::map<std::uint32_t, pcl::Supervoxel<SvPoint>::Ptr> clusters;
  supervoxels.extract(clusters);
  if (clusters.empty()) {
    out.dropped.push_back(fragment(cloud, candidates, "no_supervoxel"));
    return out;
  }
  std::multimap<std::uint32_t, std::uint32_t> adjacency;
  supervoxels.getSupervoxelAdjacency(adjacency);

  pcl::LCCPSegmentation<SvPoint> lccp;
  lccp.setConcavityToleranceThreshold(static_cast<float>(lp.concavity_tolerance_deg));
  lccp.setSanityCheck(lp.sanity_check);
  lccp.setSmoothnessCheck(lp.smoothness_check, static_cast<float>(lp.voxel_resolution_m),
                          static_cast<float>(lp.seed_resolution_m),
                          static_cast<float>(lp.smoothness_threshold));
  lccp.setKFactor(static_cast<std::uint32_t>(lp.k_factor));
  lccp.setMinSegmentSize(0);  // small segments are handled below, by points, with a record
  lccp.setInputSupervoxels(clusters, adjacency);
  lccp.segment();
  std::map<std::uint32_t, std::uint32_t> sv_to_seg;
  lccp.getSupervoxelToSegmentMap(sv_to_seg);

  std::vector<std::uint32_t> seg = pointSegments(*supervoxels.getLabeledCloud(), sv_to_seg);
  adoptOrphans(*input, seg, lp.seed_resolution_m);

  // Segment members and the number of supervoxel edges between segments.
  std::map<std::uint32_t, std::vector<int>> members;
  std::vector<int> orphans;
  for (std::size_t k = 0; k < seg.size(); ++k) {
    (seg[k] ? members[seg[k]] : orphans).push_back(candidates[k]);
  }
  if (!orphans.empty()) out.dropped.push_back(fragment(cloud, orphans, "no_supervoxel"));
  std::map<std::uint32_t, std::map<std::uint32_t, std::size_t>> edges;
  for (const auto& [a, b] : adjacency) {
    const auto sa = sv_to_seg.find(a), sb = sv_to_seg.find(b);
    if (sa == sv_to_seg.end() || sb == sv_to_seg.end() || sa->second == sb->second) continue;
    ++edges[sa->second + 1][sb->second + 1];
  }

  // The neighbour a segment shares most supervoxel edges with (ties: the larger one); 0 = none.
  auto mostConnected = [&](std::uint32_t label) {
    std::uint32_t target = 0;
    std::size_t target_edges = 0, target_size = 0;
    for (const auto& [neighbour, count] : edges[label]) {
      const auto it = members.find(neighbour);
      if (it == members.end()) continue;
      const std::size_t size = it->second.size();
      if (count > target_edges || (count == target_edges && size > target_size)) {
        target = neighbour;
        target_edges = count;
        target_size = size;
      }
    }
    return target;
  };
  // Moves `small` into `target` (0: drops it with `reason`).
  auto absorb = [&](std::uint32_t small_label, std::uint32_t target, const char* reason) {
    auto small = std::move(members[small_label]);
    members.erase(small_label);
    const auto small_edges = std::move(edges[small_label]);
    edges.erase(small_label);
    for (auto& [label, e] : edges) e.erase(small_label);
    if (target == 0) {
      out.dropped.push_back(fragment(cloud, small, reason));
      return;
    }
    auto& into = members[target];
    into.insert(into.end(), small.begin(), small.end());
    for (const auto& [neighbour, count] : small_edges) {
      if (neighbour == target || !members.count(neighbour)) continue;
      edges[target][neighbour] += count;
      edges[neighbour][target] += count;
    }
    ++out.merged;
  };

  // Small segments, smallest first, join their most connected neighbour; a small segment without
  // neighbours is an isolated fragment and dropped.
  for (;;) {
    std::uint32_t smallest = 0;
    std::size_t smallest_size = std::max(lp.min_segment_points, params.min_cluster_points);
    for (const auto& [label, m] : members) {
      if (m.size() < smallest_size) {
        smallest = label;
        smallest_size = m.size();
      }
    }
    if (smallest == 0) break;
    absorb(smallest, mostConnected(smallest), "isolated_fragment");
  }

  // Parts: a segment that does not reach down to the support and is much smaller than the
  // neighbour it hangs on is a part of it cut off at a concave edge (a mug's handle, a bottle's
  // neck, a noisy box top), not an object of its own. A box stacked on a box is about as large
  // as the one below and stays.
  const double part_lift = params.min_height_m + lp.part_min_lift_m;
  for (bool changed = true; changed;) {
    changed = false;
    std::vector<std::pair<std::size_t, std::uint32_t>> by_size;
    for (const auto& [label, m] : members) by_size.emplace_back(m.size(), label);
    std::sort(by_size.begin(), by_size.end());
    for (const auto& [size, label] : by_size) {
      double lowest = std::numeric_limits<double>::infinity();
      for (int i : members[label]) lowest = std::min(lowest, plane.signedDistance(cloud.points[i]));
      if (lowest <= part_lift) continue;
      const std::uint32_t target = mostConnected(label);
      if (target == 0 || static_cast<double>(size) >=
                             lp.part_max_fraction * static_cast<double>(members[target].size())) {
        continue;
      }
      absorb(label, target, "");
      changed = true;
      break;
    }
  }
  std::vector<std::vector<int>> segments;
  for (auto& [label, m] : members) segments.push_back(std::move(m));
  keepBySize(cloud, std::move(segments), params, out);
  log().debug("scene: {} supervoxels, {} LCCP segments kept, {} merged, {} dropped",
              clusters.size(), out.segments.size(), out.merged, out.dropped.size());
  return out;
}

}  // namespace skelgrasp::internal
