#include "skelgrasp/perception/cloud_io.h"

#include <gtest/gtest.h>

#include <spdlog/sinks/ostream_sink.h>

#include <fstream>
#include <random>
#include <sstream>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/perception/cloud_ops.h"
#include "test_support.h"

namespace skelgrasp::perception {
namespace {

PointCloud organisedGrid() {
  PointCloud cloud;
  cloud.width = 4;
  cloud.height = 3;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int v = 0; v < 3; ++v) {
    for (int u = 0; u < 4; ++u) {
      const bool hole = u == 1 && v == 2;
      cloud.points.push_back(hole ? Eigen::Vector3d::Constant(nan)
                                  : Eigen::Vector3d(0.01 * u, 0.01 * v, 0.5 + 0.001 * u));
      cloud.colors.push_back({static_cast<std::uint8_t>(10 * u), static_cast<std::uint8_t>(v), 7});
      cloud.labels.push_back(static_cast<std::uint32_t>(100 + u + 4 * v));
      cloud.normals.push_back(Eigen::Vector3d(0, 0, -1));
    }
  }
  cloud.sensor_origin = {0.1, 0.2, 0.3};
  cloud.sensor_orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX()));
  return cloud;
}

class PcdRoundTrip : public ::testing::TestWithParam<PcdEncoding> {};

TEST_P(PcdRoundTrip, KeepsFieldsOrganisationAndViewpoint) {
  const PointCloud cloud = organisedGrid();
  const std::string path =
      test::tempDir("pcd_" + std::to_string(static_cast<int>(GetParam()))) + "/grid.pcd";
  savePointCloud(path, cloud, GetParam());
  CloudLoadInfo info;
  const PointCloud loaded = loadPointCloud(path, {}, &info);
  EXPECT_TRUE(loaded.isOrganized());
  EXPECT_EQ(loaded.width, 4u);
  EXPECT_EQ(loaded.height, 3u);
  EXPECT_EQ(info.points, 12u);
  EXPECT_EQ(info.finite_points, 11u);
  ASSERT_TRUE(loaded.hasColors() && loaded.hasLabels() && loaded.hasNormals());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!cloud.points[i].allFinite()) {
      EXPECT_FALSE(loaded.points[i].allFinite());
      continue;
    }
    EXPECT_LT((loaded.points[i] - cloud.points[i]).norm(), 1e-6);
    EXPECT_EQ(loaded.colors[i], cloud.colors[i]);
    EXPECT_EQ(loaded.labels[i], cloud.labels[i]);
    EXPECT_LT((loaded.normals[i] - cloud.normals[i]).norm(), 1e-6);
  }
  EXPECT_LT((loaded.sensor_origin - cloud.sensor_origin).norm(), 1e-6);
  EXPECT_LT(loaded.sensor_orientation.angularDistance(cloud.sensor_orientation), 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Encodings, PcdRoundTrip,
                         ::testing::Values(PcdEncoding::kAscii, PcdEncoding::kBinary,
                                           PcdEncoding::kBinaryCompressed));

TEST(CloudIo, ReadsPlyVertices) {
  const std::string path = test::tempDir("ply_cloud") + "/pts.ply";
  std::ofstream(path)
      << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
         "property float y\nproperty float z\nend_header\n0 0 0\n0.1 0 0\n0 0.2 0\n";
  const PointCloud cloud = loadPointCloud(path);
  ASSERT_EQ(cloud.size(), 3u);
  EXPECT_NEAR(cloud.points[2].y(), 0.2, 1e-6);
  EXPECT_FALSE(cloud.isOrganized());
}

TEST(CloudIo, MillimetreCloudsAreDetectedAndScaled) {
  PointCloud cloud;
  for (int i = 0; i < 10; ++i) cloud.points.emplace_back(30.0 * i, 10.0, 700.0 + i);  // mm
  cloud.sensor_origin = {0, 0, 0};
  const std::string path = test::tempDir("mm_cloud") + "/mm.pcd";
  savePointCloud(path, cloud);
  CloudLoadInfo info;
  const PointCloud metres = loadPointCloud(path, {}, &info);
  EXPECT_TRUE(info.units_guessed);
  EXPECT_DOUBLE_EQ(info.scale_to_meters, 1e-3);
  EXPECT_NEAR(metres.points[9].x(), 0.27, 1e-6);
  CloudLoadOptions keep;
  keep.units = LengthUnit::kMeters;
  EXPECT_NEAR(loadPointCloud(path, keep).points[9].x(), 270.0, 1e-4);
}

struct BadCloud {
  std::string name;
  std::string file;
  std::string content;
  std::string expected;
};

class CloudIoBadInput : public ::testing::TestWithParam<BadCloud> {};

TEST_P(CloudIoBadInput, ThrowsIoErrorNamingFileAndProblem) {
  const auto& c = GetParam();
  const std::string path = test::tempDir("bad_cloud_" + c.name) + "/" + c.file;
  if (!c.content.empty()) std::ofstream(path, std::ios::binary) << c.content;
  try {
    loadPointCloud(path);
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_EQ(e.path(), path);
    EXPECT_NE(e.problem().find(c.expected), std::string::npos) << e.problem();
  }
}

const std::string kHeader =
    "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n";

INSTANTIATE_TEST_SUITE_P(
    Cases, CloudIoBadInput,
    ::testing::Values(
        BadCloud{"missing", "nothing.pcd", "", "no such file"},
        BadCloud{"format", "cloud.xyz", "1 2 3\n", "unknown point cloud format"},
        BadCloud{"garbage", "garbage.pcd", "this is not a point cloud\n",
                 "PCD header has no DATA line"},
        BadCloud{"truncated_binary", "short.pcd",
                 kHeader + "WIDTH 100\nHEIGHT 1\nPOINTS 100\nDATA binary\n" + std::string(40, 'x'),
                 "only 40 bytes follow the header"},
        BadCloud{"truncated_compressed", "short_lzf.pcd",
                 kHeader + "WIDTH 100\nHEIGHT 1\nPOINTS 100\nDATA binary_compressed\n" +
                     std::string(6, '\x01'),
                 "no compressed data"},
        BadCloud{"no_points", "empty.pcd", kHeader + "WIDTH 0\nHEIGHT 1\nPOINTS 0\nDATA ascii\n",
                 "no points"},
        BadCloud{"no_xyz", "labels.pcd",
                 "VERSION 0.7\nFIELDS label\nSIZE 4\nTYPE U\nCOUNT 1\nWIDTH 2\nHEIGHT 1\n"
                 "POINTS 2\nDATA ascii\n1\n2\n",
                 "no 'x' field"},
        // Declared sizes are checked against the file before PCL allocates (issue 13).
        BadCloud{"binary_declares_millions", "millions.pcd",
                 kHeader + "WIDTH 5000000\nHEIGHT 1\nPOINTS 5000000\nDATA binary\n" +
                     std::string(120, '\x01'),
                 "declares 5000000 points of 12 bytes (60000000 bytes of binary data), but only "
                 "120 bytes follow"},
        BadCloud{"ascii_declares_millions", "millions_ascii.pcd",
                 kHeader + "WIDTH 3000\nHEIGHT 1000\nPOINTS 3000000\nDATA ascii\n0 0 0\n1 1 1\n",
                 "declares 3000000 points"},
        BadCloud{"compressed_size_mismatch", "mismatch.pcd",
                 kHeader + "WIDTH 4000000\nHEIGHT 1\nPOINTS 4000000\nDATA binary_compressed\n" +
                     std::string("\x04\x00\x00\x00\x10\x00\x00\x00", 8) + std::string(4, 'x'),
                 "compressed data says 16 bytes"},
        BadCloud{"negative_width", "negative.pcd",
                 kHeader + "WIDTH -1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n0 0 0\n",
                 "WIDTH is negative"},
        // PCL writes past its buffer on these (fuzz/regressions/cloud_reader/pcd-*).
        BadCloud{
            "repeated_fields", "twice.pcd",
            kHeader + "WIDTH 2\nHEIGHT 1\nPOINTS 2\nFIELDS x y z w\nDATA ascii\n0 0 0\n1 1 1\n",
            "PCD header: FIELDS appears twice"},
        BadCloud{"unknown_data", "data.pcd",
                 kHeader + "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA asci\n0 0 0\n1 1 1\n",
                 "DATA must be ascii, binary or binary_compressed"},
        BadCloud{"size_count", "sizes.pcd",
                 "VERSION 0.7\nFIELDS x y z\nSIZE 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\n"
                 "HEIGHT 1\nPOINTS 1\nDATA ascii\n0 0 0\n",
                 "SIZE has 2 entries for 3 FIELDS"},
        // PCL allocates every declared point when SIZE and WIDTH are missing (fuzz/regressions/
        // cloud_reader/pcd_points_without_size_or_width).
        BadCloud{"points_without_size", "nosize.pcd",
                 "VERSION 0.7\nFIELDS x\nPOINTS 5000000\nDATA ascii\n0 0 0\n",
                 "declares 5000000 points"},
        // PCL copies each field by its type's size whatever SIZE says (fuzz/regressions/
        // cloud_reader/pcd_field_size_zero_overflow).
        BadCloud{"field_size_zero", "size0.pcd",
                 "VERSION 0.7\nFIELDS x y z\nSIZE 4 0 0\nTYPE F F F\nPOINTS 3\nDATA ascii\n0 0 0\n"
                 "0.1 0 0\n0 0.1 0\n",
                 "field 2 has SIZE 0"},
        // Without TYPE PCL picks the type itself (fuzz/regressions/cloud_reader/
        // pcd_size_without_type_overflow).
        BadCloud{"size_without_type", "notype.pcd",
                 "VERSION 0.7\nFIELDS x y z\nSIZE 8 1 1\nWIDTH 3\nHEIGHT 1\nPOINTS 3\n"
                 "DATA ascii\n0 0 0\n0.1 0 0\n0 0.1 0\n",
                 "PCD header: SIZE without TYPE"},
        BadCloud{"float_field_of_two_bytes", "f2.pcd",
                 "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 2\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\n"
                 "HEIGHT 1\nPOINTS 1\nDATA ascii\n0 0 0\n",
                 "field 3 has SIZE 2 and TYPE F"},
        // PCL reads COLUMNS (and any word starting with it) as FIELDS (fuzz/regressions/
        // cloud_reader/pcd_columns_redefines_fields).
        BadCloud{"columns_after_fields", "columns.pcd",
                 "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\n"
                 "HEIGHT 1\nCOLUMNSNT 0 0 0 1\nPOINTS 1\nDATA ascii\n0 0 0\n",
                 "PCD header: FIELDS appears twice"},
        // PCL allocates what POINTS declares before it finds that DATA is missing (fuzz/
        // regressions/cloud_reader/pcd_no_data_line_declares_335e6_points).
        BadCloud{"no_data_line", "nodata.pcd",
                 "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 335863712\nHEIGHT 1\n"
                 "POINTS 335863712\nDAT ascii\n0 0 0\n",
                 "PCD header has no DATA line"},
        // PCL takes the first word of POINTS and ignores the rest (fuzz/regressions/cloud_reader/
        // pcd_points_with_three_words_declares_5e9).
        BadCloud{"points_with_more_words", "points.pcd",
                 "VERSION 0.7\nFIELDS x y z\nPOINTS 5000000000 0 0\nDATA ascii\n0 0 0\n",
                 "PCD header: POINTS must be one count, not 3 words"},
        BadCloud{"width_with_more_words", "width.pcd",
                 "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1 9\nHEIGHT 1\n"
                 "POINTS 1\nDATA ascii\n0 0 0\n",
                 "PCD header: WIDTH must be one count, not 2 words"},
        BadCloud{"ply_without_z", "flat.ply",
                 "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                 "end_header\n0 0\n1 1\n",
                 "PLY vertex element has no 'z' property"},
        BadCloud{"ply_declares_millions", "millions.ply",
                 "ply\nformat binary_little_endian 1.0\nelement vertex 4000000\nproperty float x\n"
                 "property float y\nproperty float z\nend_header\n" +
                     std::string(36, '\x01'),
                 "declares 4000000 'vertex' elements"}),
    [](const auto& info) { return info.param.name; });

TEST(CloudIo, FilesDeclaringMoreThanTheLimitAreRefusedUnread) {
  const std::string path = test::tempDir("cloud_over_limit") + "/grid.pcd";
  PointCloud cloud;
  for (int i = 0; i < 100; ++i) cloud.points.emplace_back(0.01 * i, 0, 0.5);
  savePointCloud(path, cloud, PcdEncoding::kBinary);
  CloudLoadOptions options;
  options.max_points = 50;
  try {
    loadPointCloud(path, options);
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_EQ(e.path(), path);
    EXPECT_NE(e.problem().find("declares 100 points, more than the limit of 50"), std::string::npos)
        << e.problem();
  }
}

// A legal scan of a few million points loads, voxel-downsampled under the cap, with a warning.
TEST(CloudIo, MillionsOfPointsAreVoxelDownsampledOnLoad) {
  constexpr std::size_t kPoints = 3'000'000;
  const std::string path = test::tempDir("cloud_three_million") + "/scan.pcd";
  {
    // Points on a 0.3 m sphere, written as a binary PCD by hand (no 3M-point PointCloud copy).
    std::ofstream out(path, std::ios::binary);
    out << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " << kPoints
        << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << kPoints << "\nDATA binary\n";
    std::mt19937 rng(13);
    std::normal_distribution<float> gauss(0.0f, 1.0f);
    std::vector<float> xyz(3 * kPoints);
    for (std::size_t i = 0; i < kPoints; ++i) {
      Eigen::Vector3f p(gauss(rng), gauss(rng), gauss(rng));
      p = 0.3f * p.normalized();
      xyz[3 * i] = p.x();
      xyz[3 * i + 1] = p.y();
      xyz[3 * i + 2] = p.z();
    }
    out.write(reinterpret_cast<const char*>(xyz.data()),
              static_cast<std::streamsize>(xyz.size() * sizeof(float)));
  }
  std::ostringstream warnings;
  auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(warnings);
  log().sinks().push_back(sink);
  CloudLoadInfo info;
  const CloudLoadOptions options;
  const PointCloud cloud = loadPointCloud(path, options, &info);
  log().sinks().pop_back();

  EXPECT_EQ(info.points_in_file, kPoints);
  EXPECT_EQ(info.points, cloud.size());
  EXPECT_LE(cloud.size(), options.voxel_above_points);
  EXPECT_GT(cloud.size(), options.voxel_above_points / 10);  // downsampled, not decimated away
  EXPECT_GT(info.voxel_leaf_m, 0);
  for (const auto& p : cloud.points) ASSERT_NEAR(p.norm(), 0.3, info.voxel_leaf_m);
  EXPECT_NE(warnings.str().find("3000000 points exceed the load limit of 2000000"),
            std::string::npos)
      << warnings.str();
  EXPECT_NE(warnings.str().find("voxel-downsampled"), std::string::npos) << warnings.str();
}

TEST(CloudIo, RealScansKeepLayoutLabelsAndViewpoint) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  const std::string root = test::sharedDataDir() + "/scans/pcd/";
  // Counts from the data's SOURCES.md.
  CloudLoadInfo info;
  const PointCloud osd = loadPointCloud(root + "osd_test2.pcd", {}, &info);
  EXPECT_EQ(osd.width, 640u);
  EXPECT_EQ(osd.height, 480u);
  EXPECT_EQ(info.finite_points, 188026u);
  ASSERT_TRUE(osd.hasLabels() && osd.hasColors());
  std::size_t object_one = 0;
  for (auto l : osd.labels) object_one += l == 20 ? 1 : 0;
  EXPECT_EQ(object_one, 15612u);
  EXPECT_FALSE(info.units_guessed);

  const PointCloud mug =
      loadPointCloud(root + "pcl_table_scene_mug_stereo_textured.pcd", {}, &info);
  EXPECT_EQ(info.finite_points, 209280u);
  // VIEWPOINT 0 0 0 0 1 0 0: a half turn about x, kept as the sensor orientation.
  EXPECT_NEAR(std::abs(mug.sensor_orientation.x()), 1.0, 1e-6);

  const PointCloud krylon = loadPointCloud(root + "gpd_krylon.pcd");  // ascii, rgb as integer
  EXPECT_EQ(krylon.size(), 4467u);
  EXPECT_FALSE(krylon.isOrganized());
}

}  // namespace
}  // namespace skelgrasp::perception
