#include <limits>
#include <random>

#include "ordered_hypotheses.h"

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/grasping/planning/planners.h"

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

  // The poses are drawn from the stream in hypothesis order (prepare), so they do not depend on how
  // many threads close them. A zero normal (a degenerate face) is no pose.
  struct SurfacePose {
    bool valid = false;
    Pose gcp = Pose::Identity();
  };
  std::vector<SurfacePose> drawn;  // hypotheses drawn_first, drawn_first + 1, ...
  std::size_t drawn_first = 0;
  const auto draw = [&] {
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
    SurfacePose pose;
    if (normal.isZero()) return pose;
    const Eigen::Vector3d u = anyPerpendicular(normal), w = normal.cross(u);
    pose.valid = true;
    pose.gcp.linear() = frameFromZY(-normal, std::cos(roll) * u + std::sin(roll) * w);
    pose.gcp.translation() = point;
    return pose;
  };

  ProgressReporter progress("surface planner", params.max_hypotheses, 5.0);
  internal::OrderedHypotheses run;
  run.count =
      params.max_hypotheses > 0 ? params.max_hypotheses : std::numeric_limits<std::size_t>::max();
  run.prepare = [&](std::size_t first, std::size_t end) {
    drawn_first = first;
    drawn.resize(end - first);
    for (auto& pose : drawn) pose = draw();
  };
  run.evaluate = [&](GraspSimulator& simulator, std::size_t i) {
    const SurfacePose& pose = drawn[i - drawn_first];
    if (!pose.valid) {
      HypothesisOutcome rejected;
      rejected.reason = reason::kTooFewSurfacePoints;
      return rejected;
    }
    return evaluateHypothesis(simulator, pose.gcp, preshape, hp);
  };
  run.stop = [&] {
    return internal::planLimitReached(watch, params.timeout_s, params.max_grasps, result);
  };
  run.take = [&](std::size_t, HypothesisOutcome&& outcome) {
    ++summary.hypotheses;
    ++summary.poses;
    progress.step(summary.hypotheses);
    auto kept = countOutcome(std::move(outcome), summary);
    if (!kept) return;
    Grasp grasp = std::move(*kept);
    grasp.type = type;
    grasp.strategy = "surface";
    (type == GraspType::kPower ? summary.power : summary.precision) += 1;
    result.grasps.push_back(std::move(grasp));
  };
  internal::evaluateInOrder(hand, object, run);
  finishPlan(result, watch.seconds());
  log().info(
      "surface planner ({}): {} hypotheses, {} generated, {} force closure ({:.0f}%), {:.2f} s",
      hand.name(), summary.hypotheses, summary.generated, summary.force_closure,
      100 * summary.forceClosureRate(), summary.planning_s);
  return result;
}

}  // namespace skelgrasp::grasping
