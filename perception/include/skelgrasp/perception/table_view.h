#pragma once
// One object alone on a table, seen by the simulated depth camera (depth_camera.h) from a few
// single viewpoints: the input of the scan-to-grasp benchmark (`skelgrasp bench scan2grasp`,
// docs/scan2grasp.md), where the object's true mesh is known. The object rests on the table in a
// seeded, statically stable pose; each view is a separate scan in its own sensor frame, as a real
// camera delivers it, with the transform that maps that frame back to the mesh's own frame.
// Lengths in metres, angles in radians.
#include <cstdint>
#include <vector>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/mesh.h"
#include "skelgrasp/common/pose.h"
#include "skelgrasp/perception/depth_camera.h"
#include "skelgrasp/perception/scan.h"

namespace skelgrasp::perception {

struct TableViewParams {
  // Single views per object, each from its own seeded viewpoint (azimuths spread evenly from a
  // seeded start, so two views see opposite sides).
  int views = 2;
  // Camera distance to the object's bounding-box centre, drawn uniformly per view: a Kinect-like
  // sensor on a robot's head, 0.7-0.9 m from a table-top object.
  double min_distance_m = 0.7;
  double max_distance_m = 0.9;
  // Camera elevation above the table plane (looking down at the object), drawn uniformly per view.
  double min_elevation_rad = 0.6108652381980153;  // 35 degrees
  double max_elevation_rad = 0.8726646259971648;  // 50 degrees
  // The table: a box of this size whose top is the plane z = 0 of the world frame, the object at
  // its centre.
  double table_length_m = 1.2;
  double table_width_m = 0.8;
  double table_thickness_m = 0.04;
  // The sensor: Primesense VGA (640 x 480, fx = fy = 525) with its error model; the noise seed of
  // view v is derived from `seed` and v (the camera's own noise.seed is ignored).
  DepthCameraParams camera;
  // Multiplies the axial noise terms (1: the documented model; 0.25: a quarter of the noise).
  double noise_scale = 1.0;
  // Points lower than this along a candidate "down" direction belong to the face the object rests
  // on (the support polygon whose hull must hold the centre of mass).
  double support_tolerance_m = 0.002;
  std::uint64_t seed = 1;
  // Throws InvalidArgument for views < 1, ranges that are empty or outside (0, pi/2), non-positive
  // sizes, a negative noise scale or tolerance.
  void validate() const;
};

// How the object rests on the table.
struct RestingPose {
  Pose world_from_object = Pose::Identity();  // the mesh's frame to the world (table top z = 0)
  Eigen::Vector3d down_in_object = -Eigen::Vector3d::UnitZ();  // the mesh's axis facing the table
  // The mesh's own -z when that is statically stable (YCB meshes are stored resting on z = 0),
  // else the stable principal-axis direction with the lowest centre of mass; false when no
  // candidate was stable (the mesh's -z is used anyway).
  bool stable = true;
  bool own_orientation = true;  // the mesh's -z was used
  Eigen::Vector3d centre_of_mass_world = Eigen::Vector3d::Zero();
  double yaw_rad = 0;  // seeded turn about the vertical
};

struct TableView {
  Pose world_from_camera = Pose::Identity();
  double distance_m = 0, elevation_rad = 0, azimuth_rad = 0;
  std::uint64_t noise_seed = 0;
  // The organised depth image as a cloud in the camera's frame (x right, y down, z forward; NaN
  // where no depth), sensor origin at 0: what `run` receives from a real camera.
  Scan scan;
  // Maps poses and points of the scan's frame into the mesh's own frame.
  Pose object_from_scan = Pose::Identity();
  std::size_t object_pixels = 0;   // measured pixels on the object
  std::size_t table_pixels = 0;    // measured pixels on the table
  std::size_t dropped_pixels = 0;  // removed by the error model
};

struct TableViews {
  Status status;  // kInvalidInput for an empty mesh; kNoResult when a view sees no object pixel
  RestingPose rest;
  TriangleMesh table;   // world frame
  TriangleMesh object;  // world frame
  std::vector<TableView> views;
};

// Places `object` (its own frame, metres) on the table and renders params.views single views.
// Deterministic for params.seed. Throws InvalidArgument for bad parameters.
TableViews renderTableViews(const TriangleMesh& object, const TableViewParams& params = {});

// The resting pose alone (renderTableViews' first step): the support polygon of the lowest points
// along a candidate down direction must hold the projection of the centre of mass.
RestingPose restingPose(const TriangleMesh& object, const TableViewParams& params = {});

// The centre of mass of a closed mesh of uniform density (signed tetrahedra); for a mesh without
// volume, the area-weighted surface centroid.
Eigen::Vector3d centreOfMass(const TriangleMesh& mesh);

}  // namespace skelgrasp::perception
