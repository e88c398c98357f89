#pragma once
// A scan as the pipeline consumes it, and the single-view RGB-D "capture description".
#include <string>
#include <vector>

#include "skelgrasp/common/point_cloud.h"
#include "skelgrasp/perception/cloud_io.h"
#include "skelgrasp/perception/rgbd.h"

namespace skelgrasp::perception {

struct Scan {
  PointCloud cloud;  // metres
  // Empty, or one per point: nonzero = the point belongs to the object (a segmentation mask came
  // with the data), zero = scene (support, clutter).
  std::vector<std::uint8_t> object_mask;
  // True when cloud.normals were estimated view by view (fused multi-view data): the pipeline then
  // keeps them instead of orienting new normals towards one sensor origin.
  bool per_view_normals = false;
  std::size_t views = 1;
  std::string source;  // file or folder it came from
};

// Capture description: a JSON file naming the pieces of one RGB-D view (paths relative to the
// file), documented in docs/reconstruction.md:
//   {"depth": "depth_0.npy", "depth_scale": 1.0, "mask": "segmask_0.png", "color": "color_0.png",
//    "intrinsics": "calib/primesense.intr" | {"fx": .., "fy": .., "cx": .., "cy": ..,
//                                            "width": .., "height": ..},
//    "camera_to_world": "calib/primesense.tf" | "x y z qw qx qy qz",
//    "min_depth_m": 0.2, "max_depth_m": 3.0}
struct CaptureDescription {
  std::string path;
  std::string depth;
  double depth_scale = 1.0;  // metres per stored unit (default 1 for .npy, 0.001 for .png)
  std::string mask;          // optional
  std::string color;         // optional
  PinholeIntrinsics intrinsics;
  Pose camera_to_world = Pose::Identity();
  DepthConversion conversion;
};

// Parses and validates the description (referenced files must exist). Throws IoError naming the
// description or the referenced file.
CaptureDescription readCaptureDescription(const std::string& path);

// Loads the view: the whole depth image becomes the cloud (world frame), the mask the object mask.
// Unit sanity as for clouds. Throws IoError.
Scan loadCapture(const std::string& path, const CloudLoadOptions& options = {});

}  // namespace skelgrasp::perception
