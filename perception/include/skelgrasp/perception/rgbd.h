#pragma once
// Pinhole RGB-D geometry: depth image (+ optional mask, colour) -> points. Camera frame: x right,
// y down, z forward (OpenCV/PCL convention); lengths in metres.
#include <nlohmann/json.hpp>

#include <string>

#include "skelgrasp/common/point_cloud.h"
#include "skelgrasp/common/pose.h"
#include "skelgrasp/perception/image.h"

namespace skelgrasp::perception {

// Plausible ranges of pinhole intrinsics, checked wherever intrinsics are read. Depth cameras have
// a few hundred to a few thousand pixels a side and focal lengths of the same order; the caps leave
// room for any real camera while refusing values that only overflow later (a principal point of
// 1e308 put points at infinity and aborted PCL's kd-tree).
// Largest image side, in pixels (a float depth image this size is 1.6 GB).
constexpr int kMaxImageSidePx = 20000;
// Focal lengths, in pixels.
constexpr double kMinFocalLengthPx = 1;
constexpr double kMaxFocalLengthPx = 1e6;
// The principal point may lie off the image (a crop), by at most this many image sizes.
constexpr double kMaxPrincipalPointOffImages = 1;

struct PinholeIntrinsics {
  double fx = 525.0;  // focal lengths in pixels
  double fy = 525.0;
  double cx = 319.5;  // principal point in pixels (pixel centres at integer coordinates)
  double cy = 239.5;
  int width = 640;
  int height = 480;

  // The nominal Primesense Carmine 1.09 / Kinect v1 depth camera (VGA).
  static PinholeIntrinsics primesense() { return {}; }
  // Throws InvalidArgument naming the first value outside the ranges above.
  void validate() const;
  Eigen::Vector3d backProject(double u, double v, double depth) const {
    return {(u - cx) * depth / fx, (v - cy) * depth / fy, depth};
  }
};

// Reads intrinsics from JSON: {"fx","fy","cx","cy","width","height"}, keys optionally prefixed
// with "_" (the autolab_core .intr files of the GQ-CNN captures). Throws IoError.
PinholeIntrinsics readIntrinsicsJson(const std::string& path);
// The same from a JSON object already read (a capture description's inline "intrinsics"); errors
// name `path`. Width and height must be whole numbers; every value is validated.
PinholeIntrinsics intrinsicsFromJson(const nlohmann::json& j, const std::string& path);

// Reads a camera-to-world transform from text: either an autolab_core RigidTransform (.tf: from
// frame, to frame, translation, three rotation rows) or "x y z qw qx qy qz" on one line. Throws
// IoError.
Pose readTransformText(const std::string& path);

struct DepthConversion {
  double min_depth_m = 0.0;  // pixels outside [min, max] count as missing
  double max_depth_m = 10.0;
};

// Organised cloud (width x height, NaN where the depth is missing, zero, non-finite or out of
// range, or where `mask` is given and zero) in the world frame given by camera_to_world; the
// sensor pose is that transform. Colours are attached when `color` is given (same size).
PointCloud depthToPointCloud(const DepthImage& depth, const PinholeIntrinsics& intrinsics,
                             const Pose& camera_to_world = Pose::Identity(),
                             const MaskImage* mask = nullptr, const Image<Rgb>* color = nullptr,
                             const DepthConversion& conversion = {});

// Removes (sets to 0) pixels whose depth differs by more than `max_jump_m` from the smallest or
// largest depth in the window x window neighbourhood (missing depth counts as 0): the mixed
// foreground/background pixels structured-light sensors produce at silhouettes. The YCB reference
// scripts use a 7 x 7 window and 0.1 m.
DepthImage removeDepthDiscontinuities(const DepthImage& depth, int window = 7,
                                      double max_jump_m = 0.1, std::size_t* removed = nullptr);

}  // namespace skelgrasp::perception
