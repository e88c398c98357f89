#pragma once
// Simulated depth camera: renders triangle meshes from a pinhole camera by z-buffer rasterisation,
// then applies a seeded Primesense-like error model. A test tool (scan any mesh from known poses)
// and the demo's sensor. Lengths in metres, angles in radians.
#include <cstdint>
#include <vector>

#include "skelgrasp/common/mesh.h"
#include "skelgrasp/common/point_cloud.h"
#include "skelgrasp/common/pose.h"
#include "skelgrasp/perception/image.h"
#include "skelgrasp/perception/rgbd.h"

namespace skelgrasp::perception {

// Error model of a structured-light sensor (Primesense Carmine / Kinect v1). Defaults follow the
// published characterisations: axial noise of Nguyen, Izadi & Lovell (3DIMPVT 2012),
// sigma_z = 0.0012 + 0.0019 (z - 0.4)^2 + 0.0001 / sqrt(z) * theta^2 / (pi/2 - theta)^2 metres
// for depth z and incidence angle theta; disparity quantised to 1/8 pixel with a 7.5 cm baseline
// (Khoshelham & Elberink 2012: a depth step of about 3 mm at 1 m).
struct DepthNoiseParams {
  bool enabled = true;
  double axial_sigma_base_m = 0.0012;
  double axial_sigma_quadratic = 0.0019;  // per m^2, around axial_sigma_z0_m
  double axial_sigma_z0_m = 0.4;
  double axial_sigma_angle = 0.0001;  // incidence-angle term
  // Disparity quantisation: depth = f * baseline / disparity, disparity rounded to this step in
  // pixels; 0 = off.
  double disparity_step_px = 0.125;
  double baseline_m = 0.075;
  // Missing pixels: surfaces seen at more than `grazing_start_rad` from the view ray start to drop
  // out, linearly up to always at `grazing_max_rad`.
  double grazing_start_rad = 1.22;  // 70 degrees
  double grazing_max_rad = 1.48;    // 85 degrees
  // Depth edges (a 4-neighbour farther by more than edge_jump_fraction * depth): dropped with
  // this probability, as the matcher fails there.
  double edge_jump_fraction = 0.02;
  double edge_dropout_probability = 0.5;
  // Projector shadow: points the projector (baseline_m along the camera's +x) cannot see have no
  // depth, the characteristic band left of objects in Primesense images.
  bool projector_shadow = true;
  double random_dropout_probability = 0.005;
  std::uint64_t seed = 1;
};

struct DepthCameraParams {
  PinholeIntrinsics intrinsics = PinholeIntrinsics::primesense();
  double min_range_m = 0.35;  // Primesense working range
  double max_range_m = 3.5;
  DepthNoiseParams noise;
};

struct DepthView {
  DepthImage depth;   // metres along the optical axis; NaN = no measurement
  LabelImage labels;  // index into the scene's meshes hit at each pixel (before dropouts), -1 none
  PointCloud cloud;   // organised, world frame, sensor pose = camera_to_world; NaN where missing
  std::vector<std::uint32_t> point_labels;  // parallel to cloud.points: mesh index, or UINT32_MAX
  std::size_t valid_pixels = 0;
  std::size_t dropped_pixels = 0;  // hit a surface but removed by the error model
};

// Camera looking from `eye` at `target` with the image's up as close to `up` as possible
// (camera z towards the target, x right, y down).
Pose lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
            const Eigen::Vector3d& up = Eigen::Vector3d::UnitZ());

// Renders the scene (meshes in world coordinates; faces may have any winding) from
// camera_to_world. Throws InvalidArgument for bad intrinsics or ranges.
DepthView renderDepth(const std::vector<TriangleMesh>& scene, const Pose& camera_to_world,
                      const DepthCameraParams& params = {});

// Cameras on a circle of `radius` around `target` at `elevation_rad` above the horizontal plane
// through it (z up), `count` views evenly spread in azimuth from `azimuth0_rad`.
std::vector<Pose> orbitPoses(const Eigen::Vector3d& target, double radius, double elevation_rad,
                             int count, double azimuth0_rad = 0.0);

}  // namespace skelgrasp::perception
