#pragma once
// Internal (not installed): the segmentations behind parseScene, each over cloud.points[candidates]
// (the points above the support). PCL types stay in segmentation.cpp.
#include <vector>

#include "skelgrasp/common/point_cloud.h"
#include "skelgrasp/perception/scene.h"

namespace skelgrasp::internal {

struct Segmentation {
  std::vector<std::vector<int>> segments;  // indices into the cloud, largest first
  std::vector<perception::DroppedFragment> dropped;
  std::size_t merged = 0;  // small segments merged into a neighbour
};

// Connected components at params.cluster_tolerance_m; clusters outside [min, max] points are
// dropped and recorded.
Segmentation euclideanSegments(const PointCloud& cloud, const std::vector<int>& candidates,
                               const perception::SceneParams& params);

// Supervoxels + LCCP (params.lccp) on the points relative to the sensor origin, colour where the
// cloud has it; segments below params.lccp.min_segment_points merged into their most connected
// neighbour, or kept (from min_isolated_points) or dropped when isolated. Parts (segments hanging
// on a neighbour that could not stand alone or are much smaller and rest on its upper half) and
// the pieces of one symmetric body (oneSymmetricBody) are merged.
Segmentation lccpSegments(const PointCloud& cloud, const std::vector<int>& candidates,
                          const perception::SceneParams& params,
                          const perception::SupportPlane& plane);

// Whether two segments are one rotationally symmetric body about an axis normal to the support,
// cut apart at its rim (LccpParams, symmetric bodies): one circle on the support carries most of
// the points of both and they go round it.
bool oneSymmetricBody(const PointCloud& cloud, const std::vector<int>& a, const std::vector<int>& b,
                      const perception::SupportPlane& plane, const perception::LccpParams& lp);

// Joins segments that are one object seen in pieces around an occluder (LccpParams, hidden gaps):
// the gap between their closest points is hidden from the sensor by another segment all along
// and they share their colour. Returns the number of joins; `segments` keeps its other order.
std::size_t joinAcrossOccluders(const PointCloud& cloud, std::vector<std::vector<int>>& segments,
                                const perception::LccpParams& lp);

}  // namespace skelgrasp::internal
