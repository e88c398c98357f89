// PCL translation unit (kd-tree): segmentation scores against per-point labels.
#include "skelgrasp/perception/label_score.h"

#include <map>

#include "skelgrasp/common/error.h"
#include "skelgrasp/geometry/point_index.h"

namespace skelgrasp::perception {

bool hasObjectLabels(const PointCloud& cloud) {
  if (!cloud.hasLabels()) return false;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.labels[i] >= kFirstObjectLabel && cloud.points[i].allFinite()) return true;
  }
  return false;
}

LabelScore scoreAgainstLabels(const PointCloud& labelled, const std::vector<PointCloud>& segments) {
  if (!hasObjectLabels(labelled)) {
    throw InvalidArgument("scoreAgainstLabels: the cloud has no object labels");
  }
  std::vector<Eigen::Vector3d> points;
  std::vector<int> owner;
  for (std::size_t s = 0; s < segments.size(); ++s) {
    for (const auto& p : segments[s].points) {
      points.push_back(p);
      owner.push_back(static_cast<int>(s));
    }
  }
  // The project's one nearest-neighbour index (geometry/point_index.h).
  const geometry::PointIndex index(points);
  std::map<std::uint32_t, std::size_t> object_size;
  std::map<std::pair<std::uint32_t, int>, std::size_t> overlap;
  std::vector<std::size_t> segment_size(segments.size(), 0);
  for (std::size_t i = 0; i < labelled.size(); ++i) {
    const auto& p = labelled.points[i];
    if (!p.allFinite() || labelled.labels[i] == 0) continue;
    const std::uint32_t label = labelled.labels[i];
    const std::uint32_t object = label < kFirstObjectLabel ? 0 : label / kLabelsPerObject;
    if (object > 0) ++object_size[object];
    if (points.empty()) continue;
    const auto [nearest, distance] = index.nearest(p);
    if (nearest < 0 || distance > kLabelMatchDistanceM) continue;
    const int s = owner[nearest];
    ++segment_size[s];
    if (object > 0) ++overlap[{object, s}];
  }
  LabelScore score;
  score.segments = segments.size();
  score.segment_labels.resize(segments.size());
  std::vector<std::size_t> object_points(segments.size(), 0);
  for (const auto& [key, count] : overlap) {
    auto& s = score.segment_labels[key.second];
    object_points[key.second] += count;
    if (count > s.majority_fraction) {  // a count for now, a fraction below
      s.majority = key.first;
      s.majority_fraction = static_cast<double>(count);
    }
  }
  for (std::size_t s = 0; s < segments.size(); ++s) {
    auto& l = score.segment_labels[s];
    l.points = segment_size[s];
    const std::size_t table = segment_size[s] - object_points[s];
    if (static_cast<double>(table) > l.majority_fraction) {
      l.majority = 0;
      l.majority_fraction = static_cast<double>(table);
    }
    l.majority_fraction = l.points > 0 ? l.majority_fraction / static_cast<double>(l.points) : 0;
  }
  for (const auto& [object, size] : object_size) {
    LabelledObjectScore o;
    o.object = object;
    o.points = size;
    std::size_t best = 0;
    for (std::size_t s = 0; s < segments.size(); ++s) {
      const auto it = overlap.find({object, static_cast<int>(s)});
      if (it != overlap.end() && it->second > best) {
        best = it->second;
        o.segment = static_cast<int>(s);
      }
    }
    if (o.segment >= 0) {
      const double seg = static_cast<double>(segment_size[o.segment]);
      o.precision = best / seg;
      o.recall = static_cast<double>(best) / size;
      o.iou = best / (static_cast<double>(size) + seg - best);
    }
    score.mean_precision += o.precision;
    score.mean_recall += o.recall;
    score.mean_iou += o.iou;
    score.objects.push_back(o);
  }
  const double n = static_cast<double>(score.objects.size());
  score.mean_precision /= n;
  score.mean_recall /= n;
  score.mean_iou /= n;
  return score;
}

}  // namespace skelgrasp::perception
