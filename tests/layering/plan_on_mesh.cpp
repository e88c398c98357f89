// The smallest program that plans grasps on a mesh: skeleton + grasping only. Its shared-library
// dependencies are checked by the Layering test (tests/CMakeLists.txt): no PCL, no VTK.
#include <iostream>

#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/planning/planners.h"
#include "skelgrasp/grasping/simulation/grasp_object.h"
#include "skelgrasp/skeleton/extraction.h"

int main() {
  using namespace skelgrasp;
  const TriangleMesh mesh = geometry::shapes::makeNamedShape("bottle");
  const auto skeleton = skeleton::extractSkeleton(mesh);
  if (!skeleton.status.ok()) return 1;
  const auto hand = grasping::loadBuiltinHand("armar3");
  const grasping::GraspObject object(mesh);
  grasping::SkeletonPlannerParams params;
  params.max_grasps = 1;
  const auto plan = grasping::planSkeletonGrasps(hand, object, skeleton.skeleton, params);
  std::cout << plan.grasps.size() << " grasp(s)" << std::endl;
  return 0;
}
