#pragma once
// A mesh, its grasp object and the skeleton planner's grasps of a hand on it: the common start of
// the robust ranking and refinement tests.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "skelgrasp/grasping/planners.h"
#include "skelgrasp/skeleton/extraction.h"

namespace skelgrasp::evaluation::test_fixtures {

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

}  // namespace skelgrasp::evaluation::test_fixtures
