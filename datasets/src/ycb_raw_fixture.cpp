#include "skelgrasp/datasets/ycb_raw_fixture.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>

#include "hdf5_io.h"
#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/perception/depth_camera.h"
#include "skelgrasp/perception/image_io.h"

namespace skelgrasp::datasets {
namespace {

Eigen::Matrix3d rotationZ(double degrees) {
  return Eigen::AngleAxisd(radiansFromDegrees(degrees), Eigen::Vector3d::UnitZ())
      .toRotationMatrix();
}

Eigen::Matrix3d cameraMatrix(const perception::PinholeIntrinsics& k) {
  Eigen::Matrix3d m;
  m << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1;
  return m;
}

}  // namespace

TriangleMesh writeYcbRawFixture(const std::string& folder, const YcbRawFixtureSpec& spec) {
  if (spec.cameras.empty() || spec.angles.empty() || spec.elevation_deg.size() < 5 ||
      spec.depth_scale.size() < 5) {
    throw InvalidArgument("writeYcbRawFixture: cameras, angles, 5 elevations and 5 scales needed");
  }
  TriangleMesh object = spec.object;
  if (object.empty()) {
    object = geometry::shapes::makeCylinder(0.035, 0.10, 48, 8);
    object.transform(Pose(Eigen::Translation3d(0, 0, 0.05)));
  }
  TriangleMesh turntable = geometry::shapes::makeCylinder(0.2, 0.02, 64, 1);
  turntable.transform(Pose(Eigen::Translation3d(0, 0, -0.01)));

  namespace fs = std::filesystem;
  fs::create_directories(fs::path(folder) / "masks");
  fs::create_directories(fs::path(folder) / "poses");

  // Rig (world) frame = turntable frame at angle 0. RGB camera k looks at a point above the centre.
  const Eigen::Vector3d target(0, 0, 0.05);
  std::vector<Pose> rgb_to_world(6), ir_to_world(6);
  for (int k = 1; k <= 5; ++k) {
    const double e = radiansFromDegrees(spec.elevation_deg[k - 1]);
    const Eigen::Vector3d eye =
        target + spec.distance_m * Eigen::Vector3d(std::cos(e), 0.0, std::sin(e));
    rgb_to_world[k] = perception::lookAt(eye, target, Eigen::Vector3d::UnitZ());
    ir_to_world[k] = rgb_to_world[k] * Pose(Eigen::Translation3d(-spec.ir_offset_m, 0, 0));
  }
  perception::DepthCameraParams ir_camera;  // 640 x 480 Carmine depth
  ir_camera.intrinsics.fx = ir_camera.intrinsics.fy = 570.0;
  ir_camera.noise.enabled = spec.noise;
  ir_camera.noise.seed = spec.seed;
  ir_camera.min_range_m = 0.2;
  perception::DepthCameraParams rgb_camera;  // 1280 x 1024 colour images and masks
  rgb_camera.intrinsics = {1050.0, 1050.0, 639.5, 511.5, 1280, 1024};
  rgb_camera.noise.enabled = false;
  rgb_camera.min_range_m = 0.05;

  {
    detail::Hdf5Writer calibration(folder + "/calibration.h5");
    const Pose reference = rgb_to_world[5];
    for (int k = 1; k <= 5; ++k) {
      const std::string np = "NP" + std::to_string(k);
      calibration.matrix(np + "_ir_K", cameraMatrix(ir_camera.intrinsics));
      calibration.matrix(np + "_rgb_K", cameraMatrix(rgb_camera.intrinsics));
      calibration.matrix(np + "_rgb_d", Eigen::MatrixXd::Zero(1, 5));
      calibration.scalar(np + "_ir_depth_scale", spec.depth_scale[k - 1]);
      calibration.matrix("H_" + np + "_from_NP5", (rgb_to_world[k].inverse() * reference).matrix());
      calibration.matrix("H_" + np + "_ir_from_NP5",
                         (ir_to_world[k].inverse() * reference).matrix());
    }
  }
  {
    detail::Hdf5Writer table(folder + "/poses/turntable.h5");
    table.matrix("center", Eigen::MatrixXd::Zero(3, 1));
    table.matrix("normal", Eigen::Vector3d::UnitZ());
  }

  for (int angle : spec.angles) {
    // The turntable turned by `angle`: in the turntable frame the rig turned by -angle.
    Pose world_to_table = Pose::Identity();
    world_to_table.linear() = rotationZ(-angle);
    {
      detail::Hdf5Writer pose(fmt::format("{}/poses/NP5_{}_pose.h5", folder, angle));
      pose.matrix("H_table_from_reference_camera", (world_to_table * rgb_to_world[5]).matrix());
    }
    const std::vector<TriangleMesh> scene = {object, turntable};
    for (int k : spec.cameras) {
      if (k < 1 || k > 5) throw InvalidArgument("writeYcbRawFixture: cameras are 1..5");
      ir_camera.noise.seed = spec.seed + 1000 * static_cast<std::uint64_t>(k) + angle;
      const auto ir = perception::renderDepth(scene, world_to_table * ir_to_world[k], ir_camera);
      perception::Image<std::uint16_t> raw(ir.depth.width, ir.depth.height, 0);
      const double units = 1e-4 * spec.depth_scale[k - 1];
      for (std::size_t i = 0; i < raw.data.size(); ++i) {
        const double z = ir.depth.data[i];
        if (std::isfinite(z) && z > 0)
          raw.data[i] = static_cast<std::uint16_t>(std::lround(z / units));
      }
      detail::Hdf5Writer(fmt::format("{}/NP{}_{}.h5", folder, k, angle)).uint16Image("depth", raw);

      const auto rgb = perception::renderDepth(scene, world_to_table * rgb_to_world[k], rgb_camera);
      perception::MaskImage mask(rgb.labels.width, rgb.labels.height);
      perception::Image<Rgb> colour(rgb.labels.width, rgb.labels.height);
      for (std::size_t i = 0; i < mask.data.size(); ++i) {
        const bool is_object = rgb.labels.data[i] == 0;
        mask.data[i] = is_object ? 0 : 255;  // object black, as in the YCB masks
        colour.data[i] = is_object                 ? Rgb{200, 60, 40}
                         : rgb.labels.data[i] == 1 ? Rgb{90, 90, 90}
                                                   : Rgb{230, 230, 230};
      }
      perception::writeMaskImage(fmt::format("{}/masks/NP{}_{}_mask.pbm", folder, k, angle), mask);
      perception::writeColorImage(fmt::format("{}/NP{}_{}.jpg", folder, k, angle), colour);
    }
  }
  return object;
}

}  // namespace skelgrasp::datasets
