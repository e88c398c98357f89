#include <random>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/grasping/planners.h"

namespace skelgrasp::grasping {

PlanResult planSurfaceGrasps(const HandModel& hand, const GraspObject& object,
                             const SurfacePlannerParams& params) {
  if (params.max_hypotheses == 0 && params.timeout_s <= 0) {
    throw InvalidArgument("planSurfaceGrasps: needs max_hypotheses or a timeout");
  }
  Stopwatch watch;
  PlanResult result;
  result.planner = "surface";
  auto& summary = result.summary;
  GraspSimulator simulator(hand, object);
  const Preshape& preshape = hand.preshape(params.preshape);
  const GraspType type = params.preshape == "precision" ? GraspType::kPrecision : GraspType::kPower;
  HypothesisParams hp = params.hypothesis;
  hp.quality = withHandContactModel(hp.quality, hand);
  hp.extra_retreat_m = 0;

  // Area-weighted face sampling.
  const auto& mesh = object.mesh();
  std::vector<double> areas(mesh.numFaces());
  for (std::size_t f = 0; f < mesh.numFaces(); ++f) areas[f] = mesh.faceArea(f);
  std::discrete_distribution<std::size_t> pick_face(areas.begin(), areas.end());
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::mt19937_64 rng(params.seed);

  ProgressReporter progress("surface planner", params.max_hypotheses, 5.0);
  while (true) {
    if (params.max_hypotheses > 0 && summary.hypotheses >= params.max_hypotheses) break;
    if (params.timeout_s > 0 && watch.seconds() > params.timeout_s) {
      summary.timed_out = true;
      break;
    }
    if (params.max_grasps > 0 && result.grasps.size() >= params.max_grasps) {
      summary.max_grasps_reached = true;
      break;
    }
    const std::size_t face = pick_face(rng);
    double a = unit(rng), b = unit(rng);
    if (a + b > 1) {
      a = 1 - a;
      b = 1 - b;
    }
    const auto& t = mesh.faces[face];
    const Eigen::Vector3d point = mesh.vertices[t[0]] +
                                  a * (mesh.vertices[t[1]] - mesh.vertices[t[0]]) +
                                  b * (mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    const Eigen::Vector3d normal = object.faceNormal(face);
    const double roll = kTwoPi * unit(rng);
    ++summary.hypotheses;
    ++summary.poses;
    progress.step(summary.hypotheses);
    if (normal.isZero()) {
      ++summary.rejections[reason::kTooFewSurfacePoints];
      continue;
    }
    const Eigen::Vector3d u = anyPerpendicular(normal), w = normal.cross(u);
    Pose gcp = Pose::Identity();
    gcp.linear() = frameFromZY(-normal, std::cos(roll) * u + std::sin(roll) * w);
    gcp.translation() = point;
    auto kept = countOutcome(evaluateHypothesis(simulator, gcp, preshape, hp), summary);
    if (!kept) continue;
    Grasp grasp = std::move(*kept);
    grasp.type = type;
    grasp.strategy = "surface";
    (type == GraspType::kPower ? summary.power : summary.precision) += 1;
    result.grasps.push_back(std::move(grasp));
  }
  finishPlan(result, watch.seconds());
  log().info(
      "surface planner ({}): {} hypotheses, {} generated, {} force closure ({:.0f}%), {:.2f} s",
      hand.name(), summary.hypotheses, summary.generated, summary.force_closure,
      100 * summary.forceClosureRate(), summary.planning_s);
  return result;
}

}  // namespace skelgrasp::grasping
