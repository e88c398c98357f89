// A program built against the installed package (find_package(skelgrasp)): grasps for a
// generated bottle with the built-in SDH hand.
#include <iostream>

#include "skelgrasp/common/primitives.h"
#include "skelgrasp/grasping/planners.h"
#include "skelgrasp/skeleton/extraction.h"

int main() {
  using namespace skelgrasp;
  const TriangleMesh mesh = primitives::makeNamedShape("bottle");
  const auto skeleton = skeleton::extractSkeleton(mesh);
  const grasping::HandModel hand = grasping::loadBuiltinHand("sdh");
  const grasping::GraspObject object(mesh);
  grasping::SkeletonPlannerParams params;
  params.max_grasps = 2;
  const auto plan = grasping::planSkeletonGrasps(hand, object, skeleton.skeleton, params);
  std::cout << "consumer: " << plan.grasps.size() << " grasps on the bottle" << std::endl;
  return plan.grasps.empty() ? 1 : 0;
}
