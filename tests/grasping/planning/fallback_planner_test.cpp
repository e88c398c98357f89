// The fallback strategies for objects whose skeleton says little (balls, discs): they fill in when
// the skeleton strategies give few grasps, judge their poses as the skeleton planner does, and
// stay out of the way on objects the skeleton serves well.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "skelgrasp/geometry/principal_axes.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/planning/planners.h"
#include "skelgrasp/grasping/planning/scene.h"
#include "skelgrasp/skeleton/extraction.h"
#include "table_scene.h"

namespace skelgrasp::grasping {
namespace {

constexpr double kBallRadiusM = 0.035;
constexpr double kDiscRadiusM = 0.045;
constexpr double kDiscThicknessM = 0.015;
constexpr std::size_t kWantedGrasps = 5;  // issue 16: >= 5 force-closure grasps per hand

TriangleMesh ball() {
  return geometry::shapes::makeSphere(kBallRadiusM, 48, 24);
}
TriangleMesh disc() {
  return geometry::shapes::makeCylinder(kDiscRadiusM, kDiscThicknessM, 64, 3);
}

struct Planned {
  std::unique_ptr<GraspObject> object;
  skeleton::SkeletonResult skeleton;
  PlanResult result;
};

Planned planOn(const TriangleMesh& mesh, const HandModel& hand, SkeletonPlannerParams params = {}) {
  Planned p;
  p.object = std::make_unique<GraspObject>(mesh);
  p.skeleton = skeleton::extractSkeleton(mesh);
  EXPECT_TRUE(p.skeleton.status.ok()) << p.skeleton.status.message;
  p.result = planSkeletonGrasps(hand, *p.object, p.skeleton.skeleton, params);
  return p;
}

bool isFallbackStrategy(const std::string& strategy) {
  return strategy == "sphere" || strategy == "rim" || strategy == "axes" || strategy == "top";
}

std::size_t fallbackReasons(const PlanSummary& s) {
  std::size_t n = 0;
  for (const char* why : {reason::kFallbackNoSegment, reason::kFallbackFewGrasps})
    n += s.rejections.count(why) ? s.rejections.at(why) : 0;
  return n;
}

// Every kept grasp holds and is collision-free open and closed; fallback grasps name no skeleton
// part; the rejection counts account for every hypothesis not kept.
void expectSound(const PlanResult& r, const HandModel& hand, const GraspObject& object) {
  GraspSimulator sim(hand, object);
  for (const auto& g : r.grasps) {
    EXPECT_TRUE(g.force_closure) << g.strategy;
    EXPECT_GT(g.epsilon, 0);
    EXPECT_GE(g.contacts.size(), 2u);
    EXPECT_FALSE(sim.inCollision(g.hand_pose, hand.preshape(g.preshape).joints)) << g.strategy;
    EXPECT_FALSE(sim.inCollision(g.hand_pose, g.joints)) << g.strategy << " closed";
    if (isFallbackStrategy(g.strategy)) {
      EXPECT_EQ(g.segment, -1);
      EXPECT_EQ(g.skeleton_vertex, -1);
    }
  }
  std::size_t rejected = 0;
  for (const auto& [why, count] : r.summary.rejections) rejected += count;
  EXPECT_EQ(rejected, r.summary.hypotheses - r.grasps.size());
  EXPECT_EQ(r.summary.force_closure, r.grasps.size());
  EXPECT_EQ(r.summary.power + r.summary.precision, r.grasps.size());
}

class PaperHand : public ::testing::TestWithParam<std::string> {};

TEST_P(PaperHand, BallGetsFiveForceClosureGrasps) {
  const HandModel hand = loadBuiltinHand(GetParam());
  const auto p = planOn(ball(), hand);
  EXPECT_GE(p.result.grasps.size(), kWantedGrasps) << GetParam();
  // A clean generated ball may give the ARMAR-III and the SDH enough skeleton grasps already;
  // the fallback runs at most once.
  EXPECT_LE(fallbackReasons(p.result.summary), 1u);
  expectSound(p.result, hand, *p.object);
}

TEST_P(PaperHand, DiscGetsFiveForceClosureGrasps) {
  const HandModel hand = loadBuiltinHand(GetParam());
  const auto p = planOn(disc(), hand);
  EXPECT_GE(p.result.grasps.size(), kWantedGrasps) << GetParam();
  expectSound(p.result, hand, *p.object);
}

INSTANTIATE_TEST_SUITE_P(FallbackPlanner, PaperHand, ::testing::Values("armar3", "sdh", "shadow"),
                         [](const auto& info) { return info.param; });

TEST(FallbackPlanner, CapsuleServedByTheSkeletonIsLeftAlone) {
  const HandModel hand = loadBuiltinHand("armar3");
  const TriangleMesh capsule = geometry::shapes::makeCapsule(0.03, 0.14, 48);
  SkeletonPlannerParams no_centre;
  no_centre.centre_candidates = false;
  no_centre.surface_candidates = 0;
  SkeletonPlannerParams off = no_centre;
  off.fallback = false;
  const auto with = planOn(capsule, hand, no_centre), without = planOn(capsule, hand, off);
  ASSERT_GE(without.result.grasps.size(), SkeletonPlannerParams{}.fallback_min_grasps);
  EXPECT_EQ(fallbackReasons(with.result.summary), 0u);
  ASSERT_EQ(with.result.grasps.size(), without.result.grasps.size());
  EXPECT_EQ(with.result.summary.hypotheses, without.result.summary.hypotheses);
  for (std::size_t i = 0; i < with.result.grasps.size(); ++i) {
    EXPECT_FALSE(isFallbackStrategy(with.result.grasps[i].strategy));
    EXPECT_TRUE(
        with.result.grasps[i].hand_pose.isApprox(without.result.grasps[i].hand_pose, 1e-12));
    EXPECT_EQ(with.result.grasps[i].epsilon, without.result.grasps[i].epsilon);
  }
}

// The skeleton's grasps of a plan, keyed by strategy, vertex, preshape and pose, to compare plans
// whose ε order interleaves other grasps.
std::vector<std::string> skeletonGraspKeys(const PlanResult& r) {
  std::vector<std::string> keys;
  for (const auto& g : r.grasps) {
    if (isFallbackStrategy(g.strategy)) continue;
    const Eigen::Vector3d t = g.hand_pose.translation();
    keys.push_back(g.strategy + "/" + std::to_string(g.skeleton_vertex) + "/" + g.preshape + "/" +
                   std::to_string(std::lround(t.x() * 1e6)) + "," +
                   std::to_string(std::lround(t.y() * 1e6)) + "," +
                   std::to_string(std::lround(t.z() * 1e6)));
  }
  std::sort(keys.begin(), keys.end());
  return keys;
}

// Centre candidates: on an object the skeleton serves, the power and precision grasps about the
// centre are added to the skeleton's grasps (which stay exactly as without them), judged as the
// others, and recorded as nobody's rejection.
TEST(FallbackPlanner, CentreCandidatesAddPowerAndPrecisionGraspsAboutTheCentre) {
  const HandModel hand = loadBuiltinHand("armar3");
  const TriangleMesh capsule = geometry::shapes::makeCapsule(0.03, 0.14, 48);
  SkeletonPlannerParams with_centre;  // the centre candidates alone join the pool here
  with_centre.surface_candidates = 0;
  SkeletonPlannerParams no_centre = with_centre;
  no_centre.centre_candidates = false;
  const auto with = planOn(capsule, hand, with_centre), without = planOn(capsule, hand, no_centre);
  ASSERT_TRUE(SkeletonPlannerParams{}.centre_candidates);
  expectSound(with.result, hand, *with.object);
  EXPECT_EQ(fallbackReasons(with.result.summary), 0u);
  EXPECT_EQ(skeletonGraspKeys(with.result), skeletonGraspKeys(without.result));
  std::size_t power = 0, precision = 0;
  for (const auto& g : with.result.grasps) {
    if (!isFallbackStrategy(g.strategy)) continue;
    EXPECT_NE(g.strategy, "rim");  // a capsule is no disc, and rim poses are not centre ones
    // ARMAR-III has no alternative preshapes: each type closes its own.
    EXPECT_EQ(g.preshape, toString(g.type));
    ++(g.type == GraspType::kPower ? power : precision);
  }
  EXPECT_GE(power, kWantedGrasps);
  EXPECT_GE(precision, kWantedGrasps);
  EXPECT_EQ(with.result.grasps.size(), without.result.grasps.size() + power + precision);
  EXPECT_GT(with.result.summary.hypotheses, without.result.summary.hypotheses);
}

// Alternative preshapes (the SDH's tripods "claw" and "precision_tripod" and its lateral grips
// "lateral_power" and "lateral_precision"): every pose
// closed with a hand's power or precision preshape is also closed with that type's alternatives, by
// the skeleton strategies and the centre candidates alike; the grasps of the main preshapes stay
// exactly as without them, and switching them off or asking for the reference's quality leaves
// only those.
TEST(FallbackPlanner, AlternativePreshapesOnlyAddGraspsOfTheirOwnPreshape) {
  const HandModel sdh = loadBuiltinHand("sdh");
  const TriangleMesh capsule = geometry::shapes::makeCapsule(0.03, 0.14, 48);
  SkeletonPlannerParams with_alternatives;
  with_alternatives.surface_candidates = 0;  // the surface planner closes "power" only
  SkeletonPlannerParams without = with_alternatives;
  without.alternative_preshapes = false;
  SkeletonPlannerParams reference = with_alternatives;
  reference.hypothesis.quality.reference_compat = true;
  const auto with = planOn(capsule, sdh, with_alternatives);
  const auto main_only = planOn(capsule, sdh, without);
  const auto ref = planOn(capsule, sdh, reference);
  expectSound(with.result, sdh, *with.object);
  ASSERT_EQ(fallbackReasons(with.result.summary), fallbackReasons(main_only.result.summary));
  // An alternative's name is not its type's.
  const auto alternative = [](const Grasp& g) { return g.preshape != toString(g.type); };
  const auto keys = [&](const PlanResult& r, bool alternatives) {
    std::set<std::string> out;
    for (const auto& g : r.grasps) {
      if (alternative(g) != alternatives) continue;
      const Eigen::Vector3d t = g.hand_pose.translation();
      out.insert(g.strategy + "/" + std::to_string(g.skeleton_vertex) + "/" + g.preshape + "/" +
                 std::to_string(std::lround(t.x() * 1e6)) + "," +
                 std::to_string(std::lround(t.y() * 1e6)) + "," +
                 std::to_string(std::lround(t.z() * 1e6)));
    }
    return out;
  };
  EXPECT_EQ(keys(with.result, false), keys(main_only.result, false));
  EXPECT_TRUE(keys(main_only.result, true).empty());
  EXPECT_TRUE(keys(ref.result, true).empty());
  std::map<std::string, std::set<std::string>> strategies;  // by alternative preshape
  for (const auto& g : with.result.grasps) {
    if (!alternative(g)) continue;
    EXPECT_EQ(g.type, sdh.preshape(g.preshape).grasp_type) << g.preshape;
    strategies[g.preshape].insert(isFallbackStrategy(g.strategy) ? "centre" : "skeleton");
  }
  // The fingertip grips hold the 6 cm capsule at skeleton poses and about its middle; the claw and
  // the lateral power grip wrap it about its middle only (no skeleton pose holds).
  EXPECT_EQ(strategies["precision_tripod"], (std::set<std::string>{"centre", "skeleton"}));
  EXPECT_EQ(strategies["lateral_precision"], (std::set<std::string>{"centre", "skeleton"}));
  EXPECT_EQ(strategies["claw"].count("centre"), 1u);
  EXPECT_EQ(strategies["lateral_power"].count("centre"), 1u);
  const auto alternative_grasps =
      std::count_if(with.result.grasps.begin(), with.result.grasps.end(), alternative);
  EXPECT_EQ(with.result.grasps.size(),
            main_only.result.grasps.size() + static_cast<std::size_t>(alternative_grasps));
  EXPECT_GT(with.result.summary.hypotheses, main_only.result.summary.hypotheses);
}

// A preshape made for small objects (the SDH's narrow tripod, Preshape::max_object_length_m) is
// closed on an object no longer than its limit, and on none longer: a ball whose diameter is 80 %
// of the limit gets narrow-tripod grasps in force closure; a capsule as thick but longer than the
// limit gets none, though the same hand without the limit closes the narrow tripod on it too.
TEST(FallbackPlanner, SmallObjectPreshapesCloseOnSmallObjectsOnly) {
  const HandModel sdh = loadBuiltinHand("sdh");
  ASSERT_TRUE(sdh.preshape("narrow_tripod").max_object_length_m);
  const double limit_m = *sdh.preshape("narrow_tripod").max_object_length_m;
  HandModel unlimited = sdh;
  auto preshapes = sdh.preshapes();
  preshapes.at("narrow_tripod").max_object_length_m.reset();
  unlimited.setDescription(sdh.fingers(), sdh.palmLinks(), preshapes, sdh.thresholds(),
                           sdh.precisionIntervalM(), sdh.powerIntervalM(), sdh.closingDefaults());
  const double radius_m = 0.4 * limit_m;
  const auto narrow = [](const PlanResult& r) {
    return std::count_if(r.grasps.begin(), r.grasps.end(),
                         [](const Grasp& g) { return g.preshape == "narrow_tripod"; });
  };
  const auto small = planOn(geometry::shapes::makeSphere(radius_m, 48, 24), sdh);
  EXPECT_LE(small.object->principalLengthM(), limit_m);
  EXPECT_GT(narrow(small.result), 0);
  expectSound(small.result, sdh, *small.object);
  SkeletonPlannerParams params;
  params.surface_candidates = 0;  // the surface planner closes "power" only
  const TriangleMesh capsule = geometry::shapes::makeCapsule(radius_m, limit_m, 48);
  const auto longer = planOn(capsule, sdh, params);
  EXPECT_GT(longer.object->principalLengthM(), limit_m);
  EXPECT_EQ(narrow(longer.result), 0);
  EXPECT_GT(longer.result.grasps.size(), 0u);
  EXPECT_GT(narrow(planOn(capsule, unlimited, params).result), 0);
}

// The object's size for such preshapes is its length along its longest principal axis, whatever
// its orientation; a ball's is its diameter (any axis will do), and a mesh without area, with no
// axes, gets its bounding box diagonal rather than its length along an arbitrary axis.
TEST(FallbackPlanner, ObjectLengthIsTheLengthAlongTheLongestPrincipalAxis) {
  const TriangleMesh box = geometry::shapes::makeBox(Eigen::Vector3d(0.12, 0.05, 0.03));
  EXPECT_NEAR(GraspObject(box).principalLengthM(), 0.12, 1e-9);
  TriangleMesh turned = box;
  const Eigen::Matrix3d rotation =
      (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized())).toRotationMatrix();
  for (auto& v : turned.vertices) v = rotation * v + Eigen::Vector3d(0.3, -0.2, 0.1);
  EXPECT_NEAR(GraspObject(turned).principalLengthM(), 0.12, 1e-9);
  EXPECT_NEAR(GraspObject(geometry::shapes::makeSphere(0.02, 48, 24)).principalLengthM(), 0.04,
              1e-3);
  TriangleMesh sliver;
  sliver.vertices = {{0, 0, 0}, {0, 0.05, 0}, {0, 0.1, 0}};
  sliver.faces = {{0, 1, 2}};
  EXPECT_NEAR(geometry::principalLengthM(sliver, geometry::surfacePrincipalAxes(sliver)), 0.1,
              1e-12);
}

// A grasp limit does not shut the centre candidates out: the skeleton strategies stop at its
// larger half, the centre candidates fill up the rest.
TEST(FallbackPlanner, CentreCandidatesGetTheRestOfAGraspLimit) {
  const HandModel hand = loadBuiltinHand("armar3");
  const TriangleMesh capsule = geometry::shapes::makeCapsule(0.03, 0.14, 48);
  for (std::size_t limit : {1u, 5u}) {
    SkeletonPlannerParams limited;
    limited.max_grasps = limit;
    const auto p = planOn(capsule, hand, limited);
    std::size_t centre = 0, skeleton = 0;
    for (const auto& g : p.result.grasps) (isFallbackStrategy(g.strategy) ? centre : skeleton) += 1;
    EXPECT_EQ(skeleton, (limit + 1) / 2) << limit;
    EXPECT_EQ(centre, limit / 2) << limit;
    EXPECT_TRUE(p.result.summary.max_grasps_reached) << limit;
    expectSound(p.result, hand, *p.object);
  }
}

// A hand without power grasps (the parallel gripper) gets its centre candidates as precision
// grasps.
TEST(FallbackPlanner, CentreCandidatesOfAGripperArePrecisionGrasps) {
  const HandModel hand = loadBuiltinHand("parallel_gripper");
  ASSERT_FALSE(hand.thresholds().power.has_value());
  const TriangleMesh capsule = geometry::shapes::makeCapsule(0.02, 0.10, 48);
  const auto p = planOn(capsule, hand);
  std::size_t centre = 0;
  for (const auto& g : p.result.grasps) {
    if (!isFallbackStrategy(g.strategy)) continue;
    ++centre;
    EXPECT_EQ(g.preshape, "precision");
  }
  EXPECT_GT(centre, 0u);
  expectSound(p.result, hand, *p.object);
}

// Surface candidates: the surface planner's hypotheses join the pool, counted in the summary, with
// their own strategy name; the other strategies' grasps are unchanged.
TEST(FallbackPlanner, SurfaceCandidatesJoinThePool) {
  const HandModel hand = loadBuiltinHand("armar3");
  const TriangleMesh capsule = geometry::shapes::makeCapsule(0.03, 0.14, 48);
  ASSERT_EQ(SkeletonPlannerParams{}.surface_candidates, 50u);
  SkeletonPlannerParams with_surface, without_surface;
  constexpr std::size_t kSurfaceHypotheses = 30;
  with_surface.surface_candidates = kSurfaceHypotheses;
  without_surface.surface_candidates = 0;
  const auto with = planOn(capsule, hand, with_surface),
             without = planOn(capsule, hand, without_surface);
  expectSound(with.result, hand, *with.object);
  EXPECT_EQ(with.result.summary.hypotheses, without.result.summary.hypotheses + kSurfaceHypotheses);
  std::map<std::string, std::size_t> others_with, others_without;
  std::size_t surface = 0;
  for (const Grasp& g : with.result.grasps) {
    if (g.strategy != "surface") {
      ++others_with[g.strategy];
      continue;
    }
    ++surface;
    EXPECT_EQ(g.preshape, "power");
  }
  for (const Grasp& g : without.result.grasps) ++others_without[g.strategy];
  EXPECT_EQ(others_with, others_without);
  EXPECT_GT(surface, 0u);
  EXPECT_EQ(with.result.grasps.size(), without.result.grasps.size() + surface);
}

TEST(FallbackPlanner, SwitchedOffLeavesTheBallToTheSkeleton) {
  const HandModel hand = loadBuiltinHand("armar3");
  SkeletonPlannerParams off;
  off.fallback = false;
  const auto p = planOn(ball(), hand, off);
  EXPECT_EQ(fallbackReasons(p.result.summary), 0u);
  for (const auto& g : p.result.grasps) EXPECT_FALSE(isFallbackStrategy(g.strategy));
}

TEST(FallbackPlanner, DiscIsRecognisedAndPinchedAtTheRim) {
  const TriangleMesh mesh = disc();
  const PrincipalAxes pa = surfacePrincipalAxes(mesh);
  EXPECT_NEAR(std::abs(pa.axes.col(2).z()), 1.0, 1e-6);  // the thin axis is the cylinder's
  EXPECT_LT(pa.sd(2), FallbackStrategyParams{}.disc_ratio * pa.sd(1));
  EXPECT_NEAR(pa.sd(0), pa.sd(1), 1e-3);

  const HandModel hand = loadBuiltinHand("sdh");
  const GraspObject object(mesh);
  const PlanResult r = planFallbackGrasps(hand, object, {});
  expectSound(r, hand, object);
  std::set<std::string> strategies;
  for (const auto& g : r.grasps) strategies.insert(g.strategy);
  EXPECT_TRUE(strategies.count("rim")) << "no rim grasp among " << r.grasps.size();
}

// On a disc the rim's in-plane approaches at quarter turns are also principal-axis approaches:
// each such pose is tried once, so no grasp of the plan repeats another.
TEST(FallbackPlanner, NoPoseIsTriedTwice) {
  const GraspObject object(disc());
  for (const char* hand_name : {"armar3", "sdh"}) {
    const HandModel hand = loadBuiltinHand(hand_name);
    const PlanResult r = planFallbackGrasps(hand, object, {});
    ASSERT_GE(r.grasps.size(), kWantedGrasps) << hand_name;
    std::set<std::string> strategies;
    for (std::size_t i = 0; i < r.grasps.size(); ++i) {
      strategies.insert(r.grasps[i].strategy);
      for (std::size_t j = 0; j < i; ++j) {
        const Grasp &a = r.grasps[i], &b = r.grasps[j];
        if (a.preshape != b.preshape) continue;
        EXPECT_FALSE(a.gcp_pose.isApprox(b.gcp_pose, 1e-6))
            << hand_name << ": grasps " << j << " (" << b.strategy << ") and " << i << " ("
            << a.strategy << ") are tried from the same pose";
      }
    }
    // Both strategies still contribute where their poses differ.
    EXPECT_TRUE(strategies.count("rim")) << hand_name;
    EXPECT_TRUE(strategies.count("axes")) << hand_name;
  }
}

TEST(FallbackPlanner, BallIsNoDiscAndResultsAreDeterministicForASeed) {
  const TriangleMesh mesh = ball();
  const PrincipalAxes pa = surfacePrincipalAxes(mesh);
  EXPECT_GT(pa.sd(2), FallbackStrategyParams{}.disc_ratio * pa.sd(1));

  const HandModel hand = loadBuiltinHand("sdh");
  const GraspObject object(mesh);
  FallbackPlannerParams params;
  params.seed = 3;
  params.max_grasps = 6;
  const PlanResult a = planFallbackGrasps(hand, object, params);
  const PlanResult b = planFallbackGrasps(hand, object, params);
  EXPECT_TRUE(a.summary.max_grasps_reached);
  ASSERT_EQ(a.grasps.size(), b.grasps.size());
  EXPECT_LE(a.grasps.size(), 6u);
  for (std::size_t i = 0; i < a.grasps.size(); ++i) {
    EXPECT_NE(a.grasps[i].strategy, "rim");
    EXPECT_TRUE(a.grasps[i].hand_pose.isApprox(b.grasps[i].hand_pose, 1e-12));
    EXPECT_EQ(a.grasps[i].epsilon, b.grasps[i].epsilon);
  }
}

// The "top" strategy: only where the scene check knows a support plane, and then from above only
// (straight down or tilted by the configured angle), with the fingers spreading along the box's
// long side on the straight-down poses at quarter turns.
TEST(FallbackPlanner, TopStrategyComesFromAboveWhenThereIsASupportPlane) {
  const HandModel hand = loadBuiltinHand("sdh");
  const GraspObject object(test::boxStandingOnTable());
  const SceneChecker table(hand, nullptr, test::table());
  FallbackPlannerParams params;
  params.strategies.sphere = params.strategies.rim = params.strategies.axes = false;
  const PlanResult free_space = planFallbackGrasps(hand, object, params);
  EXPECT_EQ(free_space.summary.poses, 0u) << "top poses without a support plane";

  params.hypothesis.scene = &table;
  const PlanResult r = planFallbackGrasps(hand, object, params);
  const FallbackStrategyParams& sp = params.strategies;
  const std::size_t poses = sp.top_rolls + sp.top_tilted_azimuths * sp.top_tilted_rolls;
  // Precision, power and the SDH's alternatives of each (of power its claw and lateral grip, of
  // precision its tripod and lateral pinch; the narrow tripod is for smaller objects).
  EXPECT_EQ(r.summary.poses, 6 * poses);
  EXPECT_GE(r.grasps.size(), kWantedGrasps);
  expectSound(r, hand, object);
  const double steepest = std::cos(sp.top_tilt_rad) - 1e-9;
  for (const auto& g : r.grasps) {
    EXPECT_EQ(g.strategy, "top");
    const Eigen::Vector3d approach = g.gcp_pose.rotation().col(2);
    EXPECT_GE(-approach.z(), steepest) << approach.transpose();
    // The hand stays above the table (the scene check's plane).
    EXPECT_FALSE(table.checkPose(g.hand_pose, g.joints).collision);
  }
}

// Top poses are also tried centred across their closing axis. A triangular plate's centroid lies a
// quarter of the circumradius off the middle of the chord along an altitude (20 mm from the side,
// 40 mm from the vertex), so the rolls that close along an altitude get a centred twin (the box
// of the test above, symmetric about its centre, gets none).
TEST(FallbackPlanner, TopPosesAreAlsoTriedCentredBetweenTheFacesTheFingersCloseOn) {
  const HandModel hand = loadBuiltinHand("parallel_gripper");
  constexpr double kCircumradiusM = 0.04, kPlateHeightM = 0.02;
  TriangleMesh plate = geometry::shapes::makeCylinder(kCircumradiusM, kPlateHeightM, 3, 2);
  plate.transform(Pose(Eigen::Translation3d(0, 0, kPlateHeightM / 2)));  // lying on z = 0
  const GraspObject object(plate);
  const SceneChecker table(hand, nullptr, SupportPlane{Eigen::Vector4d(0, 0, 1, 0)});
  FallbackPlannerParams params;
  params.strategies.sphere = params.strategies.rim = params.strategies.axes = false;
  params.hypothesis.scene = &table;
  const FallbackStrategyParams& sp = params.strategies;
  const std::size_t top_poses = sp.top_rolls + sp.top_tilted_azimuths * sp.top_tilted_rolls;

  params.strategies.top_centring_band_m = 0;
  const PlanResult at_centroid = planFallbackGrasps(hand, object, params);
  EXPECT_EQ(at_centroid.summary.poses, top_poses);  // the gripper: precision only

  params.strategies.top_centring_band_m = FallbackStrategyParams{}.top_centring_band_m;
  const PlanResult centred = planFallbackGrasps(hand, object, params);
  EXPECT_GT(centred.summary.poses, top_poses);
  EXPECT_LE(centred.summary.poses, 2 * top_poses);
  expectSound(centred, hand, object);
  EXPECT_GE(centred.grasps.size(), at_centroid.grasps.size());

  params.strategies.top_centring_band_m = -0.01;
  EXPECT_THROW(planFallbackGrasps(hand, object, params), InvalidArgument);
}

TEST(FallbackPlanner, RejectsEmptySampling) {
  const HandModel hand = loadBuiltinHand("sdh");
  const GraspObject object(ball());
  FallbackPlannerParams params;
  params.strategies.sphere_rolls = 0;
  EXPECT_THROW(planFallbackGrasps(hand, object, params), InvalidArgument);
}

}  // namespace
}  // namespace skelgrasp::grasping
