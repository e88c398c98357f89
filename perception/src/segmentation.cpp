// PCL translation unit: the segmentations of the points above the support, Euclidean clusters and
// supervoxels + LCCP (locally convex connected patches).
#include "skelgrasp/internal/segmentation.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/segmentation/extract_clusters.h>
#include <pcl/segmentation/lccp_segmentation.h>
#include <pcl/segmentation/supervoxel_clustering.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <set>

#include "skelgrasp/common/logging.h"
#include "skelgrasp/geometry/principal_axes.h"
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

// The candidates in a frame whose origin is the sensor: PCL's supervoxels orient every normal
// toward (0, 0, 0) (flipNormalTowardsViewpoint with a fixed origin), and LCCP reads convexity from
// those normals. In a world frame (the demo scene) the origin lies under the table, so surfaces
// facing away from it got inverted normals, convex edges read as concave and objects fell apart
// into faces. A fused scan has one recorded origin: a surface only another view saw, facing away
// from that origin, can still be inverted. A non-finite origin (bad metadata) leaves the frame.
pcl::PointCloud<SvPoint>::Ptr toSupervoxelInput(const PointCloud& cloud,
                                                const std::vector<int>& candidates) {
  auto out = std::make_shared<pcl::PointCloud<SvPoint>>();
  out->points.resize(candidates.size());
  const bool colors = cloud.hasColors();
  const Eigen::Vector3d origin =
      cloud.sensor_origin.allFinite() ? cloud.sensor_origin : Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const Eigen::Vector3d p = cloud.points[candidates[k]] - origin;
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

// A much smaller part rests on its neighbour above this fraction of the neighbour's own height (a
// bottle's neck: 0.97; the demo ball pushed against the bottle, 0.18 of its points: 0.06).
constexpr double kPartRestsAbove = 0.5;

// Two segments are tested as one symmetric body when their boxes come this close: a mug's rim is
// thinner than a supervoxel and the ends of its near and far walls can be centimetres apart.
constexpr double kSymmetricPairReachM = 0.05;

// How a segment stands on the support: its lowest point above the plane, its own height (top
// above its lowest point) and its widest horizontal extent (along the main axis of its points
// projected on the plane). The part rule reads from these whether the segment could stand alone.
struct Stance {
  double lowest_m = 0;
  double height_m = 0;
  double width_m = 0;
};

Stance stanceOf(const PointCloud& cloud, const std::vector<int>& members,
                const perception::SupportPlane& plane) {
  Stance s;
  if (members.empty()) return s;
  std::vector<Eigen::Vector3d> points;
  points.reserve(members.size());
  double top = -std::numeric_limits<double>::infinity();
  s.lowest_m = std::numeric_limits<double>::infinity();
  for (int i : members) {
    const Eigen::Vector3d& p = cloud.points[i];
    const double h = plane.signedDistance(p);
    s.lowest_m = std::min(s.lowest_m, h);
    top = std::max(top, h);
    points.push_back(p);
  }
  s.height_m = top - s.lowest_m;
  s.width_m = geometry::footprintExtents(points, plane.normal).widest_m;
  return s;
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

  // The neighbour a segment shares most supervoxel edges with (ties: the larger one) among those
  // `eligible` accepts; 0 = none.
  const auto any = [](std::uint32_t) { return true; };
  auto mostConnected = [&](std::uint32_t label, const auto& eligible) {
    std::uint32_t target = 0;
    std::size_t target_edges = 0, target_size = 0;
    for (const auto& [neighbour, count] : edges[label]) {
      const auto it = members.find(neighbour);
      if (it == members.end() || !eligible(neighbour)) continue;
      const std::size_t size = it->second.size();
      if (count > target_edges || (count == target_edges && size > target_size)) {
        target = neighbour;
        target_edges = count;
        target_size = size;
      }
    }
    return target;
  };
  // Stances of the current segments, computed once per segment and forgotten when it changes:
  // the part rules below ask for a segment's and its neighbours' stances on every pass.
  std::map<std::uint32_t, Stance> stances;
  auto stanceFor = [&](std::uint32_t label) {
    auto it = stances.find(label);
    if (it == stances.end())
      it = stances.emplace(label, stanceOf(cloud, members[label], plane)).first;
    return it->second;
  };
  // Moves `small` into `target` (0: drops it with `reason`).
  auto absorb = [&](std::uint32_t small_label, std::uint32_t target, const char* reason) {
    auto small = std::move(members[small_label]);
    members.erase(small_label);
    stances.erase(small_label);
    stances.erase(target);
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

  // Small segments, smallest first, join their most connected neighbour. A small segment without
  // neighbours is an object of its own from min_isolated_points on and an isolated fragment,
  // dropped, below that.
  std::set<std::uint32_t> isolated;
  for (;;) {
    std::uint32_t smallest = 0;
    std::size_t smallest_size = std::max(lp.min_segment_points, params.min_cluster_points);
    for (const auto& [label, m] : members) {
      if (m.size() < smallest_size && !isolated.count(label)) {
        smallest = label;
        smallest_size = m.size();
      }
    }
    if (smallest == 0) break;
    const std::uint32_t target = mostConnected(smallest, any);
    if (target == 0 &&
        smallest_size >= std::max(lp.min_isolated_points, params.min_cluster_points)) {
      isolated.insert(smallest);
    } else {
      absorb(smallest, target, "isolated_fragment");
    }
  }

  // Parts: a segment that hangs on a neighbour (its lowest point part_min_lift_m above the
  // neighbour's) and either could not stand on its own (taller than part_max_aspect times its
  // widest horizontal extent: a hammer's handle standing on its head) or is much smaller than
  // that neighbour (part_max_fraction: a bottle's neck) is a part of it cut off at a concave
  // edge, not an object of its own. A box stacked on a box or an object leaning
  // on another is wider than it is tall and not much smaller than what it rests on, and stays.
  for (bool changed = true; changed;) {
    changed = false;
    std::vector<std::pair<std::size_t, std::uint32_t>> by_size;
    for (const auto& [label, m] : members) by_size.emplace_back(m.size(), label);
    std::sort(by_size.begin(), by_size.end());
    for (const auto& [size, label] : by_size) {
      // A part hangs on the neighbour it belongs to: its lowest point is part_min_lift_m above
      // the neighbour's. A flat object lying beside a larger one reaches lower and stays.
      const Stance stance = stanceFor(label);
      const auto hangsOn = [&](std::uint32_t neighbour, double rests_above) {
        const Stance below = stanceFor(neighbour);
        return stance.lowest_m >
               below.lowest_m + std::max(lp.part_min_lift_m, rests_above * below.height_m);
      };
      std::uint32_t target = 0;
      if (stance.height_m > lp.part_max_aspect * stance.width_m) {
        target = mostConnected(label, [&](std::uint32_t n) { return hangsOn(n, 0.0); });
      }
      if (target == 0) {
        // A much smaller part also rests on the upper half of its neighbour (a bottle's neck); a
        // ball pushed against a bottle rests on the table however high its lowest visible point.
        const std::uint32_t below =
            mostConnected(label, [&](std::uint32_t n) { return hangsOn(n, kPartRestsAbove); });
        if (below != 0 && static_cast<double>(size) <
                              lp.part_max_fraction * static_cast<double>(members[below].size())) {
          target = below;
        }
      }
      if (target == 0) continue;
      log().debug(
          "scene: a segment of {} points {:.3f} m up ({:.3f} m tall, {:.3f} m wide) is a "
          "part of its neighbour",
          size, stance.lowest_m, stance.height_m, stance.width_m);
      absorb(label, target, "");
      changed = true;
      break;
    }
  }
  // Symmetric bodies: segments on one circle about an axis normal to the support are one body cut
  // at its rim; the smaller joins the larger. The pieces need not share a supervoxel edge (a thin
  // rim leaves none), only come within kSymmetricPairReachM of each other. A pair found apart
  // stays apart until one of them grows: after a join only the grown segment's pairs are tested.
  std::set<std::pair<std::uint32_t, std::uint32_t>> apart;
  for (bool changed = lp.join_symmetric_bodies; changed;) {
    changed = false;
    std::vector<std::pair<std::uint32_t, AxisAlignedBox>> boxes;
    for (const auto& [label, m] : members) {
      AxisAlignedBox box;
      for (int i : m) box.extend(cloud.points[i]);
      boxes.emplace_back(label, box);
    }
    for (std::size_t i = 0; i < boxes.size() && !changed; ++i) {
      for (std::size_t j = i + 1; j < boxes.size() && !changed; ++j) {
        const AxisAlignedBox& bi = boxes[i].second;
        const AxisAlignedBox& bj = boxes[j].second;
        if (((bi.min.array() - kSymmetricPairReachM) > bj.max.array()).any() ||
            ((bj.min.array() - kSymmetricPairReachM) > bi.max.array()).any())
          continue;
        const std::uint32_t a = boxes[i].first, b = boxes[j].first;
        if (apart.count({a, b})) continue;
        if (!oneSymmetricBody(cloud, members[a], members[b], plane, lp)) {
          apart.insert({a, b});
          continue;
        }
        const bool a_smaller = members[a].size() < members[b].size();
        const std::uint32_t grown = a_smaller ? b : a;
        log().debug("scene: segments of {} and {} points are one symmetric body", members[a].size(),
                    members[b].size());
        absorb(a_smaller ? a : b, grown, "");
        for (auto it = apart.begin(); it != apart.end();)
          it = it->first == grown || it->second == grown ? apart.erase(it) : std::next(it);
        changed = true;
      }
    }
  }
  std::vector<std::vector<int>> segments;
  for (auto& [label, m] : members) segments.push_back(std::move(m));
  out.merged += joinAcrossOccluders(cloud, segments, lp);
  keepBySize(cloud, std::move(segments), params, out);
  log().debug("scene: {} supervoxels, {} LCCP segments kept, {} merged, {} dropped",
              clusters.size(), out.segments.size(), out.merged, out.dropped.size());
  return out;
}

}  // namespace skelgrasp::internal
