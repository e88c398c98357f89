#pragma once
// The one triangle rasteriser of the project: which pixels a projected triangle covers and at
// what depth (perspective-correct). The PNG renderer (render.h) and the simulated depth camera
// (perception/depth_camera.h) both scan-convert through it; each keeps its own z-buffer contents
// (colours, mesh and face labels) in the visitor.
#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>

namespace skelgrasp::raster {

// Where pixel (x, y) samples the image plane: at (x + offset, y + offset). The depth camera
// samples at integer coordinates (the pinhole model's pixel convention), the renderer at pixel
// centres.
inline constexpr double kCornerSample = 0.0;
inline constexpr double kCentreSample = 0.5;

// Triangles whose projected area (pixels squared) is below this are seen edge-on: nothing drawn.
inline constexpr double kDegenerateAreaPx2 = 1e-12;

// Calls visit(x, y, depth) for every pixel of a width x height image whose sample point lies in
// the triangle, edges included (a pixel on an edge shared by two faces is visited for both; the
// caller's depth test decides). `screen` holds the vertices in pixels, `depth` their camera-frame
// depths (> 0); the depth is interpolated linearly in 1/z, which is exact for a planar triangle.
template <class Visit>
void rasteriseTriangle(const std::array<Eigen::Vector2d, 3>& screen,
                       const std::array<double, 3>& depth, int width, int height,
                       double sample_offset, Visit&& visit) {
  const double sx[3] = {screen[0].x(), screen[1].x(), screen[2].x()};
  const double sy[3] = {screen[0].y(), screen[1].y(), screen[2].y()};
  const double inv_z[3] = {1.0 / depth[0], 1.0 / depth[1], 1.0 / depth[2]};
  const double area = (sx[1] - sx[0]) * (sy[2] - sy[0]) - (sx[2] - sx[0]) * (sy[1] - sy[0]);
  if (std::abs(area) < kDegenerateAreaPx2) return;
  // Pixels whose sample point lies in the triangle's bounding box.
  const auto first = [&](const double* s) {
    return std::max(0, static_cast<int>(std::ceil(std::min({s[0], s[1], s[2]}) - sample_offset)));
  };
  const auto last = [&](const double* s, int size) {
    return std::min(size - 1,
                    static_cast<int>(std::floor(std::max({s[0], s[1], s[2]}) - sample_offset)));
  };
  const int x0 = first(sx), x1 = last(sx, width), y0 = first(sy), y1 = last(sy, height);
  const double inv_area = 1.0 / area;
  for (int y = y0; y <= y1; ++y) {
    const double qy = y + sample_offset;
    for (int x = x0; x <= x1; ++x) {
      const double qx = x + sample_offset;
      // Barycentric weights from edge functions.
      const double w0 = ((sx[1] - qx) * (sy[2] - qy) - (sx[2] - qx) * (sy[1] - qy)) * inv_area;
      const double w1 = ((sx[2] - qx) * (sy[0] - qy) - (sx[0] - qx) * (sy[2] - qy)) * inv_area;
      const double w2 = 1.0 - w0 - w1;
      if (w0 < 0 || w1 < 0 || w2 < 0) continue;
      visit(x, y, 1.0 / (w0 * inv_z[0] + w1 * inv_z[1] + w2 * inv_z[2]));
    }
  }
}

}  // namespace skelgrasp::raster
