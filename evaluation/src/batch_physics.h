#pragma once
// Internal: the physics judge in a batch (BatchParams::physics): the first grasps of a run, as the
// run returns them, executed nominally by the rigid-body simulation (docs/physics.md).
#include <memory>
#include <optional>
#include <vector>

#include "batch_records.h"
#include "skelgrasp/common/mesh.h"
#include "skelgrasp/evaluation/batch.h"
#include "skelgrasp/grasping/grasp.h"
#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/grasping/simulation/grasp_object.h"

namespace skelgrasp::physics {
class PhysicalObject;
}

namespace skelgrasp::evaluation::internal {

// The object as the engine moves it, built once per object and shared by its hands' runs.
std::shared_ptr<const physics::PhysicalObject> physicalObject(const TriangleMesh& mesh,
                                                              const PhysicsJudging& params);

// Executes the first params.grasps of `grasps` (at friction `mu`); `holds` gets one entry per
// grasp of `grasps` (unset for a grasp not judged).
PhysicsMeasures judgeGrasps(const grasping::HandModel& hand, const grasping::GraspObject& object,
                            const physics::PhysicalObject& physical,
                            const std::vector<grasping::Grasp>& grasps, double mu,
                            const PhysicsJudging& params, std::vector<std::optional<bool>>& holds);

}  // namespace skelgrasp::evaluation::internal
