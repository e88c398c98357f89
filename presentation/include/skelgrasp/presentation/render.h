#pragma once
// A small software renderer for checking results by eye: flat-shaded triangles with a z-buffer,
// overlay lines, points and text, written as PNG (through OpenCV). Perspective camera.
#include <memory>
#include <string>
#include <vector>

#include "skelgrasp/common/mesh.h"

namespace skelgrasp::presentation {

struct Camera {
  Eigen::Vector3d eye = Eigen::Vector3d(0.5, 0.5, 0.5);
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double fov_y_rad = 0.6;
  int width = 640;
  int height = 480;

  // A camera looking at the box centre from direction `view_from` (towards the eye), far enough
  // for the whole box to fit with a margin.
  static Camera framing(const AxisAlignedBox& box, const Eigen::Vector3d& view_from, int width,
                        int height, const Eigen::Vector3d& up = Eigen::Vector3d::UnitZ());
};

class Canvas {
 public:
  explicit Canvas(const Camera& camera, Rgb background = {255, 255, 255});
  ~Canvas();
  Canvas(Canvas&&) noexcept;
  Canvas& operator=(Canvas&&) noexcept;

  const Camera& camera() const;

  // Opaque flat-shaded mesh; vertex colours (averaged per face) are used when present and
  // `use_vertex_colors` is set, else `color`.
  void drawMesh(const TriangleMesh& mesh, Rgb color, bool use_vertex_colors = true);
  // Overlay primitives, drawn on top of everything so far unless depth_test is set.
  void drawLine(const Eigen::Vector3d& a, const Eigen::Vector3d& b, Rgb color, int thickness_px = 2,
                bool depth_test = false);
  void drawPoint(const Eigen::Vector3d& p, Rgb color, int radius_px = 3, bool depth_test = false);
  // Text at pixel coordinates (top-left origin).
  void drawText(int x, int y, const std::string& text, Rgb color = {20, 20, 20},
                double scale = 0.5);

  // Projects a point to pixel coordinates; false if behind the camera.
  bool project(const Eigen::Vector3d& p, double& u, double& v, double& depth) const;

  // Writes PNG; throws IoError.
  void savePng(const std::string& path) const;

  // Side-by-side composition of equally sized canvases (row-major grid with `columns`).
  static void saveGrid(const std::vector<const Canvas*>& panels, int columns,
                       const std::string& path);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// A grouped bar chart as PNG: one group per x label, one bar per series in each group.
struct BarSeries {
  std::string label;
  Rgb colour;
  std::vector<double> values;  // one per x label
};
void saveBarChartPng(const std::string& path, const std::string& title,
                     const std::vector<std::string>& x_labels, const std::vector<BarSeries>& series,
                     const std::string& y_label, int width = 900, int height = 420);

}  // namespace skelgrasp::presentation
