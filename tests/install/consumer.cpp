// A program built against the installed package (find_package(skelgrasp)): ranked grasps for a
// generated bottle with the built-in SDH hand, as `skelgrasp plan` gives them.
#include <iostream>

#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/ranking/plan_grasps.h"

int main() {
  using namespace skelgrasp;
  const TriangleMesh mesh = geometry::shapes::makeNamedShape("bottle");
  const grasping::HandModel hand = grasping::loadBuiltinHand("sdh");
  ranking::PlanOptions options;
  options.skeleton_planner.max_grasps = 2;
  const ranking::GraspPlan plan = ranking::planGrasps(mesh, hand, options);
  if (!plan.status.ok() || !plan.grasps.front().robustness) return 1;
  std::cout << "consumer: " << plan.grasps.size() << " grasps on the bottle, the best with r "
            << plan.grasps.front().robustness->r << std::endl;
  return 0;
}
