#pragma once
// Internal (not installed): the one place where skelgrasp point clouds meet PCL types. Only .cpp
// files of perception/ and reconstruction/ include this header.
#include <pcl/PCLPointCloud2.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <vector>

#include "skelgrasp/common/point_cloud.h"

namespace skelgrasp::internal {

// The working point type of the filters: position, colour and normal in one struct, so voxel
// averaging and index filters carry all of them.
using PclPoint = pcl::PointXYZRGBNormal;
using PclCloud = pcl::PointCloud<PclPoint>;

// Copies points (and normals, colours when present) and the sensor pose; organised clouds keep
// width and height. Missing normals are zero, missing colours black.
PclCloud::Ptr toPcl(const PointCloud& cloud);
// `normals`/`colors`: copy those fields back. Labels are not part of PclPoint.
PointCloud fromPcl(const PclCloud& cloud, bool normals, bool colors);

pcl::PointCloud<pcl::PointXYZ>::Ptr toPclXyz(const std::vector<Eigen::Vector3d>& points);

// Any PCD/PLY field layout -> PointCloud: x y z required; rgb/rgba, label and normal_x/y/z copied
// when present. Returns false (and names the problem) when x, y or z is missing.
bool fromBlob(const pcl::PCLPointCloud2& blob, PointCloud& out, std::string& problem);
// PointCloud -> blob with x y z [+ rgb] [+ label] [+ normal_x normal_y normal_z curvature].
pcl::PCLPointCloud2 toBlob(const PointCloud& cloud);

}  // namespace skelgrasp::internal
