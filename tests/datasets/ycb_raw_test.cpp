#include "skelgrasp/datasets/ycb_raw.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/datasets/input.h"
#include "skelgrasp/datasets/ycb_raw_fixture.h"
#include "skelgrasp/geometry/mesh_query.h"
#include "skelgrasp/geometry/mesh_topology.h"
#include "skelgrasp/geometry/surface_distance.h"
#include "skelgrasp/pipeline/reconstruct_scan.h"
#include "test_support.h"

namespace skelgrasp::datasets {
namespace {

namespace fs = std::filesystem;

struct Fixture {
  std::string dir;
  TriangleMesh object;
};

// A 7 cm x 10 cm cylinder on a turntable seen by NP1, NP3 and NP5 at 0, 90, 180 and 270 degrees.
Fixture writeFixture(const std::string& name, bool noise) {
  Fixture f;
  f.dir = test::tempDir(name) + "/000_test_cylinder";
  YcbRawFixtureSpec spec;
  spec.noise = noise;
  f.object = writeYcbRawFixture(f.dir, spec);
  return f;
}

// ctest runs every test in its own process, in parallel: each test writes its own fixture.
Fixture clean() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return writeFixture(std::string("ycb_raw_") + info->name(), false);
}

TEST(YcbRaw, FixtureHasTheYcbLayout) {
  const fs::path dir = clean().dir;
  const std::string elsewhere = test::tempDir("not_ycb");
  for (const char* f : {"calibration.h5", "NP1_0.h5", "NP5_270.h5", "NP3_90.jpg",
                        "masks/NP3_180_mask.pbm", "poses/NP5_90_pose.h5", "poses/turntable.h5"}) {
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  }
  EXPECT_EQ(findYcbRawFolder(dir.string()), dir.string());
  EXPECT_EQ(findYcbRawFolder(dir.parent_path().string()), dir.string());  // "<id>/" inside
  EXPECT_EQ(findYcbRawFolder(elsewhere), "");
}

TEST(YcbRaw, FusedPointsLieOnTheKnownShapeFromAllSides) {
  const Fixture fixture = clean();
  const YcbRawCapture capture = loadYcbRaw(fixture.dir);
  ASSERT_EQ(capture.views.size(), 12u);  // the three units present, four angles
  const PointCloud& cloud = capture.scan.cloud;
  ASSERT_GT(cloud.size(), 20000u);
  ASSERT_TRUE(cloud.hasNormals());
  EXPECT_TRUE(capture.scan.per_view_normals);
  const geometry::MeshQuery truth(fixture.object);
  double worst = 0;
  int sectors[8] = {0};
  std::size_t side = 0, outward = 0, close = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d& p = cloud.points[i];
    const double d = truth.distance(p);
    worst = std::max(worst, d);
    close += d < 0.002 ? 1 : 0;
    if (p.z() > 0.01 && p.z() < 0.09) {
      ++sectors[static_cast<int>((std::atan2(p.y(), p.x()) + kPi) / (kPi / 4)) % 8];
      // Side points: normals point away from the axis (each view oriented its own); the
      // exceptions are a few points NP5 sees from above next to the rim, whose neighbourhood is
      // mostly top.
      const Eigen::Vector3d radial(p.x(), p.y(), 0);
      ++side;
      outward += cloud.normals[i].dot(radial.normalized()) > 0.5 ? 1 : 0;
    }
  }
  // The transform chain (IR -> NP5 -> turntable, per-unit depth scales of 0.98-1.02) is exact to
  // the 0.1 mm depth units, and the masks keep the turntable out. Measured: 99.9 % of the points
  // within 2 mm of the cylinder; the worst, 8 mm, is turntable next to the base that NP5's RGB
  // camera sees hidden behind the cylinder's side while its IR camera does not see that side.
  EXPECT_GT(static_cast<double>(close), 0.995 * static_cast<double>(cloud.size()));
  std::cout << "[ ycb raw  ] within 2 mm: " << 100.0 * close / cloud.size() << "%, worst "
            << 1000 * worst << " mm" << std::endl;
  EXPECT_LT(worst, 0.01);
  for (int s : sectors) EXPECT_GT(s, 200);  // seen all around
  EXPECT_GT(static_cast<double>(outward), 0.99 * static_cast<double>(side));
  for (const auto& v : capture.views)
    EXPECT_GT(v.object_points, 500u) << v.camera << "/" << v.angle;
}

TEST(YcbRaw, NoisyCaptureReconstructsTheCylinder) {
  const Fixture noisy = writeFixture("ycb_raw_noisy", true);
  InputKind kind;
  const perception::Scan scan = loadInput(noisy.dir, {}, &kind);
  EXPECT_EQ(kind, InputKind::kYcbRaw);
  const auto r = pipeline::reconstructScan(scan);
  ASSERT_TRUE(r.status.ok()) << r.status.message;
  const auto& m = r.objects.at(0).meshing;
  EXPECT_TRUE(geometry::analyzeTopology(m.mesh).closed);
  const auto chamfer = geometry::chamferDistance(m.mesh, noisy.object, 10000);
  std::cout << "[ ycb raw  ] fixture cylinder: chamfer " << 1000 * chamfer.symmetric_m << " mm, "
            << 100 * m.report.observed_fraction << "% observed" << std::endl;
  // Measured 1.0 mm: the turntable hides the bottom, which the surface closes flat.
  EXPECT_LT(chamfer.symmetric_m, 0.003);
}

TEST(YcbRaw, MissingOrBrokenPiecesAreNamed) {
  const Fixture f = writeFixture("ycb_raw_broken", false);
  fs::remove(fs::path(f.dir) / "masks/NP3_90_mask.pbm");
  try {
    loadYcbRaw(f.dir);
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("NP3_90_mask.pbm"), std::string::npos) << e.what();
  }
  YcbRawParams only_np2;
  only_np2.cameras = {2};
  EXPECT_THROW(loadYcbRaw(f.dir, only_np2), IoError);  // NP2 is not in the fixture
  std::ofstream(fs::path(f.dir) / "calibration.h5") << "not hdf5";
  try {
    loadYcbRaw(f.dir);
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("calibration.h5"), std::string::npos) << e.what();
  }
  EXPECT_THROW(loadYcbRaw(test::tempDir("ycb_raw_empty")), IoError);
  YcbRawParams bad;
  bad.cameras = {6};
  EXPECT_THROW(loadYcbRaw(f.dir, bad), InvalidArgument);
}

}  // namespace
}  // namespace skelgrasp::datasets
