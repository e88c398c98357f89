#pragma once
// Point cloud filters (PCL) and normal estimation. Lengths in metres.
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/point_cloud.h"

namespace skelgrasp::perception {

struct FilterParams {
  // Keep only points inside this box (cloud frame). Off by default.
  std::optional<AxisAlignedBox> crop_box;
  // Voxel-grid downsampling leaf (centroid of each occupied voxel; normals and colours averaged,
  // labels taken from the nearest input point); 0 = off. 3 mm keeps the shape of household objects
  // at Primesense resolution while cutting a 640x480 scene to tens of thousands of points.
  double voxel_leaf_m = 0.003;
  // Statistical outlier removal: a point goes when its mean distance to its `sor_mean_k` nearest
  // neighbours exceeds the global mean by `sor_stddev_mul` standard deviations; mean_k 0 = off.
  int sor_mean_k = 20;
  double sor_stddev_mul = 2.0;
};

struct FilterStep {
  std::string name;  // "non_finite", "crop_box", "voxel_grid", "outlier_removal"
  std::size_t points_in = 0;
  std::size_t points_out = 0;
  double time_s = 0;
};

struct FilterResult {
  Status status;     // kInvalidInput: empty or all-NaN input; kNoResult: nothing left after filters
  PointCloud cloud;  // unorganised
  std::vector<FilterStep> steps;
  double time_s = 0;
};

// NaN removal always runs first; then crop box, voxel grid, outlier removal (each when on).
// Throws InvalidArgument for negative sizes.
FilterResult filterCloud(const PointCloud& cloud, const FilterParams& params = {});

struct NormalParams {
  // Neighbourhood for the PCA normal: all points within `radius_m` (used when k == 0), else the
  // k nearest. 1 cm spans about three voxels of the default grid on each side.
  double radius_m = 0.01;
  int k = 0;
  // OpenMP threads for PCL's NormalEstimationOMP; 0 = all cores. One by default: the pipeline runs
  // beside other work (tests in parallel, a second engineer's build) where OpenMP only contends.
  int threads = 1;
};

struct NormalResult {
  Status status;
  PointCloud cloud;                // input points that got a normal, normals towards the sensor
  std::size_t dropped_points = 0;  // too few neighbours for a normal
  double time_s = 0;
};

// Normals oriented towards cloud.sensor_origin (PCL's viewpoint flip). Throws InvalidArgument for
// a non-positive radius with k == 0.
NormalResult estimateNormals(const PointCloud& cloud, const NormalParams& params = {});

// Several views of one object, each with its own sensor pose, in a common frame: normals are
// estimated per view (so each faces its own sensor) and the views are concatenated. The result's
// sensor_origin is the mean of the views' origins; colours and labels are kept when every view has
// them.
PointCloud fuseViews(const std::vector<PointCloud>& views, const NormalParams& params = {});

}  // namespace skelgrasp::perception
