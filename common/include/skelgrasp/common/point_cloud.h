#pragma once
// Thin point-cloud type shared across modules. Coordinates in metres, in the frame named by the
// producer (usually the sensor's or the scan's frame).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

#include "skelgrasp/common/mesh.h"

namespace skelgrasp {

struct PointCloud {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> normals;  // empty, or one unit normal per point
  std::vector<Rgb> colors;               // empty, or one per point
  std::vector<std::uint32_t> labels;     // empty, or one per point
  // Where the sensor was, in the cloud's frame (from the PCD VIEWPOINT field or capture pose).
  Eigen::Vector3d sensor_origin = Eigen::Vector3d::Zero();
  Eigen::Quaterniond sensor_orientation = Eigen::Quaterniond::Identity();
  // Organised clouds (one point per image pixel, row-major, NaN for pixels without depth) carry
  // the image size; 0 x 0 means unorganised. Any filter that drops points makes a cloud
  // unorganised.
  std::uint32_t width = 0;
  std::uint32_t height = 0;

  std::size_t size() const { return points.size(); }
  bool empty() const { return points.empty(); }
  bool hasNormals() const { return !normals.empty() && normals.size() == points.size(); }
  bool hasColors() const { return !colors.empty() && colors.size() == points.size(); }
  bool hasLabels() const { return !labels.empty() && labels.size() == points.size(); }
  bool isOrganized() const {
    return width > 0 && height > 0 && std::size_t{width} * height == points.size();
  }
  AxisAlignedBox bounds() const { return boundingBox(points); }
};

}  // namespace skelgrasp
