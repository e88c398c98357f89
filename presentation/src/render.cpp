// OpenCV is used only for the image buffer and 2D drawing; libpng encodes (png_file.h).
#include "skelgrasp/presentation/render.h"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <filesystem>
#include <limits>

#include "png_file.h"
#include "skelgrasp/common/atomic_file.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/rasterise.h"

namespace skelgrasp::presentation {
namespace {

// Smallest radius (metres) a camera frames, so a point-sized box still gets a finite distance.
constexpr double kMinFramingRadiusM = 1e-3;
// Points closer to the eye than this (metres, along the view axis) are behind the near plane.
constexpr double kNearPlaneM = 1e-6;
// A view direction and `up` whose cross product is shorter than this are parallel (unit vectors).
constexpr double kParallelUpNorm = 1e-9;
// Depth-tested overlays: lines are drawn in this many pieces, each shown when its start is no
// more than the tolerance (metres) behind the surface, so lines on a surface stay visible.
constexpr int kDepthTestedLineSegments = 64;
constexpr double kOverlayDepthToleranceM = 1e-4;

}  // namespace

Camera Camera::framing(const AxisAlignedBox& box, const Eigen::Vector3d& view_from, int width,
                       int height, const Eigen::Vector3d& up) {
  Camera cam;
  cam.width = width;
  cam.height = height;
  cam.up = up;
  cam.target = box.center();
  const double radius = std::max(0.5 * box.diagonal(), kMinFramingRadiusM);
  const double fov = std::min(cam.fov_y_rad, cam.fov_y_rad * width / height);
  const double distance = radius / std::sin(0.5 * fov) * 1.05;
  cam.eye = cam.target + view_from.normalized() * distance;
  return cam;
}

struct Canvas::Impl {
  Camera camera;
  cv::Mat image;  // BGR
  std::vector<double> depth;
  Eigen::Matrix3d world_to_cam;  // rows: right, down, forward
  double focal = 1;

  bool toCamera(const Eigen::Vector3d& p, Eigen::Vector3d& c) const {
    c = world_to_cam * (p - camera.eye);
    return c.z() > kNearPlaneM;
  }
  Eigen::Vector2d toPixel(const Eigen::Vector3d& c) const {
    return {0.5 * camera.width + focal * c.x() / c.z(),
            0.5 * camera.height + focal * c.y() / c.z()};
  }
};

Canvas::Canvas(const Camera& camera, Rgb background) : impl_(std::make_unique<Impl>()) {
  if (camera.width <= 0 || camera.height <= 0) throw InvalidArgument("Canvas: empty image size");
  impl_->camera = camera;
  impl_->image = cv::Mat(camera.height, camera.width, CV_8UC3,
                         cv::Scalar(background[2], background[1], background[0]));
  impl_->depth.assign(static_cast<std::size_t>(camera.width) * camera.height,
                      std::numeric_limits<double>::infinity());
  const Eigen::Vector3d forward = (camera.target - camera.eye).normalized();
  Eigen::Vector3d right = forward.cross(camera.up);
  if (right.norm() < kParallelUpNorm) right = forward.cross(Eigen::Vector3d::UnitX());
  right.normalize();
  const Eigen::Vector3d down = forward.cross(right);
  impl_->world_to_cam.row(0) = right;
  impl_->world_to_cam.row(1) = down;
  impl_->world_to_cam.row(2) = forward;
  impl_->focal = 0.5 * camera.height / std::tan(0.5 * camera.fov_y_rad);
}

Canvas::~Canvas() = default;
Canvas::Canvas(Canvas&&) noexcept = default;
Canvas& Canvas::operator=(Canvas&&) noexcept = default;

const Camera& Canvas::camera() const {
  return impl_->camera;
}

bool Canvas::project(const Eigen::Vector3d& p, double& u, double& v, double& depth) const {
  Eigen::Vector3d c;
  if (!impl_->toCamera(p, c)) return false;
  const Eigen::Vector2d px = impl_->toPixel(c);
  u = px.x();
  v = px.y();
  depth = c.z();
  return true;
}

void Canvas::drawMesh(const TriangleMesh& mesh, Rgb color, bool use_vertex_colors) {
  auto& im = *impl_;
  const int w = im.camera.width, h = im.camera.height;
  const bool colours = use_vertex_colors && mesh.vertex_colors.size() == mesh.vertices.size();
  const Eigen::Vector3d light = (im.camera.eye - im.camera.target).normalized();
  std::vector<Eigen::Vector3d> cam(mesh.vertices.size());
  std::vector<char> valid(mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    valid[i] = im.toCamera(mesh.vertices[i], cam[i]);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& t = mesh.faces[f];
    if (!valid[t[0]] || !valid[t[1]] || !valid[t[2]]) continue;
    const Eigen::Vector2d p0 = im.toPixel(cam[t[0]]), p1 = im.toPixel(cam[t[1]]),
                          p2 = im.toPixel(cam[t[2]]);
    // Two-sided lighting: the renderer is for inspection, inverted faces should still show.
    const double shade = 0.35 + 0.65 * std::abs(mesh.faceNormal(f).dot(light));
    Eigen::Vector3d base(color[0], color[1], color[2]);
    if (colours) {
      base.setZero();
      for (int k = 0; k < 3; ++k) {
        const auto& c = mesh.vertex_colors[t[k]];
        base += Eigen::Vector3d(c[0], c[1], c[2]) / 3.0;
      }
    }
    const cv::Vec3b bgr(static_cast<uchar>(std::min(255.0, base[2] * shade)),
                        static_cast<uchar>(std::min(255.0, base[1] * shade)),
                        static_cast<uchar>(std::min(255.0, base[0] * shade)));
    raster::rasteriseTriangle({p0, p1, p2}, {cam[t[0]].z(), cam[t[1]].z(), cam[t[2]].z()}, w, h,
                              raster::kCentreSample, [&](int x, int y, double z) {
                                double& zbuf = im.depth[static_cast<std::size_t>(y) * w + x];
                                if (z < zbuf) {
                                  zbuf = z;
                                  im.image.at<cv::Vec3b>(y, x) = bgr;
                                }
                              });
  }
}

void Canvas::drawLine(const Eigen::Vector3d& a, const Eigen::Vector3d& b, Rgb color,
                      int thickness_px, bool depth_test) {
  auto& im = *impl_;
  Eigen::Vector3d ca, cb;
  if (!im.toCamera(a, ca) || !im.toCamera(b, cb)) return;
  const cv::Scalar bgr(color[2], color[1], color[0]);
  if (!depth_test) {
    const Eigen::Vector2d pa = im.toPixel(ca), pb = im.toPixel(cb);
    cv::line(im.image, cv::Point2d(pa.x(), pa.y()), cv::Point2d(pb.x(), pb.y()), bgr, thickness_px,
             cv::LINE_AA);
    return;
  }
  const int steps = kDepthTestedLineSegments;
  for (int i = 0; i < steps; ++i) {
    const Eigen::Vector3d c0 = ca + (cb - ca) * (double(i) / steps);
    const Eigen::Vector3d c1 = ca + (cb - ca) * (double(i + 1) / steps);
    const Eigen::Vector2d p0 = im.toPixel(c0), p1 = im.toPixel(c1);
    const int x = static_cast<int>(p0.x()), y = static_cast<int>(p0.y());
    if (x < 0 || y < 0 || x >= im.camera.width || y >= im.camera.height) continue;
    if (c0.z() >
        im.depth[static_cast<std::size_t>(y) * im.camera.width + x] + kOverlayDepthToleranceM)
      continue;
    cv::line(im.image, cv::Point2d(p0.x(), p0.y()), cv::Point2d(p1.x(), p1.y()), bgr, thickness_px,
             cv::LINE_AA);
  }
}

void Canvas::drawPoint(const Eigen::Vector3d& p, Rgb color, int radius_px, bool depth_test) {
  auto& im = *impl_;
  Eigen::Vector3d c;
  if (!im.toCamera(p, c)) return;
  const Eigen::Vector2d px = im.toPixel(c);
  const int x = static_cast<int>(px.x()), y = static_cast<int>(px.y());
  if (depth_test && x >= 0 && y >= 0 && x < im.camera.width && y < im.camera.height &&
      c.z() >
          im.depth[static_cast<std::size_t>(y) * im.camera.width + x] + kOverlayDepthToleranceM) {
    return;
  }
  cv::circle(im.image, cv::Point2d(px.x(), px.y()), radius_px,
             cv::Scalar(color[2], color[1], color[0]), cv::FILLED, cv::LINE_AA);
}

void Canvas::drawText(int x, int y, const std::string& text, Rgb color, double scale) {
  cv::putText(impl_->image, text, cv::Point(x, y + static_cast<int>(20 * scale)),
              cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(color[2], color[1], color[0]), 1,
              cv::LINE_AA);
}

namespace {
void writePng(const std::string& path, const cv::Mat& image) {
  internal::writeBgrPng(path, image.cols, image.rows, image.ptr<std::uint8_t>(0), image.step[0]);
}
}  // namespace

void Canvas::savePng(const std::string& path) const {
  writePng(path, impl_->image);
}

void Canvas::saveGrid(const std::vector<const Canvas*>& panels, int columns,
                      const std::string& path) {
  if (panels.empty() || columns <= 0) throw InvalidArgument("saveGrid: no panels");
  const int w = panels[0]->impl_->camera.width, h = panels[0]->impl_->camera.height;
  const int rows = (static_cast<int>(panels.size()) + columns - 1) / columns;
  cv::Mat grid(rows * h, columns * w, CV_8UC3, cv::Scalar(255, 255, 255));
  for (std::size_t i = 0; i < panels.size(); ++i) {
    const auto& img = panels[i]->impl_->image;
    if (img.cols != w || img.rows != h) throw InvalidArgument("saveGrid: panels differ in size");
    img.copyTo(
        grid(cv::Rect(static_cast<int>(i % columns) * w, static_cast<int>(i / columns) * h, w, h)));
  }
  writePng(path, grid);
}

}  // namespace skelgrasp::presentation
