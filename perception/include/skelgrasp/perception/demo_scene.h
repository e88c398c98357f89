#pragma once
// The demo's table scene, made in code and scanned by the simulated depth camera: the embedded
// default input of `skelgrasp demo`, and a scene with known ground truth for tests.
#include <cstdint>
#include <string>
#include <vector>

#include "skelgrasp/common/point_cloud.h"
#include "skelgrasp/common/pose.h"

namespace skelgrasp::perception {

struct DemoScene {
  std::vector<TriangleMesh> meshes;  // world frame; 0 = the table (its top at z = 0), then objects
  std::vector<std::string> names;    // parallel to meshes: "table", "bottle", "mug", ...
  std::vector<Eigen::Vector3d> centres;  // parallel: bounding-box centres (targets for nearest:)
  PointCloud cloud;                      // the views fused (NaNs removed), per-view normals, sensor
                                         // origin = the first camera
  std::vector<Pose> cameras;             // camera-to-world of each view
};

// Moves one object of the demo scene: its bounding-box centre goes to (x, y) on the table (metres,
// world frame), e.g. to push two objects into contact.
struct DemoPlacement {
  std::string name;  // "bottle", "mug", "box", "hammer" or "ball"
  double x = 0, y = 0;
};

// A 1.2 x 0.8 m table with a bottle (with a neck), a mug (with a handle), a box, a hammer-like T
// standing on its head and a ball, seen by `views` Primesense-like cameras from the front half (50
// degrees elevation, 0.85 m from the table centre), with the sensor error model seeded by `seed`.
// `moved` overrides the default positions (unknown names throw InvalidArgument).
DemoScene makeDemoScene(std::uint64_t seed = 1, int views = 3,
                        const std::vector<DemoPlacement>& moved = {});

}  // namespace skelgrasp::perception
