#pragma once
// Segmentation quality against per-point ground-truth labels (mOSD-style clouds: the Object
// Segmentation Database's `label` field). Used by `skelgrasp bench segment` and the tests.
#include <cstdint>
#include <vector>

#include "skelgrasp/common/point_cloud.h"

namespace skelgrasp::perception {

// mOSD label convention: 0 = no label, 1-9 = the table, 10 k + j (k >= 1, j in 0-9) = object k.
constexpr std::uint32_t kFirstObjectLabel = 10;
constexpr std::uint32_t kLabelsPerObject = 10;
// A labelled point counts for the segment of its nearest segment point within this distance (the
// 3 mm voxel grid moves points by at most 2.6 mm).
constexpr double kLabelMatchDistanceM = 0.005;

// True when the cloud has a label per point and at least one object label.
bool hasObjectLabels(const PointCloud& cloud);

struct LabelledObjectScore {
  std::uint32_t object = 0;  // k of the labels 10 k .. 10 k + 9
  std::size_t points = 0;    // labelled points (finite) of the object
  int segment = -1;          // best segment: the one holding most of its points; -1 = none
  double precision = 0;      // object points in that segment / labelled points in the segment
  double recall = 0;         // object points in that segment / all object points
  double iou = 0;            // overlap / (object points + segment points - overlap)
};

struct SegmentLabels {
  std::size_t points = 0;        // labelled points that went to the segment
  std::uint32_t majority = 0;    // object most of them belong to (0 = the table)
  double majority_fraction = 0;  // its share of them
};

struct LabelScore {
  std::vector<LabelledObjectScore> objects;  // by object number
  std::size_t segments = 0;
  std::vector<SegmentLabels> segment_labels;                 // parallel to the segments
  double mean_precision = 0, mean_recall = 0, mean_iou = 0;  // over labelled objects
};

// Every labelled, finite point of `labelled` (labels 0 ignored, table points count against the
// segment that took them) goes to the segment of its nearest segment point within
// kLabelMatchDistanceM; each object is matched to the segment holding most of its points. Throws
// InvalidArgument when the cloud has no object labels.
LabelScore scoreAgainstLabels(const PointCloud& labelled, const std::vector<PointCloud>& segments);

}  // namespace skelgrasp::perception
