// PCL translation unit: conversions between skelgrasp::PointCloud and PCL clouds and blobs.
#include "skelgrasp/internal/pcl_conversions.h"

#include <pcl/common/io.h>
#include <pcl/conversions.h>

#include <algorithm>

namespace skelgrasp::internal {
namespace {

bool hasField(const pcl::PCLPointCloud2& blob, const std::string& name) {
  return std::any_of(blob.fields.begin(), blob.fields.end(),
                     [&](const pcl::PCLPointField& f) { return f.name == name; });
}

void setSensorPose(const PointCloud& from, Eigen::Vector4f& origin,
                   Eigen::Quaternionf& orientation) {
  origin = Eigen::Vector4f(static_cast<float>(from.sensor_origin.x()),
                           static_cast<float>(from.sensor_origin.y()),
                           static_cast<float>(from.sensor_origin.z()), 0.0f);
  orientation = from.sensor_orientation.cast<float>();
}

}  // namespace

PclCloud::Ptr toPcl(const PointCloud& cloud) {
  auto out = std::make_shared<PclCloud>();
  out->points.resize(cloud.size());
  const bool normals = cloud.hasNormals();
  const bool colors = cloud.hasColors();
  bool dense = true;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    PclPoint& q = out->points[i];
    const auto& p = cloud.points[i];
    q.x = static_cast<float>(p.x());
    q.y = static_cast<float>(p.y());
    q.z = static_cast<float>(p.z());
    dense = dense && p.allFinite();
    if (normals) {
      q.normal_x = static_cast<float>(cloud.normals[i].x());
      q.normal_y = static_cast<float>(cloud.normals[i].y());
      q.normal_z = static_cast<float>(cloud.normals[i].z());
    } else {
      q.normal_x = q.normal_y = q.normal_z = 0.0f;
    }
    q.curvature = 0.0f;
    if (colors) {
      q.r = cloud.colors[i][0];
      q.g = cloud.colors[i][1];
      q.b = cloud.colors[i][2];
    } else {
      q.r = q.g = q.b = 0;
    }
    q.a = 255;
  }
  if (cloud.isOrganized()) {
    out->width = cloud.width;
    out->height = cloud.height;
  } else {
    out->width = static_cast<std::uint32_t>(cloud.size());
    out->height = 1;
  }
  out->is_dense = dense;
  setSensorPose(cloud, out->sensor_origin_, out->sensor_orientation_);
  return out;
}

PointCloud fromPcl(const PclCloud& cloud, bool normals, bool colors) {
  PointCloud out;
  out.points.reserve(cloud.size());
  if (normals) out.normals.reserve(cloud.size());
  if (colors) out.colors.reserve(cloud.size());
  for (const auto& q : cloud.points) {
    out.points.emplace_back(q.x, q.y, q.z);
    if (normals) out.normals.emplace_back(q.normal_x, q.normal_y, q.normal_z);
    if (colors) out.colors.push_back({q.r, q.g, q.b});
  }
  if (cloud.height > 1 && std::size_t{cloud.width} * cloud.height == cloud.size()) {
    out.width = cloud.width;
    out.height = cloud.height;
  }
  out.sensor_origin = cloud.sensor_origin_.head<3>().cast<double>();
  out.sensor_orientation = cloud.sensor_orientation_.cast<double>();
  return out;
}

pcl::PointCloud<pcl::PointXYZ>::Ptr toPclXyz(const std::vector<Eigen::Vector3d>& points) {
  auto out = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  out->points.reserve(points.size());
  for (const auto& p : points) {
    out->points.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()),
                             static_cast<float>(p.z()));
  }
  out->width = static_cast<std::uint32_t>(out->points.size());
  out->height = 1;
  out->is_dense = false;
  return out;
}

bool fromBlob(const pcl::PCLPointCloud2& blob, PointCloud& out, std::string& problem) {
  for (const char* axis : {"x", "y", "z"}) {
    if (!hasField(blob, axis)) {
      problem = std::string("no '") + axis + "' field";
      return false;
    }
  }
  pcl::PointCloud<pcl::PointXYZ> xyz;
  pcl::fromPCLPointCloud2(blob, xyz);
  out = PointCloud{};
  out.points.reserve(xyz.size());
  for (const auto& q : xyz.points) out.points.emplace_back(q.x, q.y, q.z);
  if (hasField(blob, "rgb") || hasField(blob, "rgba")) {
    // PCL maps "rgb" and "rgba" onto the same packed colour.
    pcl::PointCloud<pcl::PointXYZRGB> rgb;
    pcl::fromPCLPointCloud2(blob, rgb);
    out.colors.reserve(rgb.size());
    for (const auto& q : rgb.points) out.colors.push_back({q.r, q.g, q.b});
  }
  if (hasField(blob, "label")) {
    pcl::PointCloud<pcl::Label> labels;
    pcl::fromPCLPointCloud2(blob, labels);
    out.labels.reserve(labels.size());
    for (const auto& q : labels.points) out.labels.push_back(q.label);
  }
  if (hasField(blob, "normal_x") && hasField(blob, "normal_y") && hasField(blob, "normal_z")) {
    pcl::PointCloud<pcl::Normal> normals;
    pcl::fromPCLPointCloud2(blob, normals);
    out.normals.reserve(normals.size());
    for (const auto& q : normals.points) {
      out.normals.emplace_back(q.normal_x, q.normal_y, q.normal_z);
    }
  }
  if (blob.height > 1 && std::size_t{blob.width} * blob.height == out.size()) {
    out.width = blob.width;
    out.height = blob.height;
  }
  return true;
}

pcl::PCLPointCloud2 toBlob(const PointCloud& cloud) {
  pcl::PointCloud<pcl::PointXYZ> xyz;
  xyz.points.reserve(cloud.size());
  for (const auto& p : cloud.points) {
    xyz.points.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()),
                            static_cast<float>(p.z()));
  }
  const bool organised = cloud.isOrganized();
  const std::uint32_t width = organised ? cloud.width : static_cast<std::uint32_t>(cloud.size());
  const std::uint32_t height = organised ? cloud.height : 1;
  auto shape = [&](auto& c) {
    c.width = width;
    c.height = height;
    c.is_dense = false;
  };
  shape(xyz);
  pcl::PCLPointCloud2 blob;
  pcl::toPCLPointCloud2(xyz, blob);
  auto concat = [&blob](const pcl::PCLPointCloud2& more) {
    pcl::PCLPointCloud2 joined;
    pcl::concatenateFields(blob, more, joined);
    blob = std::move(joined);
  };
  if (cloud.hasColors()) {
    pcl::PointCloud<pcl::RGB> rgb;
    rgb.points.resize(cloud.size());
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      rgb.points[i].r = cloud.colors[i][0];
      rgb.points[i].g = cloud.colors[i][1];
      rgb.points[i].b = cloud.colors[i][2];
      rgb.points[i].a = 255;
    }
    shape(rgb);
    pcl::PCLPointCloud2 part;
    pcl::toPCLPointCloud2(rgb, part);
    concat(part);
  }
  if (cloud.hasLabels()) {
    pcl::PointCloud<pcl::Label> labels;
    labels.points.resize(cloud.size());
    for (std::size_t i = 0; i < cloud.size(); ++i) labels.points[i].label = cloud.labels[i];
    shape(labels);
    pcl::PCLPointCloud2 part;
    pcl::toPCLPointCloud2(labels, part);
    concat(part);
  }
  if (cloud.hasNormals()) {
    pcl::PointCloud<pcl::Normal> normals;
    normals.points.resize(cloud.size());
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      normals.points[i].normal_x = static_cast<float>(cloud.normals[i].x());
      normals.points[i].normal_y = static_cast<float>(cloud.normals[i].y());
      normals.points[i].normal_z = static_cast<float>(cloud.normals[i].z());
      normals.points[i].curvature = 0.0f;
    }
    shape(normals);
    pcl::PCLPointCloud2 part;
    pcl::toPCLPointCloud2(normals, part);
    concat(part);
  }
  return blob;
}

}  // namespace skelgrasp::internal
