#pragma once
// A mesh, its grasp object and the skeleton planner's grasps of a hand on it: the common start of
// the robust ranking and refinement tests.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/planning/planners.h"
#include "skelgrasp/ranking/robust_ranking.h"
#include "skelgrasp/skeleton/extraction.h"

namespace skelgrasp::ranking::test_fixtures {

struct Planned {
  grasping::HandModel hand;
  TriangleMesh mesh;
  std::unique_ptr<grasping::GraspObject> object;
  grasping::SkeletonPlannerParams params;
  grasping::PlanResult plan;
};

// At most `max_grasps` grasps of `hand` on `mesh`, sorted by epsilon as the planner returns them.
inline Planned planOn(const std::string& hand, TriangleMesh mesh, std::size_t max_grasps) {
  Planned p{grasping::loadBuiltinHand(hand), std::move(mesh), nullptr, {}, {}};
  p.object = std::make_unique<grasping::GraspObject>(p.mesh);
  const auto skel = skeleton::extractSkeleton(p.mesh);
  EXPECT_TRUE(skel.status.ok()) << skel.status.message;
  p.params.max_grasps = max_grasps;
  p.params.timeout_s = 60;
  p.plan = grasping::planSkeletonGrasps(p.hand, *p.object, skel.skeleton, p.params);
  return p;
}

// A 70 mm cylinder, 200 mm long, planned once for ARMAR-III (8 grasps), shared by the tests.
inline const Planned& cylinder() {
  static const Planned planned =
      planOn("armar3", geometry::shapes::makeCylinder(0.035, 0.2, 48, 10), 8);
  return planned;
}

// Scores the best top_k by epsilon, without screening.
inline RobustRankingParams fewSamples(int samples, std::size_t top_k) {
  RobustRankingParams params;
  params.robustness.samples = samples;
  params.top_k = top_k;
  params.screen_k = top_k;
  return params;
}

}  // namespace skelgrasp::ranking::test_fixtures
