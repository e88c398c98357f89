#include "skelgrasp/perception/rgbd.h"

#include <gtest/gtest.h>

#include <fstream>

#include "skelgrasp/common/error.h"
#include "skelgrasp/perception/depth_camera.h"
#include "skelgrasp/perception/image_io.h"
#include "skelgrasp/perception/scan.h"
#include "test_support.h"

namespace skelgrasp::perception {
namespace {

TEST(Rgbd, BackProjectsAFrontoParallelPlane) {
  PinholeIntrinsics k{500, 500, 9.5, 7.5, 20, 16};
  DepthImage depth(20, 16, 0.8f);
  depth.at(3, 4) = 0.0f;  // missing
  MaskImage mask(20, 16, 255);
  mask.at(5, 5) = 0;
  const Pose camera = lookAt({0, 0, 1}, {0, 0, 0}, Eigen::Vector3d::UnitY());  // looking down -z
  const PointCloud cloud = depthToPointCloud(depth, k, camera, &mask);
  ASSERT_TRUE(cloud.isOrganized());
  EXPECT_FALSE(cloud.points[4 * 20 + 3].allFinite());
  EXPECT_FALSE(cloud.points[5 * 20 + 5].allFinite());
  for (const auto& p : cloud.points) {
    if (p.allFinite()) {
      EXPECT_NEAR(p.z(), 0.2, 1e-6);  // 0.8 m (float) in front of a camera at z = 1
    }
  }
  // Pixel (u, v) lies (u - cx) z / fx to the camera's right.
  const Eigen::Vector3d corner = camera.inverse() * cloud.points[0];
  EXPECT_NEAR(corner.x(), (0 - 9.5) * 0.8 / 500, 1e-7);
  EXPECT_NEAR(corner.y(), (0 - 7.5) * 0.8 / 500, 1e-7);
  EXPECT_LT((cloud.sensor_origin - Eigen::Vector3d(0, 0, 1)).norm(), 1e-12);
  EXPECT_THROW(depthToPointCloud(DepthImage(3, 3, 1.0f), k), InvalidArgument);
}

TEST(Rgbd, ReadsAutolabIntrinsicsAndTransforms) {
  const std::string dir = test::tempDir("rgbd_calib");
  std::ofstream(dir + "/cam.intr") << R"({"_fx": 525.0, "_fy": 520.0, "_cx": 319.5, "_cy": 239.5,
                                          "_width": 640, "_height": 480, "_skew": 0.0})";
  const PinholeIntrinsics k = readIntrinsicsJson(dir + "/cam.intr");
  EXPECT_EQ(k.fy, 520.0);
  EXPECT_EQ(k.width, 640);
  std::ofstream(dir + "/cam.tf") << "cam\nworld\n0.1 0.2 0.3\n1 0 0\n0 0 -1\n0 1 0\n";
  const Pose pose = readTransformText(dir + "/cam.tf");
  EXPECT_LT((pose.translation() - Eigen::Vector3d(0.1, 0.2, 0.3)).norm(), 1e-12);
  EXPECT_LT((pose * Eigen::Vector3d::UnitY() - Eigen::Vector3d(0.1, 0.2, 1.3)).norm(), 1e-9);
  std::ofstream(dir + "/one.txt") << "1 2 3 1 0 0 0\n";
  EXPECT_LT((readTransformText(dir + "/one.txt").translation() - Eigen::Vector3d(1, 2, 3)).norm(),
            1e-12);
  std::ofstream(dir + "/bad.tf") << "cam\nworld\n0 0 0\n1 0 0\n0 2 0\n0 0 1\n";
  EXPECT_THROW(readTransformText(dir + "/bad.tf"), IoError);
  std::ofstream(dir + "/bad.intr") << R"({"fx": 500})";
  EXPECT_THROW(readIntrinsicsJson(dir + "/bad.intr"), IoError);
}

TEST(Rgbd, CaptureDescriptionLoadsDepthMaskAndPose) {
  const std::string dir = test::tempDir("capture");
  DepthImage depth(8, 6, 0.7f);
  writeDepthNpy(dir + "/depth.npy", depth);
  MaskImage mask(8, 6, 0);
  mask.at(2, 2) = mask.at(3, 2) = 255;
  writeMaskImage(dir + "/mask.png", mask);
  std::ofstream(dir + "/capture.json") << R"({"depth": "depth.npy", "mask": "mask.png",
             "intrinsics": {"fx": 100, "fy": 100, "cx": 3.5, "cy": 2.5, "width": 8, "height": 6},
             "camera_to_world": "0 0 1 0 1 0 0"})";
  const Scan scan = loadCapture(dir + "/capture.json");
  ASSERT_EQ(scan.cloud.size(), 48u);
  ASSERT_EQ(scan.object_mask.size(), 48u);
  EXPECT_EQ(std::count(scan.object_mask.begin(), scan.object_mask.end(), 1), 2);
  // Camera at z = 1 turned half a turn about x: it looks down, the points are at z = 0.3.
  EXPECT_NEAR(scan.cloud.points[0].z(), 0.3, 1e-6);

  std::ofstream(dir + "/missing_depth.json") << R"({"depth": "nope.npy", "intrinsics": {}})";
  try {
    loadCapture(dir + "/missing_depth.json");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("nope.npy"), std::string::npos) << e.what();
  }
  std::ofstream(dir + "/no_intrinsics.json") << R"({"depth": "depth.npy"})";
  EXPECT_THROW(loadCapture(dir + "/no_intrinsics.json"), IoError);
  std::ofstream(dir + "/wrong_size.json")
      << R"({"depth": "depth.npy", "intrinsics": {"fx": 100, "fy": 100, "cx": 3.5, "cy": 2.5,
             "width": 640, "height": 480}})";
  EXPECT_THROW(loadCapture(dir + "/wrong_size.json"), IoError);
  writeDepthNpy(dir + "/zeros.npy", DepthImage(8, 6, 0.0f));
  std::ofstream(dir + "/zeros.json") << R"({"depth": "zeros.npy",
             "intrinsics": {"fx": 100, "fy": 100, "cx": 3.5, "cy": 2.5, "width": 8, "height": 6}})";
  EXPECT_THROW(loadCapture(dir + "/zeros.json"), IoError);
}

TEST(Rgbd, InlineIntrinsicsTakeAutolabKeysAndPlausibleValuesOnly) {
  const std::string dir = test::tempDir("capture_intrinsics");
  writeDepthNpy(dir + "/depth.npy", DepthImage(8, 6, 0.7f));
  // The docs allow "_fx"-style keys inline as in .intr files.
  std::ofstream(dir + "/autolab.json") << R"({"depth": "depth.npy", "intrinsics": {"_fx": 100,
             "_fy": 100, "_cx": 3.5, "_cy": 2.5, "_width": 8, "_height": 6}})";
  EXPECT_EQ(readCaptureDescription(dir + "/autolab.json").intrinsics.width, 8);
  const auto refused = [&](const std::string& intrinsics, const std::string& expected) {
    SCOPED_TRACE(intrinsics);
    std::ofstream(dir + "/bad.json")
        << R"({"depth": "depth.npy", "intrinsics": )" << intrinsics << "}";
    try {
      readCaptureDescription(dir + "/bad.json");
      ADD_FAILURE() << "accepted";
    } catch (const IoError& e) {
      EXPECT_EQ(e.path(), dir + "/bad.json");
      EXPECT_NE(e.problem().find(expected), std::string::npos) << e.what();
    }
  };
  const std::string rest = R"("width": 8, "height": 6})";
  refused(R"({"fx": 100, "fy": 100, "cx": 1e308, "cy": 2.5, )" + rest, "cx = 1e+308");
  refused(R"({"fx": 100, "fy": 100, "cx": -1e6, "cy": 2.5, )" + rest, "cx = -1e+06");
  refused(R"({"fx": 1e308, "fy": 100, "cx": 3.5, "cy": 2.5, )" + rest, "fx = 1e+308");
  refused(R"({"fx": 1e-308, "fy": 100, "cx": 3.5, "cy": 2.5, )" + rest, "fx = 1e-308");
  refused(R"({"fx": 100, "fy": 100, "cx": 3.5, "cy": 2.5, "width": 8.5, "height": 6})",
          "width = 8.5 is not a whole number");
  refused(R"({"fx": 100, "fy": 100, "cx": 3.5, "cy": 2.5, "width": 8, "height": 4e9})",
          "height = 4e+09 is not a whole number of pixels in [1, 20000]");
  refused(R"({"fx": "100", "fy": 100, "cx": 3.5, "cy": 2.5, )" + rest, "'fx' is not a number");
  refused(R"({"fy": 100, "cx": 3.5, "cy": 2.5, )" + rest, "lack a numeric 'fx'");
}

TEST(Rgbd, DepthImageSizeComesFromTheHeaderAndIsCapped) {
  const std::string dir = test::tempDir("depth_size");
  writeDepthNpy(dir + "/depth.npy", DepthImage(8, 6, 0.7f));
  const ImageSize size = readDepthImageSize(dir + "/depth.npy");
  EXPECT_EQ(size.width, 8);
  EXPECT_EQ(size.height, 6);
  // A header declaring 30000 x 30000 with four pixels of data: refused by the cap, not by the
  // data's length (a sparse file would hold it).
  std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (30000, 30000), }";
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::ofstream huge(dir + "/huge.npy", std::ios::binary);
  huge << std::string("\x93NUMPY\x01\x00", 8) << static_cast<char>(header.size() & 0xff)
       << static_cast<char>(header.size() >> 8) << header << std::string(16, '\0');
  huge.close();
  for (const auto& read : {+[](const std::string& p) { readDepthImageSize(p); },
                           +[](const std::string& p) { readDepthNpy(p); }}) {
    try {
      read(dir + "/huge.npy");
      ADD_FAILURE() << "accepted";
    } catch (const IoError& e) {
      EXPECT_NE(e.problem().find("exceeds the largest image side of 20000"), std::string::npos)
          << e.what();
    }
  }
}

TEST(Rgbd, PrimesenseCalibrationLooksDown) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  const std::string calib = test::sharedDataDir() + "/captures/gqcnn_primesense/calib/";
  const PinholeIntrinsics k = readIntrinsicsJson(calib + "primesense.intr");
  EXPECT_EQ(k.fx, 525.0);
  EXPECT_EQ(k.cx, 319.5);
  const Pose pose = readTransformText(calib + "primesense.tf");
  EXPECT_NEAR(pose.linear().determinant(), 1.0, 1e-9);
  EXPECT_LT((pose.linear() * Eigen::Vector3d::UnitZ()).z(), -0.97);  // optical axis points down
  EXPECT_NEAR(pose.translation().z(), 0.872913, 1e-6);
}

}  // namespace
}  // namespace skelgrasp::perception
