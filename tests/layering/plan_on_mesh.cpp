// The smallest program that plans and ranks grasps on a mesh: skeleton, grasping and ranking only.
// Its shared-library dependencies are checked by the Layering test (tests/CMakeLists.txt): no
// PCL, no VTK, no OpenCV, no libpng.
#include <iostream>

#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/ranking/plan_grasps.h"

int main() {
  using namespace skelgrasp;
  const TriangleMesh mesh = geometry::shapes::makeNamedShape("bottle");
  const auto hand = grasping::loadBuiltinHand("armar3");
  ranking::PlanOptions options;
  options.skeleton_planner.max_grasps = 1;
  const ranking::GraspPlan plan = ranking::planGrasps(mesh, hand, options);
  if (plan.skeleton_failed) return 1;
  std::cout << plan.grasps.size() << " grasp(s)" << std::endl;
  return 0;
}
