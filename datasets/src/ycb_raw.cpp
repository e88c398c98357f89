#include "skelgrasp/datasets/ycb_raw.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <regex>

#include "hdf5_io.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/perception/cloud_ops.h"
#include "skelgrasp/perception/image_io.h"
#include "skelgrasp/perception/rgbd.h"

namespace skelgrasp::datasets {
namespace {

namespace fs = std::filesystem;

Pose rigid(const Eigen::MatrixXd& m, const std::string& file, const std::string& name) {
  if (m.rows() != 4 || m.cols() != 4) {
    throw IoError(file, "'" + name + "' is " + std::to_string(m.rows()) + "x" +
                            std::to_string(m.cols()) + ", expected 4x4");
  }
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  const bool proper = (r.transpose() * r - Eigen::Matrix3d::Identity()).norm() < 1e-3 &&
                      r.determinant() > 0 &&
                      (m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() < 1e-6 && m.allFinite();
  if (!proper) throw IoError(file, "'" + name + "' is not a rigid transform");
  Pose pose = Pose::Identity();
  pose.linear() = r;
  pose.translation() = m.topRightCorner<3, 1>();
  return pose;
}

perception::PinholeIntrinsics intrinsicsFrom(const Eigen::MatrixXd& k, int width, int height,
                                             const std::string& file, const std::string& name) {
  if (k.rows() != 3 || k.cols() != 3 || !(k(0, 0) > 0) || !(k(1, 1) > 0)) {
    throw IoError(file, "'" + name + "' is not a 3x3 camera matrix");
  }
  perception::PinholeIntrinsics intrinsics;
  intrinsics.fx = k(0, 0);
  intrinsics.fy = k(1, 1);
  intrinsics.cx = k(0, 2);
  intrinsics.cy = k(1, 2);
  intrinsics.width = width;
  intrinsics.height = height;
  return intrinsics;
}

std::vector<int> anglesOnDisk(const std::string& folder, int reference, int step) {
  std::vector<int> angles;
  const std::regex pattern("NP" + std::to_string(reference) + "_(\\d+)_pose\\.h5");
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder + "/poses", ec)) {
    std::smatch m;
    const std::string name = entry.path().filename().string();
    if (!std::regex_match(name, m, pattern)) continue;
    const int angle = std::stoi(m[1]);
    if (step <= 0 || angle % step == 0) angles.push_back(angle);
  }
  std::sort(angles.begin(), angles.end());
  return angles;
}

struct ViewResult {
  PointCloud cloud;
  YcbRawView info;
};

ViewResult loadView(const std::string& folder, const detail::Hdf5Reader& calibration,
                    const std::string& calibration_path, int camera, int angle,
                    const YcbRawParams& params) {
  const std::string np = "NP" + std::to_string(camera);
  const std::string ref = "NP" + std::to_string(params.reference_camera);
  const std::string depth_path = fmt::format("{}/{}_{}.h5", folder, np, angle);
  const std::string mask_path = fmt::format("{}/masks/{}_{}_mask.pbm", folder, np, angle);
  const std::string pose_path = fmt::format("{}/poses/{}_{}_pose.h5", folder, ref, angle);

  const auto raw = detail::Hdf5Reader(depth_path).uint16Image("depth");
  const double scale = calibration.scalar(np + "_ir_depth_scale") * 1e-4;  // 100 um units
  if (!(scale > 0)) throw IoError(calibration_path, np + "_ir_depth_scale is not positive");
  perception::DepthImage depth(raw.width, raw.height);
  for (std::size_t i = 0; i < raw.data.size(); ++i) {
    depth.data[i] = static_cast<float>(raw.data[i] * scale);
  }
  const perception::DepthImage unfiltered = depth;
  depth = perception::removeDepthDiscontinuities(depth, params.discontinuity_window,
                                                 params.discontinuity_jump_m);

  const std::string ir_k_name = calibration.has(np + "_ir_K") ? np + "_ir_K" : np + "_depth_K";
  const auto ir = intrinsicsFrom(calibration.matrix(ir_k_name), raw.width, raw.height,
                                 calibration_path, ir_k_name);
  const perception::MaskImage mask = perception::readMaskImage(mask_path);
  const auto rgb = intrinsicsFrom(calibration.matrix(np + "_rgb_K"), mask.width, mask.height,
                                  calibration_path, np + "_rgb_K");
  const std::string rgb_name = "H_" + np + "_from_" + ref;
  const std::string ir_name = "H_" + np + "_ir_from_" + ref;
  const Pose rgb_from_ref = rigid(calibration.matrix(rgb_name), calibration_path, rgb_name);
  const Pose ir_from_ref = rigid(calibration.matrix(ir_name), calibration_path, ir_name);
  const Pose table_from_ref =
      rigid(detail::Hdf5Reader(pose_path).matrix("H_table_from_reference_camera"), pose_path,
            "H_table_from_reference_camera");
  const Pose rgb_from_ir = rgb_from_ref * ir_from_ref.inverse();
  const Pose table_from_ir = table_from_ref * ir_from_ref.inverse();

  // The mask lives in the RGB image: a depth pixel is object when its 3-D point projects onto an
  // object pixel there and is not hidden from the RGB camera by a nearer point (the two cameras
  // are a few centimetres apart, so the IR camera sees turntable behind the object's silhouette
  // that projects into the mask). Occlusion is tested on a half-resolution depth buffer of the
  // RGB view (about one cell per depth pixel) filled from the unfiltered depth, so that the
  // silhouette pixels the discontinuity filter drops still hide what lies behind them.
  const std::uint8_t object_value = params.mask_object_is_black ? 0 : 255;
  struct Projected {
    int u, v;  // full-resolution RGB pixel
    float z;   // depth in the RGB camera
  };
  std::vector<Projected> projected(raw.data.size(), Projected{-1, -1, 0.0f});
  perception::Image<float> nearest((mask.width + 1) / 2, (mask.height + 1) / 2,
                                   std::numeric_limits<float>::infinity());
  ViewResult view;
  view.info.camera = camera;
  view.info.angle = angle;
  for (int v = 0; v < depth.height; ++v) {
    for (int u = 0; u < depth.width; ++u) {
      const double z = unfiltered.at(u, v);
      if (!(z > 0)) continue;
      ++view.info.valid_pixels;
      const Eigen::Vector3d p = rgb_from_ir * ir.backProject(u, v, z);
      if (p.z() <= 0) continue;
      const int mu = static_cast<int>(std::lround(rgb.fx * p.x() / p.z() + rgb.cx));
      const int mv = static_cast<int>(std::lround(rgb.fy * p.y() / p.z() + rgb.cy));
      if (!mask.contains(mu, mv)) continue;
      projected[static_cast<std::size_t>(v) * depth.width + u] = {mu, mv,
                                                                  static_cast<float>(p.z())};
      float& cell = nearest.at(mu / 2, mv / 2);
      cell = std::min(cell, static_cast<float>(p.z()));
    }
  }
  perception::MaskImage ir_mask(raw.width, raw.height, 0);
  for (std::size_t i = 0; i < projected.size(); ++i) {
    const Projected& q = projected[i];
    if (q.u < 0 || !(depth.data[i] > 0)) continue;
    const bool in_mask = (mask.at(q.u, q.v) != 0) == (object_value != 0);
    const bool visible = q.z <= nearest.at(q.u / 2, q.v / 2) + std::max(0.01f, 0.02f * q.z);
    ir_mask.data[i] = in_mask && visible ? 1 : 0;
  }
  perception::DepthConversion range;
  range.min_depth_m = params.min_depth_m;
  range.max_depth_m = params.max_depth_m;
  const PointCloud organised =
      perception::depthToPointCloud(depth, ir, table_from_ir, &ir_mask, nullptr, range);
  std::vector<int> finite;
  for (std::size_t i = 0; i < organised.size(); ++i) {
    if (organised.points[i].allFinite()) finite.push_back(static_cast<int>(i));
  }
  view.cloud = perception::subset(organised, finite);
  view.info.object_points = view.cloud.size();
  view.info.camera_position = table_from_ir.translation();
  return view;
}

}  // namespace

std::string findYcbRawFolder(const std::string& path) {
  std::error_code ec;
  if (!fs::is_directory(path, ec)) return {};
  if (fs::exists(fs::path(path) / "calibration.h5", ec)) return path;
  std::vector<std::string> found;
  for (const auto& entry : fs::directory_iterator(path, ec)) {
    if (entry.is_directory(ec) && fs::exists(entry.path() / "calibration.h5", ec)) {
      found.push_back(entry.path().string());
    }
  }
  return found.size() == 1 ? found.front() : std::string();
}

YcbRawCapture loadYcbRaw(const std::string& path, const YcbRawParams& params) {
  if (params.discontinuity_window < 3 || !(params.max_depth_m > params.min_depth_m)) {
    throw InvalidArgument("loadYcbRaw: need cameras, a window >= 3 and max depth > min depth");
  }
  for (int c : params.cameras) {
    if (c < 1 || c > 5)
      throw InvalidArgument("loadYcbRaw: cameras are NP1..NP5, got " + std::to_string(c));
  }
  const std::string folder = findYcbRawFolder(path);
  if (folder.empty()) {
    throw IoError(path,
                  "not a YCB raw capture (no calibration.h5 here or in a single sub-folder; "
                  "expected calibration.h5, NP<k>_<angle>.h5, masks/ and poses/)");
  }
  std::vector<int> angles = params.angles;
  if (angles.empty()) angles = anglesOnDisk(folder, params.reference_camera, params.angle_step_deg);
  if (angles.empty()) {
    throw IoError(folder + "/poses", "no NP" + std::to_string(params.reference_camera) +
                                         "_<angle>_pose.h5 at a multiple of " +
                                         std::to_string(params.angle_step_deg) + " degrees");
  }
  std::vector<int> cameras = params.cameras;
  if (cameras.empty()) {
    for (int k = 1; k <= 5; ++k) {
      if (fs::exists(fmt::format("{}/NP{}_{}.h5", folder, k, angles.front()))) cameras.push_back(k);
    }
    if (cameras.empty()) {
      throw IoError(folder, fmt::format("no NP<k>_{}.h5 depth image", angles.front()));
    }
  }
  const std::string calibration_path = folder + "/calibration.h5";
  const detail::Hdf5Reader calibration(calibration_path);

  YcbRawCapture capture;
  capture.folder = folder;
  std::vector<PointCloud> views;
  const std::size_t total = cameras.size() * angles.size();
  ProgressReporter progress("YCB raw views", total, 5.0);
  for (int camera : cameras) {
    for (int angle : angles) {
      ViewResult view = loadView(folder, calibration, calibration_path, camera, angle, params);
      capture.views.push_back(view.info);
      if (view.cloud.size() >= 3) views.push_back(std::move(view.cloud));
      progress.step(capture.views.size());
    }
  }
  perception::Scan& scan = capture.scan;
  scan.cloud = perception::fuseViews(views, params.normals);
  scan.object_mask.assign(scan.cloud.size(), 1);
  scan.per_view_normals = true;
  scan.views = capture.views.size();
  scan.source = folder;
  if (scan.cloud.empty()) throw IoError(folder, "no depth pixel falls inside the object masks");
  log().info("{}: {} views ({} cameras x {} angles) fused into {} object points", folder,
             capture.views.size(), cameras.size(), angles.size(), scan.cloud.size());
  return capture;
}

}  // namespace skelgrasp::datasets
