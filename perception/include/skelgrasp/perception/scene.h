#pragma once
// Table-top scene parsing: the dominant support plane (RANSAC), the objects above it (segments of
// the points inside the prism over the plane's convex hull: supervoxels + LCCP, or Euclidean
// clusters), the chosen target(s) and the rest of the scene. Lengths in metres, in the cloud's
// frame.
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/point_cloud.h"

namespace skelgrasp::perception {

enum class PlaneRequirement {
  kRequired,  // no plane found -> status kNoResult
  kOptional,  // use it when found, else cluster the whole cloud
  kNone,      // do not look for one (single-object clouds)
};
PlaneRequirement parsePlaneRequirement(const std::string& text);  // required | optional | none
const char* toString(PlaneRequirement requirement);

enum class TargetMode { kLargest, kAll, kNearest, kIndex };

// How the points above the support are split into objects.
enum class SegmentationMethod {
  // Connected components at cluster_tolerance_m: fast, but touching objects stay one cluster.
  kEuclidean,
  // Supervoxels, then locally convex connected patches (LCCP, Stein et al., CVPR 2014): objects
  // that touch meet at a concave edge and are cut there (stacked boxes, a can against a box).
  kLccp,
};
SegmentationMethod parseSegmentationMethod(const std::string& text);  // lccp | euclidean
const char* toString(SegmentationMethod method);

// Supervoxel + LCCP parameters (PCL's SupervoxelClustering and LCCPSegmentation). The defaults
// were chosen over the eight labelled mOSD scans with `skelgrasp bench segment` (one setting for
// all scenes; docs/reconstruction.md has the sweep).
struct LccpParams {
  // Octree leaf of the supervoxels and the spacing of their seeds.
  double voxel_resolution_m = 0.006;
  double seed_resolution_m = 0.03;
  // Weights of the supervoxel distance; colour counts only when the cloud has colours.
  double color_importance = 0.2;
  double spatial_importance = 0.4;
  double normal_importance = 1.0;
  // Two adjacent supervoxels join when their connection is convex or concave by less than this.
  double concavity_tolerance_deg = 27.0;
  // LCCP's sanity criterion (singular connections are not convex) and smoothness check (a step
  // between supervoxels with parallel normals is a cut); threshold as in PCL (fudge factor).
  bool sanity_check = true;
  bool smoothness_check = true;
  double smoothness_threshold = 0.1;
  // Extended convexity: an edge is convex only when k of its neighbours' edges agree (0 = off).
  int k_factor = 0;
  // Segments with fewer points are fragments (an object's face cut off at a concave edge, a rim, a
  // mug's handle): merged into the adjacent segment they share most supervoxel edges with. 500
  // folds the demo mug's handle (about 380 points from three views) into the mug; the smallest
  // object segment in the eight mOSD scans has 616 points, and their scores are the same as at 200.
  std::size_t min_segment_points = 500;
  // A segment below min_segment_points with no adjacent segment is an object of its own from this
  // many points on, and an isolated fragment (dropped and recorded) below.
  std::size_t min_isolated_points = 200;
  // Parts (docs/reconstruction.md): a segment whose lowest point is more than part_min_lift_m
  // above that of a neighbour is merged into the one it shares most edges with when it could not
  // stand on its own there (its own height over its widest horizontal extent above
  // part_max_aspect: a hammer's handle standing on its head; the tallest lifted object in the
  // eight mOSD scans is 2.4 times as tall as it is wide), or when it rests on that neighbour's
  // upper half and has fewer than part_max_fraction of its points (a bottle's neck; at 0.35 this
  // merged objects lying on others in mOSD 46 and 50, whose fractions are 0.27-0.32).
  double part_min_lift_m = 0.015;
  double part_max_aspect = 3.0;
  double part_max_fraction = 0.2;
  // Hidden gaps (docs/reconstruction.md): two segments are one object seen in pieces around an
  // occluder when every point of the gap between their closest points, sampled every
  // hidden_gap_step_m, lies behind another segment (a point of it within
  // hidden_gap_ray_radius_rad of the viewing ray, nearer to the sensor by hidden_gap_min_depth_m;
  // 0.01 rad is about three 3 mm voxels at 1 m), the gap is at most hidden_gap_max_m, and, in
  // clouds with colours, their mean colours differ by at most hidden_gap_max_colour_distance
  // (Euclidean, 0-255 RGB). The sensor must be at the cloud's sensor origin (single views).
  bool join_hidden_gaps = true;
  double hidden_gap_max_m = 0.15;
  double hidden_gap_step_m = 0.005;
  double hidden_gap_ray_radius_rad = 0.01;
  double hidden_gap_min_depth_m = 0.01;
  double hidden_gap_max_colour_distance = 25.0;
  // Symmetric bodies (docs/perception.md): two adjacent segments are one rotationally symmetric
  // body cut at its rim (a mug's near wall outside and far wall inside) when, projected on the
  // support, one circle of radius symmetric_min_radius_m to symmetric_max_radius_m carries at
  // least symmetric_min_ring_fraction of the points of each (within symmetric_ring_tolerance
  // times the radius) and together they cover symmetric_min_coverage of its circumference.
  bool join_symmetric_bodies = true;
  double symmetric_min_radius_m = 0.015;
  double symmetric_max_radius_m = 0.15;
  double symmetric_ring_tolerance = 0.12;
  double symmetric_min_ring_fraction = 0.5;
  double symmetric_min_coverage = 0.75;
};

struct TargetSpec {
  TargetMode mode = TargetMode::kLargest;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // kNearest: cluster centroid nearest to this
  // kIndex: the object with this index in the scene's object list (sorted by point count, largest
  // first: index 0 is "largest"), the numbering `run --object all` and the reports use.
  std::size_t index = 0;

  // "largest" | "all" | "nearest:x,y,z" (metres, cloud frame) | "index:k" (k >= 0). Throws
  // InvalidArgument.
  static TargetSpec parse(const std::string& text);
  std::string toString() const;
};

struct SceneParams {
  PlaneRequirement plane = PlaneRequirement::kRequired;
  // RANSAC inlier distance; PCL's RANSAC is deterministic (fixed seed 12345). 1 cm absorbs the
  // axial noise of Primesense-class sensors at 1-1.5 m.
  double plane_distance_m = 0.01;
  int plane_max_iterations = 1000;
  // A plane must hold at least this fraction of the points (after filtering) to count as a
  // support candidate; smaller planes are object faces.
  double min_plane_fraction = 0.1;
  // Up to this many planes are extracted one after the other (each from the points the previous
  // ones left); those holding at least `plane_candidate_ratio` of the largest one's inliers compete
  // and the one nearest to the sensor is the support. Scenes often show the floor behind the table
  // with more points than the table (the PCL mug scene does); a big box top is much smaller than
  // the table it stands on (mOSD scene 58: 0.28 of it).
  int plane_candidates = 3;
  double plane_candidate_ratio = 0.5;
  // A candidate counts only when this share of its inliers lies within half the inlier distance.
  // Measured: tables and boards 0.93-0.995 (mOSD, PCL scenes, Primesense captures), the bands
  // RANSAC finds around cans and balls 0.47-0.61.
  double min_plane_flatness = 0.8;
  // Objects: points between these heights above the plane (towards the sensor)...
  double min_height_m = 0.01;
  double max_height_m = 0.5;
  // ...and, when set, inside the prism over the convex hull of the plane's inliers, grown by
  // plane_hull_margin_m. The visible table ends where objects at its edge hide it: in mOSD scan 58
  // a whole object (6 000 points) and half of its neighbour stand up to ~10 cm outside the hull of
  // the table points. 0.10 m brought LCCP's recall over the eight mOSD scans from 0.896 to 0.935
  // (scan 58: 0.828 to 0.929) and precision from 0.969 to 0.992 (docs/reconstruction.md).
  bool restrict_to_plane_hull = true;
  double plane_hull_margin_m = 0.10;
  // With an object mask the mask decides what is object; only mask pixels that bled onto the
  // support (closer to the plane than this) are dropped. Lower than min_height_m so that flat
  // objects (a bag clip lying down) keep their points.
  double masked_min_height_m = 0.003;
  // Segmentation of the points above the support (a mask or no plane: always Euclidean, the
  // mask says what belongs together and without a support there is nothing to stand on). LCCP is
  // the default: over the eight labelled mOSD scans it finds every scene's objects within one
  // (precision 0.992, recall 0.960; Euclidean: 0.641 at about the same recall, touching objects
  // welded), and the symmetric-body rule joins the mugs of the PCL and GPD scans that it would
  // cut at the rim. docs/perception.md has the measurements.
  SegmentationMethod segmentation = SegmentationMethod::kLccp;
  LccpParams lccp;
  // Euclidean clustering: points closer than the tolerance join a cluster. Over the mOSD scenes
  // 1 cm scored best (precision 0.665 vs 0.617 at 1.5 cm, recall 0.921 for both); below it objects
  // with dropouts fall apart. Touching objects stay merged whatever the tolerance.
  double cluster_tolerance_m = 0.01;
  // Objects have at least this many points; smaller clusters are dropped (LCCP: see also
  // lccp.min_segment_points). Every drop is recorded in SceneResult::dropped.
  std::size_t min_cluster_points = 50;
  std::size_t max_cluster_points = 0;  // 0 = unlimited (larger clusters are dropped, recorded)
  TargetSpec target;
};

struct SupportPlane {
  // n.x + d = 0 with |n| = 1 and n pointing towards the sensor ("up" for a table seen from above).
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double d = 0;
  std::size_t inliers = 0;
  double signedDistance(const Eigen::Vector3d& p) const { return normal.dot(p) + d; }
};

struct ClusterInfo {
  std::size_t points = 0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  AxisAlignedBox box;                                // cloud frame
  Eigen::Vector3d extent = Eigen::Vector3d::Zero();  // PCA-aligned box edge lengths, descending
  double height_above_plane_m = 0;                   // highest point above the plane (0 if none)
  bool selected = false;
};

ClusterInfo describeCluster(const PointCloud& cluster, const std::optional<SupportPlane>& plane);

// A group of points above the support that did not become an object, and why.
struct DroppedFragment {
  std::size_t points = 0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  std::string reason;  // e.g. "below_min_points", "above_max_points", "isolated_fragment"
};

struct SceneResult {
  Status status;  // kNoResult: no plane (when required), no object above the plane
  std::optional<SupportPlane> plane;
  PointCloud plane_points;                // RANSAC inliers
  std::vector<PointCloud> clusters;       // every cluster, largest first
  std::vector<ClusterInfo> cluster_info;  // parallel to clusters
  std::vector<std::size_t> selected;      // indices into clusters, per the target spec
  // Everything that is neither a plane inlier nor in a selected cluster: other objects, clutter,
  // points below or beside the table (what a collision model of the scene needs besides the plane).
  PointCloud other_points;
  // The part of other_points in no cluster at all: clutter, fragments too small to be objects,
  // points beside or below the table (the rest of other_points are the unselected clusters).
  PointCloud loose_points;
  std::vector<DroppedFragment> dropped;  // candidate points that became no object, with reasons
  std::size_t merged_fragments = 0;      // small LCCP segments merged into a neighbour
  SegmentationMethod segmentation = SegmentationMethod::kEuclidean;  // the method that ran
  std::size_t candidate_points = 0;                                  // points that were clustered
  double plane_time_s = 0;
  double cluster_time_s = 0;
};

// `object_mask` (empty or one per point, nonzero = known object point, e.g. from a segmentation
// mask): the plane is fitted to the other points and is always optional; the object is the mask
// points above it, as one cluster made of every mask cluster of at least min_cluster_points (the
// mask says they belong together; smaller ones are mask bleed and sensor debris). Throws
// InvalidArgument for bad parameters or a mask of the wrong size.
SceneResult parseScene(const PointCloud& cloud, const SceneParams& params = {},
                       const std::vector<std::uint8_t>& object_mask = {});

}  // namespace skelgrasp::perception
