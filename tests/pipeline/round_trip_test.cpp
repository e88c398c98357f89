// Virtual scans of known meshes from several views, with Primesense-like noise, reconstructed and
// compared with the original: the end-to-end accuracy of perception + reconstruction.
#include <gtest/gtest.h>

#include <filesystem>

#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/mesh_topology.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/geometry/surface_distance.h"
#include "skelgrasp/perception/depth_camera.h"
#include "skelgrasp/pipeline/reconstruct_scan.h"
#include "test_support.h"

namespace skelgrasp::pipeline {
namespace {

// Eight views around the object's centre, 0.6 m away: six 30 degrees above it, two 30 below.
perception::Scan virtualScan(const TriangleMesh& mesh, std::uint64_t seed) {
  const Eigen::Vector3d centre = mesh.bounds().center();
  std::vector<Pose> poses = perception::orbitPoses(centre, 0.6, 0.52, 6);
  for (const auto& p : perception::orbitPoses(centre, 0.6, -0.52, 2, 0.8)) poses.push_back(p);
  std::vector<PointCloud> views;
  perception::DepthCameraParams camera;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    camera.noise.seed = seed + i;
    views.push_back(perception::renderDepth({mesh}, poses[i], camera).cloud);
  }
  perception::Scan scan;
  scan.cloud = perception::fuseViews(views);
  scan.object_mask.assign(scan.cloud.size(), 1);
  scan.per_view_normals = true;
  scan.views = views.size();
  return scan;
}

struct RoundTrip {
  ReconstructionResult result;
  geometry::ChamferDistance chamfer;
};

RoundTrip roundTrip(const TriangleMesh& mesh, std::uint64_t seed) {
  RoundTrip out;
  out.result = reconstructScan(virtualScan(mesh, seed));
  if (out.result.status.ok()) {
    out.chamfer =
        geometry::chamferDistance(out.result.objects.at(0).meshing.mesh, mesh, 20000, seed);
  }
  return out;
}

TEST(RoundTrip, GeneratedShapesComeBackWithinAFewMillimetres) {
  for (const std::string name : {"bottle", "hammer"}) {
    const TriangleMesh shape = geometry::regularise(geometry::shapes::makeNamedShape(name)).mesh;
    const RoundTrip r = roundTrip(shape, 100);
    ASSERT_TRUE(r.result.status.ok()) << name << ": " << r.result.status.message;
    const auto& m = r.result.objects[0].meshing;
    EXPECT_TRUE(geometry::analyzeTopology(m.mesh).closed);
    EXPECT_GT(m.report.observed_fraction, 0.9) << name;  // seen from all around
    std::cout << "[ chamfer  ] " << name << ": " << 1000 * r.chamfer.symmetric_m << " mm (p95 "
              << 1000 * std::max(r.chamfer.a_to_b_p95_m, r.chamfer.b_to_a_p95_m) << " mm)"
              << std::endl;
    EXPECT_LT(r.chamfer.symmetric_m, 0.001) << name;  // measured 0.22 mm (bottle), 0.29 (hammer)
  }
}

TEST(RoundTrip, YcbMeshesComeBackWithinAFewMillimetres) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  for (const std::string id :
       {"006_mustard_bottle", "025_mug", "011_banana", "035_power_drill", "003_cracker_box"}) {
    const TriangleMesh mesh = loadMesh(test::sharedDataDir() + "/objects/ycb/" + id + ".ply");
    const RoundTrip r = roundTrip(mesh, 200);
    ASSERT_TRUE(r.result.status.ok()) << id << ": " << r.result.status.message;
    const auto& m = r.result.objects[0].meshing;
    EXPECT_TRUE(geometry::analyzeTopology(m.mesh).closed) << id;
    std::cout << "[ chamfer  ] " << id << ": " << 1000 * r.chamfer.symmetric_m << " mm (p95 "
              << 1000 * std::max(r.chamfer.a_to_b_p95_m, r.chamfer.b_to_a_p95_m) << " mm), "
              << m.report.vertices << " vertices, " << 100 * m.report.observed_fraction
              << "% observed, " << r.result.total_s << " s" << std::endl;
    // Measured symmetric Chamfer distances: mustard bottle 0.22 mm, banana 0.22, power drill 0.35,
    // cracker box 0.29; the mug 2.7 mm because no view sees the bottom of its cavity, which the
    // surface closes over.
    EXPECT_LT(r.chamfer.symmetric_m, id == "025_mug" ? 0.004 : 0.001) << id;
  }
}

}  // namespace
}  // namespace skelgrasp::pipeline
