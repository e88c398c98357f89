// The planners close their hypotheses on every core of the task arena and take them in order
// (ordered_hypotheses.h): the plan must not depend on the number of threads.
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <functional>

#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/planning/fallback_planner.h"
#include "skelgrasp/grasping/planning/planners.h"
#include "skelgrasp/skeleton/extraction.h"
#include "table_scene.h"
#include "test_support.h"

namespace skelgrasp::grasping {
namespace {

// More threads than this machine may have cores, so that the chunks really interleave.
constexpr int kManyThreads = 4;

PlanResult planOnThreads(int threads, const std::function<PlanResult()>& plan) {
  const tbb::global_control allow(tbb::global_control::max_allowed_parallelism, threads);
  tbb::task_arena arena(threads);
  PlanResult result;
  arena.execute([&] { result = plan(); });
  return result;
}

// Same grasps (bit for bit) in the same order, and the same counts and reasons.
void expectSamePlan(const PlanResult& one, const PlanResult& many, const std::string& what) {
  SCOPED_TRACE(what);
  const PlanSummary &a = one.summary, &b = many.summary;
  EXPECT_EQ(a.hypotheses, b.hypotheses);
  EXPECT_EQ(a.poses, b.poses);
  EXPECT_EQ(a.generated, b.generated);
  EXPECT_EQ(a.force_closure, b.force_closure);
  EXPECT_EQ(a.rejections, b.rejections);
  EXPECT_EQ(a.scene_collision_links, b.scene_collision_links);
  EXPECT_EQ(a.precision, b.precision);
  EXPECT_EQ(a.power, b.power);
  EXPECT_EQ(a.max_grasps_reached, b.max_grasps_reached);
  ASSERT_EQ(one.grasps.size(), many.grasps.size());
  for (std::size_t i = 0; i < one.grasps.size(); ++i) {
    const Grasp &g = one.grasps[i], &h = many.grasps[i];
    EXPECT_EQ(g.hand_pose.matrix(), h.hand_pose.matrix()) << "grasp " << i;
    EXPECT_EQ(g.joints, h.joints) << "grasp " << i;
    EXPECT_EQ(g.epsilon, h.epsilon) << "grasp " << i;
    EXPECT_EQ(g.strategy, h.strategy) << "grasp " << i;
    EXPECT_EQ(g.preshape, h.preshape) << "grasp " << i;
    EXPECT_EQ(g.skeleton_vertex, h.skeleton_vertex) << "grasp " << i;
    EXPECT_EQ(g.contacts.size(), h.contacts.size()) << "grasp " << i;
  }
}

void expectSkeletonPlanIndependentOfThreads(const TriangleMesh& mesh, const std::string& name) {
  const GraspObject object(mesh);
  const auto skel = skeleton::extractSkeleton(mesh);
  ASSERT_TRUE(skel.status.ok()) << name << ": " << skel.status.message;
  for (const char* hand_name : {"armar3", "sdh"}) {
    const HandModel hand = loadBuiltinHand(hand_name);
    for (std::size_t max_grasps : {std::size_t{0}, std::size_t{7}}) {
      SkeletonPlannerParams params;
      params.max_grasps = max_grasps;
      const auto plan = [&] { return planSkeletonGrasps(hand, object, skel.skeleton, params); };
      const PlanResult one = planOnThreads(1, plan), many = planOnThreads(kManyThreads, plan);
      EXPECT_GT(one.summary.generated, 0u) << name << " " << hand_name;
      expectSamePlan(one, many,
                     name + " " + hand_name + " max_grasps " + std::to_string(max_grasps));
    }
  }
}

TEST(PlannerThreads, SkeletonPlanIsTheSameOnOneAndManyThreads) {
  for (const char* shape : {"mug", "box", "ball"})
    expectSkeletonPlanIndependentOfThreads(geometry::shapes::makeNamedShape(shape), shape);
}

TEST(PlannerThreads, SkeletonPlanOfRealMeshesIsTheSameOnOneAndManyThreads) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  for (const char* name : {"048_hammer", "017_orange"}) {
    const TriangleMesh mesh =
        loadMesh(test::sharedDataDir() + "/objects/ycb/" + std::string(name) + ".ply");
    expectSkeletonPlanIndependentOfThreads(mesh, name);
  }
}

TEST(PlannerThreads, SurfacePlanDrawsTheSamePosesOnOneAndManyThreads) {
  const TriangleMesh mesh = geometry::shapes::makeNamedShape("capsule");
  const GraspObject object(mesh);
  const HandModel hand = loadBuiltinHand("armar3");
  SurfacePlannerParams params;
  params.max_hypotheses = 150;  // not a multiple of any chunk: the last chunk is partial
  for (std::size_t max_grasps : {std::size_t{0}, std::size_t{5}}) {
    params.max_grasps = max_grasps;
    const auto plan = [&] { return planSurfaceGrasps(hand, object, params); };
    const PlanResult one = planOnThreads(1, plan), many = planOnThreads(kManyThreads, plan);
    EXPECT_EQ(one.summary.hypotheses, max_grasps ? one.summary.hypotheses : 150u);
    expectSamePlan(one, many, "surface, max_grasps " + std::to_string(max_grasps));
  }
}

// The scene check is called from every thread at once: with a table under the box, the top
// strategy's poses are checked against it and the plan is still the one thread's.
TEST(PlannerThreads, FallbackPlanWithASceneIsTheSameOnOneAndManyThreads) {
  const HandModel hand = loadBuiltinHand("sdh");
  const GraspObject object(test::boxStandingOnTable());
  const SceneChecker table(hand, nullptr, test::table());
  FallbackPlannerParams params;
  params.hypothesis.scene = &table;
  const auto plan = [&] { return planFallbackGrasps(hand, object, params); };
  const PlanResult one = planOnThreads(1, plan), many = planOnThreads(kManyThreads, plan);
  EXPECT_GT(one.summary.rejections.count("scene_collision"), 0u)
      << "the table should rule out some poses";
  expectSamePlan(one, many, "fallback with a table");
}

}  // namespace
}  // namespace skelgrasp::grasping
