#include "skelgrasp/perception/rgbd.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"

namespace skelgrasp::perception {

void PinholeIntrinsics::validate() const {
  auto focal = [](const char* name, double f) {
    if (!(f >= kMinFocalLengthPx && f <= kMaxFocalLengthPx))
      throw InvalidArgument(fmt::format("{} = {:g} is not a focal length in [{:g}, {:g}] pixels",
                                        name, f, kMinFocalLengthPx, kMaxFocalLengthPx));
  };
  auto side = [](const char* name, int n) {
    if (n < 1 || n > kMaxImageSidePx)
      throw InvalidArgument(
          fmt::format("{} = {} is not an image size in [1, {}] pixels", name, n, kMaxImageSidePx));
  };
  auto centre = [](const char* name, double c, int size) {
    const double margin = kMaxPrincipalPointOffImages * size;
    if (!(c >= -margin && c <= size + margin))
      throw InvalidArgument(fmt::format(
          "{} = {:g} puts the principal point more than {:g} image size(s) off the {}-pixel image",
          name, c, kMaxPrincipalPointOffImages, size));
  };
  focal("fx", fx);
  focal("fy", fy);
  side("width", width);
  side("height", height);
  centre("cx", cx, width);
  centre("cy", cy, height);
}

PinholeIntrinsics intrinsicsFromJson(const nlohmann::json& j, const std::string& path) {
  if (!j.is_object()) throw IoError(path, "intrinsics must be a JSON object");
  auto get = [&](const std::string& key) -> double {
    for (const std::string& k : {key, "_" + key}) {
      if (!j.contains(k)) continue;
      if (!j[k].is_number()) throw IoError(path, "intrinsics '" + k + "' is not a number");
      return j[k].get<double>();
    }
    throw IoError(path, "intrinsics lack a numeric '" + key + "'");
  };
  auto size = [&](const std::string& key) -> int {
    const double n = get(key);
    if (!(n >= 1 && n <= kMaxImageSidePx) || n != std::floor(n))
      throw IoError(path, fmt::format("intrinsics {} = {:g} is not a whole number of pixels in "
                                      "[1, {}]",
                                      key, n, kMaxImageSidePx));
    return static_cast<int>(n);
  };
  PinholeIntrinsics k;
  k.fx = get("fx");
  k.fy = get("fy");
  k.cx = get("cx");
  k.cy = get("cy");
  k.width = size("width");
  k.height = size("height");
  try {
    k.validate();
  } catch (const InvalidArgument& e) {
    throw IoError(path, std::string("intrinsics ") + e.what());
  }
  return k;
}

PinholeIntrinsics readIntrinsicsJson(const std::string& path) {
  return intrinsicsFromJson(readJsonFile(path), path);
}

Pose readTransformText(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path, "cannot open for reading");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (line.find_first_not_of(" \t\r") != std::string::npos) lines.push_back(line);
  }
  if (lines.size() == 1) {
    try {
      return parsePose(lines[0]);
    } catch (const InvalidArgument& e) {
      throw IoError(path, e.what());
    }
  }
  // autolab_core RigidTransform: from frame, to frame, translation, rotation rows.
  if (lines.size() != 6) {
    throw IoError(path,
                  "expected 'x y z qw qx qy qz' or an autolab .tf (from, to, translation, three "
                  "rotation rows), found " +
                      std::to_string(lines.size()) + " lines");
  }
  auto row = [&](int index) {
    std::istringstream s(lines[index]);
    Eigen::Vector3d v;
    std::string extra;
    if (!(s >> v.x() >> v.y() >> v.z()) || (s >> extra) || !v.allFinite()) {
      throw IoError(path, "line " + std::to_string(index + 1) + ": expected three numbers");
    }
    return v;
  };
  Pose pose = Pose::Identity();
  pose.translation() = row(2);
  Eigen::Matrix3d r;
  for (int i = 0; i < 3; ++i) r.row(i) = row(3 + i).transpose();
  if ((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() > 1e-3 || r.determinant() < 0) {
    throw IoError(path, "rotation rows are not a proper rotation matrix");
  }
  // Re-orthonormalise the 6-digit text values.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  pose.linear() = svd.matrixU() * svd.matrixV().transpose();
  return pose;
}

PointCloud depthToPointCloud(const DepthImage& depth, const PinholeIntrinsics& intrinsics,
                             const Pose& camera_to_world, const MaskImage* mask,
                             const Image<Rgb>* color, const DepthConversion& conversion) {
  intrinsics.validate();
  if (depth.width != intrinsics.width || depth.height != intrinsics.height) {
    throw InvalidArgument("depth image is " + std::to_string(depth.width) + "x" +
                          std::to_string(depth.height) + " but the intrinsics say " +
                          std::to_string(intrinsics.width) + "x" +
                          std::to_string(intrinsics.height));
  }
  if (mask && (mask->width != depth.width || mask->height != depth.height)) {
    throw InvalidArgument("mask and depth image sizes differ");
  }
  if (color && (color->width != depth.width || color->height != depth.height)) {
    throw InvalidArgument("colour and depth image sizes differ");
  }
  PointCloud cloud;
  cloud.width = static_cast<std::uint32_t>(depth.width);
  cloud.height = static_cast<std::uint32_t>(depth.height);
  cloud.points.resize(depth.data.size());
  if (color) cloud.colors.resize(depth.data.size());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int v = 0; v < depth.height; ++v) {
    for (int u = 0; u < depth.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * depth.width + u;
      const double z = depth.data[i];
      const bool valid = std::isfinite(z) && z > 0 && z >= conversion.min_depth_m &&
                         z <= conversion.max_depth_m && (!mask || mask->data[i] != 0);
      cloud.points[i] = valid ? Eigen::Vector3d(camera_to_world * intrinsics.backProject(u, v, z))
                              : Eigen::Vector3d::Constant(nan);
      if (color) cloud.colors[i] = color->data[i];
    }
  }
  cloud.sensor_origin = camera_to_world.translation();
  cloud.sensor_orientation = Eigen::Quaterniond(camera_to_world.linear()).normalized();
  return cloud;
}

}  // namespace skelgrasp::perception
