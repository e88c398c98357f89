#include "skelgrasp/perception/cloud_ops.h"

namespace skelgrasp::perception {

PointCloud subset(const PointCloud& cloud, const std::vector<int>& indices) {
  PointCloud out;
  out.sensor_origin = cloud.sensor_origin;
  out.sensor_orientation = cloud.sensor_orientation;
  out.points.reserve(indices.size());
  for (int i : indices) out.points.push_back(cloud.points[i]);
  if (cloud.hasNormals()) {
    out.normals.reserve(indices.size());
    for (int i : indices) out.normals.push_back(cloud.normals[i]);
  }
  if (cloud.hasColors()) {
    out.colors.reserve(indices.size());
    for (int i : indices) out.colors.push_back(cloud.colors[i]);
  }
  if (cloud.hasLabels()) {
    out.labels.reserve(indices.size());
    for (int i : indices) out.labels.push_back(cloud.labels[i]);
  }
  return out;
}

void append(PointCloud& cloud, const PointCloud& more) {
  if (cloud.empty()) {
    cloud = more;
    cloud.width = cloud.height = 0;
    return;
  }
  const bool normals = cloud.hasNormals() && more.hasNormals();
  const bool colors = cloud.hasColors() && more.hasColors();
  const bool labels = cloud.hasLabels() && more.hasLabels();
  cloud.points.insert(cloud.points.end(), more.points.begin(), more.points.end());
  if (normals) {
    cloud.normals.insert(cloud.normals.end(), more.normals.begin(), more.normals.end());
  } else {
    cloud.normals.clear();
  }
  if (colors) {
    cloud.colors.insert(cloud.colors.end(), more.colors.begin(), more.colors.end());
  } else {
    cloud.colors.clear();
  }
  if (labels) {
    cloud.labels.insert(cloud.labels.end(), more.labels.begin(), more.labels.end());
  } else {
    cloud.labels.clear();
  }
  cloud.width = cloud.height = 0;
}

PointCloud transformed(const PointCloud& cloud, const Pose& pose) {
  PointCloud out = cloud;
  for (auto& p : out.points) p = pose * p;
  for (auto& n : out.normals) n = pose.linear() * n;
  out.sensor_origin = pose * cloud.sensor_origin;
  out.sensor_orientation = Eigen::Quaterniond(pose.linear()) * cloud.sensor_orientation;
  out.sensor_orientation.normalize();
  return out;
}

std::size_t countFinite(const PointCloud& cloud) {
  std::size_t n = 0;
  for (const auto& p : cloud.points) n += p.allFinite() ? 1 : 0;
  return n;
}

}  // namespace skelgrasp::perception
