#pragma once
// Small point-cloud manipulations shared by the perception stages (no library involved).
#include <vector>

#include "skelgrasp/common/point_cloud.h"
#include "skelgrasp/common/pose.h"

namespace skelgrasp::perception {

// The points at `indices` with their normals, colours and labels; unorganised; same sensor pose.
PointCloud subset(const PointCloud& cloud, const std::vector<int>& indices);

// Appends `more` to `cloud`. Per-point attributes survive only when both clouds have them; the
// result is unorganised and keeps `cloud`'s sensor pose (or `more`'s when `cloud` was empty).
void append(PointCloud& cloud, const PointCloud& more);

// Points, normals and sensor pose mapped through `pose` (organisation kept).
PointCloud transformed(const PointCloud& cloud, const Pose& pose);

// Number of points with finite coordinates.
std::size_t countFinite(const PointCloud& cloud);

}  // namespace skelgrasp::perception
