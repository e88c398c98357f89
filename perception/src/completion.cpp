// Height-map completion on the support plane; OpenCV does the grid morphology.
#include "skelgrasp/perception/completion.h"

#include <opencv2/imgproc.hpp>

#include <cmath>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/pose.h"

namespace skelgrasp::perception {

SupportCompletion completeOnSupport(const PointCloud& object, const SupportPlane& plane,
                                    const SupportCompletionParams& params) {
  if (!(params.cell_m > 0) || params.closing_cells < 0) {
    throw InvalidArgument("completeOnSupport: cell must be positive, closing non-negative");
  }
  SupportCompletion out;
  if (object.empty()) return out;
  // Plane frame: origin under the object's first point, e1/e2 in the plane, n up.
  const Eigen::Vector3d n = plane.normal;
  const Eigen::Vector3d e1 = anyPerpendicular(n);
  const Eigen::Vector3d e2 = n.cross(e1);
  const Eigen::Vector3d origin =
      object.points.front() - plane.signedDistance(object.points.front()) * n;
  const double s = params.cell_m;
  const int margin = params.closing_cells + 1;

  double amin = 1e300, bmin = 1e300, amax = -1e300, bmax = -1e300;
  for (const auto& p : object.points) {
    const double a = (p - origin).dot(e1), b = (p - origin).dot(e2);
    amin = std::min(amin, a);
    amax = std::max(amax, a);
    bmin = std::min(bmin, b);
    bmax = std::max(bmax, b);
  }
  const int cols = static_cast<int>(std::floor((amax - amin) / s)) + 1 + 2 * margin;
  const int rows = static_cast<int>(std::floor((bmax - bmin) / s)) + 1 + 2 * margin;
  if (static_cast<double>(cols) * rows > 4e7) {
    throw InvalidArgument("completeOnSupport: object too large for the height-map cell");
  }
  cv::Mat height(rows, cols, CV_32FC1, cv::Scalar(0.0f));
  cv::Mat occupied(rows, cols, CV_8UC1, cv::Scalar(0));
  for (const auto& p : object.points) {
    const int c = static_cast<int>(std::floor(((p - origin).dot(e1) - amin) / s)) + margin;
    const int r = static_cast<int>(std::floor(((p - origin).dot(e2) - bmin) / s)) + margin;
    const float h = static_cast<float>(std::max(0.0, plane.signedDistance(p)));
    occupied.at<std::uint8_t>(r, c) = 255;
    height.at<float>(r, c) = std::max(height.at<float>(r, c), h);
  }
  if (params.closing_cells > 0) {
    const int k = 2 * params.closing_cells + 1;
    const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k));
    cv::Mat closed;
    cv::morphologyEx(occupied, closed, cv::MORPH_CLOSE, kernel);
    // Cells the closing added take the highest neighbouring column.
    cv::Mat grown;
    cv::dilate(height, grown, kernel);
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        if (closed.at<std::uint8_t>(r, c) && !occupied.at<std::uint8_t>(r, c)) {
          height.at<float>(r, c) = grown.at<float>(r, c);
        }
      }
    }
    occupied = closed;
  }

  auto at = [&](double a, double b, double h) { return origin + a * e1 + b * e2 + h * n; };
  const int dr[4] = {0, 0, 1, -1}, dc[4] = {1, -1, 0, 0};
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (!occupied.at<std::uint8_t>(r, c)) continue;
      ++out.footprint_cells;
      const double a = amin + (c - margin + 0.5) * s, b = bmin + (r - margin + 0.5) * s;
      out.points.points.push_back(at(a, b, 0.0));
      out.points.normals.push_back(-n);
      ++out.bottom_points;
      const double top = height.at<float>(r, c);
      for (int k = 0; k < 4; ++k) {
        const int rn = r + dr[k], cn = c + dc[k];
        if (occupied.at<std::uint8_t>(rn, cn)) continue;  // margin keeps rn, cn inside
        const Eigen::Vector3d outward = dc[k] * e1 + dr[k] * e2;
        const double wa = a + 0.5 * s * dc[k], wb = b + 0.5 * s * dr[k];
        for (double h = 0.5 * s; h < top; h += s) {
          out.points.points.push_back(at(wa, wb, h));
          out.points.normals.push_back(outward);
          ++out.wall_points;
        }
      }
    }
  }
  out.points.sensor_origin = object.sensor_origin;
  return out;
}

}  // namespace skelgrasp::perception
