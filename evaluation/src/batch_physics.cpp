#include "batch_physics.h"

#include "skelgrasp/evaluation/simulate.h"
#include "skelgrasp/physics/execution.h"
#include "skelgrasp/physics/physical_object.h"

namespace skelgrasp::evaluation::internal {

std::shared_ptr<const physics::PhysicalObject> physicalObject(const TriangleMesh& mesh,
                                                              const PhysicsJudging& params) {
  physics::PhysicalObjectParams object;
  object.mass_kg = params.mass_kg;
  return std::make_shared<const physics::PhysicalObject>(mesh, object);
}

PhysicsMeasures judgeGrasps(const grasping::HandModel& hand, const grasping::GraspObject& object,
                            const physics::PhysicalObject& physical,
                            const std::vector<grasping::Grasp>& grasps, double mu,
                            const PhysicsJudging& params, std::vector<std::optional<bool>>& holds) {
  std::vector<grasping::GraspPlacement> placements;
  for (std::size_t i = 0; i < grasps.size() && i < params.grasps; ++i)
    placements.push_back(
        {nlohmann::json(static_cast<int>(i)), grasps[i].hand_pose, grasps[i].preshape});
  holds.assign(grasps.size(), std::nullopt);
  PhysicsMeasures measures;
  if (placements.empty()) return measures;
  SimulateParams simulate;
  simulate.frictions = {mu};
  const SimulateResult result = simulateGrasps(hand, object, physical, placements, simulate);
  for (std::size_t i = 0; i < result.grasps.size(); ++i) {
    const physics::ExecutionResult& run = result.grasps[i].by_friction.front().nominal;
    holds[i] = run.holds;
    ++measures.judged;
    measures.holds += run.holds;
    measures.start_failures += run.failed_phase == physics::ExecutionPhase::kStart;
    measures.closing_failures += run.failed_phase == physics::ExecutionPhase::kClosing;
    measures.disturbance_failures += run.failed_phase == physics::ExecutionPhase::kDisturbance;
  }
  measures.cpu_s = result.execution_cpu_s;
  return measures;
}

}  // namespace skelgrasp::evaluation::internal
