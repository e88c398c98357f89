// The skeleton and surface planners on shapes with known answers, and their bookkeeping.
#include <gtest/gtest.h>

#include <numeric>

#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/planning/planners.h"
#include "skelgrasp/skeleton/extraction.h"
#include "test_support.h"

namespace skelgrasp::grasping {
namespace {

struct Planned {
  TriangleMesh mesh;
  std::unique_ptr<GraspObject> object;
  skeleton::SkeletonResult skeleton;
  PlanResult result;
};

Planned planOn(const TriangleMesh& mesh, const HandModel& hand, SkeletonPlannerParams params = {}) {
  Planned p;
  p.mesh = mesh;
  p.object = std::make_unique<GraspObject>(mesh);
  p.skeleton = skeleton::extractSkeleton(mesh);
  EXPECT_TRUE(p.skeleton.status.ok()) << p.skeleton.status.message;
  p.result = planSkeletonGrasps(hand, *p.object, p.skeleton.skeleton, params);
  return p;
}

// Every kept grasp: force closure, collision-free in its preshape at its pose, and the summary's
// reason codes account for every hypothesis that was not kept.
void expectConsistent(const PlanResult& r, const HandModel& hand, const GraspObject& object) {
  GraspSimulator sim(hand, object);
  for (const auto& g : r.grasps) {
    EXPECT_TRUE(g.force_closure);
    EXPECT_GT(g.epsilon, 0);
    EXPECT_GE(g.contacts.size(), 2u);
    EXPECT_FALSE(sim.inCollision(g.hand_pose, hand.preshape(g.preshape).joints))
        << "grasp " << g.id;
    EXPECT_FALSE(sim.inCollision(g.hand_pose, g.joints)) << "grasp " << g.id << " closed";
  }
  for (std::size_t i = 1; i < r.grasps.size(); ++i)
    EXPECT_GE(r.grasps[i - 1].epsilon, r.grasps[i].epsilon);
  const auto& s = r.summary;
  std::size_t rejected = 0;
  for (const auto& [why, count] : s.rejections) rejected += count;
  EXPECT_EQ(rejected, s.hypotheses - r.grasps.size());
  EXPECT_LE(s.generated, s.hypotheses);
  EXPECT_EQ(s.force_closure, r.grasps.size());  // min epsilon 0: every force closure grasp is kept
  EXPECT_EQ(s.power + s.precision, r.grasps.size());
}

// The skeleton strategies alone: neither the centre nor the surface candidates join the pool
// (fallback_planner_test.cpp examines those).
SkeletonPlannerParams skeletonStrategiesOnly() {
  SkeletonPlannerParams params;
  params.centre_candidates = false;
  params.surface_candidates = 0;
  return params;
}

TEST(SkeletonPlanner, CylinderGetsPowerGraspsApproachingAcrossTheAxis) {
  const HandModel hand = loadBuiltinHand("armar3");
  const SkeletonPlannerParams skeleton_only = skeletonStrategiesOnly();
  const auto p = planOn(geometry::shapes::makeCylinder(0.035, 0.2, 48, 10), hand, skeleton_only);
  ASSERT_FALSE(p.result.grasps.empty());
  expectConsistent(p.result, hand, *p.object);
  std::size_t across = 0;
  for (const auto& g : p.result.grasps) {
    EXPECT_EQ(g.type,
              GraspType::kPower);  // lambda2 ~ 0.71 r = 25 mm: power, too thick for precision
    const double along = std::abs(g.gcp_pose.rotation().col(2).z());
    if (g.strategy == "2a") {
      EXPECT_LT(along, 0.15);
      ++across;
    } else {
      EXPECT_EQ(g.strategy, "4");  // at the ends, along the axis
      EXPECT_GT(along, 0.9);
    }
  }
  EXPECT_GT(across, 100u);
  EXPECT_GT(p.result.summary.forceClosureRate(), 0.8);
}

TEST(SkeletonPlanner, ThinRodGetsOnlyPrecisionGrasps) {
  const HandModel hand = loadBuiltinHand("armar3");
  const SkeletonPlannerParams skeleton_only = skeletonStrategiesOnly();
  const auto p = planOn(geometry::shapes::makeCylinder(0.005, 0.16, 16, 20), hand, skeleton_only);
  ASSERT_FALSE(p.result.grasps.empty());
  expectConsistent(p.result, hand, *p.object);
  for (const auto& g : p.result.grasps) EXPECT_EQ(g.type, GraspType::kPrecision);
  EXPECT_GT(p.result.summary.rejections.at(reason::kThicknessOutOfRange), 0u);  // no power
}

TEST(SkeletonPlanner, PrecisionRetreatBacksPrecisionGraspsOffFurther) {
  const HandModel hand = loadBuiltinHand("armar3");
  const TriangleMesh rod = geometry::shapes::makeCylinder(0.005, 0.16, 16, 20);
  SkeletonPlannerParams params;
  params.precision_retreat_m = 0.008;
  params.fallback = false;
  const auto p = planOn(rod, hand, params);
  ASSERT_FALSE(p.result.grasps.empty());
  expectConsistent(p.result, hand, *p.object);
  // Moving away from a convex rod along the approach stays free, so every grasp takes the whole
  // extra back-off on top of its first free pose.
  for (const auto& g : p.result.grasps) EXPECT_GE(g.retreat_m, 0.008 - 1e-12) << g.id;
  params.precision_retreat_m = -0.001;
  EXPECT_THROW(planSkeletonGrasps(hand, *p.object, p.skeleton.skeleton, params), InvalidArgument);
}

TEST(SkeletonPlanner, ClearanceBacksOpenHandsOffByTheSurfaceErrorAroundThem) {
  // A rod along z whose upper half is uncertain by 6 mm: hands aimed there back off at least that
  // far beyond their first free pose; hands on the exact half stay as close as before.
  const HandModel hand = loadBuiltinHand("armar3");
  const TriangleMesh rod = geometry::shapes::makeCylinder(0.005, 0.16, 16, 20);
  SkeletonPlannerParams params;
  params.fallback = false;
  const auto exact = planOn(rod, hand, params);
  ASSERT_FALSE(exact.result.grasps.empty());
  constexpr double kUncertain = 0.006;
  params.hypothesis.clearance = [](const Eigen::Vector3d& gcp) {
    return gcp.z() > 0.01 ? kUncertain : 0.0;
  };
  const auto p = planOn(rod, hand, params);
  ASSERT_FALSE(p.result.grasps.empty());
  expectConsistent(p.result, hand, *p.object);
  std::size_t upper = 0, lower_close = 0;
  for (const auto& g : p.result.grasps) {
    // The hypothesis' centre: the grasp's, before the back-off along its approach (z).
    const Eigen::Vector3d aimed =
        g.gcp_pose.translation() + g.retreat_m * g.gcp_pose.rotation().col(2);
    if (aimed.z() > 0.01) {
      EXPECT_GE(g.retreat_m, kUncertain - 1e-12) << g.id;
      ++upper;
    } else if (aimed.z() < 0) {
      lower_close += g.retreat_m < kUncertain;
    }
  }
  EXPECT_GT(upper, 0u);
  EXPECT_GT(lower_close, 0u);
  params.hypothesis.clearance = [](const Eigen::Vector3d&) { return -0.001; };
  EXPECT_THROW(planSkeletonGrasps(hand, *p.object, p.skeleton.skeleton, params), InvalidArgument);
}

TEST(SkeletonPlanner, BoxGetsRectangularGraspsAlongItsPrincipalAxes) {
  const HandModel hand = loadBuiltinHand("armar3");
  const auto p = planOn(geometry::shapes::makeBox({0.05, 0.09, 0.26}, 6), hand);
  ASSERT_FALSE(p.result.grasps.empty());
  expectConsistent(p.result, hand, *p.object);
  std::size_t rectangular = 0;
  for (const auto& g : p.result.grasps) {
    if (g.strategy != "1b" && g.strategy != "2b") continue;
    ++rectangular;
    // Approach along the long axis of the 5 x 9 cm section (y), fingers spread along the box (z).
    EXPECT_GT(std::abs(g.gcp_pose.rotation().col(2).y()), 0.95);
    EXPECT_GT(std::abs(g.gcp_pose.rotation().col(1).z()), 0.95);
  }
  EXPECT_GT(rectangular, 50u);
}

TEST(SkeletonPlanner, MugGetsGraspsOnBodyAndHandle) {
  const HandModel hand = loadBuiltinHand("armar3");
  const auto p = planOn(geometry::shapes::makeNamedShape("mug"), hand);
  expectConsistent(p.result, hand, *p.object);
  std::size_t handle = 0, body = 0;
  for (const auto& g : p.result.grasps) {
    if (g.skeleton_vertex < 0) continue;  // centre candidates and fallbacks sit on no vertex
    const Eigen::Vector3d s = p.skeleton.skeleton.vertices[g.skeleton_vertex].position;
    (s.x() > 0.045 ? handle : body) += 1;  // the handle ring lies beyond x = 4.5 cm
  }
  EXPECT_GT(handle, 5u);
  EXPECT_GT(body, 5u);
}

TEST(SkeletonPlanner, IsDeterministicForASeedAndHonoursLimits) {
  const HandModel hand = loadBuiltinHand("sdh");
  const TriangleMesh mesh = geometry::shapes::makeNamedShape("bottle");
  SkeletonPlannerParams params;
  params.max_grasps = 10;
  params.seed = 7;
  const auto a = planOn(mesh, hand, params), b = planOn(mesh, hand, params);
  ASSERT_EQ(a.result.grasps.size(), b.result.grasps.size());
  EXPECT_LE(a.result.grasps.size(), 10u);
  EXPECT_TRUE(a.result.summary.max_grasps_reached);
  for (std::size_t i = 0; i < a.result.grasps.size(); ++i) {
    EXPECT_TRUE(a.result.grasps[i].hand_pose.isApprox(b.result.grasps[i].hand_pose, 1e-12));
    EXPECT_EQ(a.result.grasps[i].epsilon, b.result.grasps[i].epsilon);
  }
  params.max_grasps = 0;
  params.timeout_s = 1e-6;
  const auto timed = planOn(mesh, hand, params);
  EXPECT_TRUE(timed.result.summary.timed_out);
  EXPECT_EQ(timed.result.summary.hypotheses, 0u);
}

TEST(SkeletonPlanner, ExplainsWhyNothingWasFound) {
  // The gripper opens 8 cm: nothing about a 20 cm ball fits its thresholds.
  const HandModel hand = loadBuiltinHand("parallel_gripper");
  const auto p = planOn(geometry::shapes::makeSphere(0.1), hand);
  EXPECT_TRUE(p.result.grasps.empty());
  EXPECT_EQ(p.result.status.code, StatusCode::kNoResult);
  EXPECT_GT(p.result.summary.hypotheses, 0u);
  EXPECT_GT(p.result.summary.rejections.at(reason::kGraspTypeDisabled), 0u);  // no power grasps
  expectConsistent(p.result, hand, *p.object);
}

// The gripper's fingers are soft by default (torsional friction); a caller can still ask for point
// contacts, and two point contacts never hold a torque about the line through them.
TEST(SkeletonPlanner, PointContactsCanBeAskedForOnASoftFingeredHand) {
  const HandModel hand = loadBuiltinHand("parallel_gripper");
  ASSERT_GT(hand.closingDefaults().torsional_friction_m, 0);
  const TriangleMesh rod = geometry::shapes::makeCylinder(0.012, 0.12, 32, 12);
  // The same poses as the point-contact plan below.
  const SkeletonPlannerParams skeleton_only = skeletonStrategiesOnly();
  const auto soft = planOn(rod, hand, skeleton_only);  // nullopt: the hand's soft fingers
  ASSERT_FALSE(soft.result.grasps.empty());
  expectConsistent(soft.result, hand, *soft.object);

  SkeletonPlannerParams point;
  point.hypothesis.quality.torsional_friction_m = 0.0;
  point.fallback = false;  // the skeleton's two-finger pinches only (the fallback adds palm grasps)
  point.surface_candidates = 0;
  const auto rigid = planOn(rod, hand, point);
  EXPECT_EQ(rigid.result.summary.hypotheses, soft.result.summary.hypotheses);
  EXPECT_GT(rigid.result.summary.generated, 0u);
  EXPECT_EQ(rigid.result.summary.force_closure, 0u);
  EXPECT_TRUE(rigid.result.grasps.empty());
}

TEST(SurfacePlanner, SamplesTheRequestedHypothesesWithReasons) {
  const HandModel hand = loadBuiltinHand("armar3");
  const GraspObject object(geometry::shapes::makeCylinder(0.035, 0.2, 48, 10));
  SurfacePlannerParams params;
  params.max_hypotheses = 60;
  params.seed = 3;
  const PlanResult r = planSurfaceGrasps(hand, object, params);
  EXPECT_EQ(r.summary.hypotheses, 60u);
  expectConsistent(r, hand, object);
  for (const auto& g : r.grasps) {
    EXPECT_EQ(g.strategy, "surface");
    EXPECT_EQ(g.type, GraspType::kPower);
    EXPECT_EQ(g.skeleton_vertex, -1);
  }
  const PlanResult again = planSurfaceGrasps(hand, object, params);
  ASSERT_EQ(again.grasps.size(), r.grasps.size());
  for (std::size_t i = 0; i < r.grasps.size(); ++i)
    EXPECT_EQ(again.grasps[i].epsilon, r.grasps[i].epsilon);
}

// The paper's claim on real meshes: the skeleton planner's force-closure rate is higher than the
// surface planner's (ARMAR-III, mean over a fixed set of YCB objects; a 5 mm vertex distance and
// 200 surface hypotheses keep it quick).
TEST(PlannersOnRealMeshes, SkeletonBeatsSurfaceForceClosureRateForArmar3) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  const HandModel hand = loadBuiltinHand("armar3");
  double skeleton_rate = 0, surface_rate = 0;
  const std::vector<std::string> objects = {"006_mustard_bottle", "021_bleach_cleanser",
                                            "011_banana", "003_cracker_box", "048_hammer"};
  for (const auto& name : objects) {
    const TriangleMesh mesh = loadMesh(test::sharedDataDir() + "/objects/ycb/" + name + ".ply");
    SkeletonPlannerParams sp;
    sp.vertex_distance_m = 0.005;
    const auto skel = planOn(mesh, hand, sp);
    SurfacePlannerParams fp;
    fp.max_hypotheses = 200;
    const PlanResult surf = planSurfaceGrasps(hand, *skel.object, fp);
    std::printf("%s: skeleton %.1f%% of %zu, surface %.1f%% of %zu\n", name.c_str(),
                100 * skel.result.summary.forceClosureRate(), skel.result.summary.generated,
                100 * surf.summary.forceClosureRate(), surf.summary.generated);
    skeleton_rate += skel.result.summary.forceClosureRate() / objects.size();
    surface_rate += surf.summary.forceClosureRate() / objects.size();
  }
  std::printf("mean force-closure rate: skeleton %.1f%%, surface %.1f%%\n", 100 * skeleton_rate,
              100 * surface_rate);
  EXPECT_GT(skeleton_rate, surface_rate);
}

}  // namespace
}  // namespace skelgrasp::grasping
