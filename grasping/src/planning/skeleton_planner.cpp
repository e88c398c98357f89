#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/grasping/planning/planners.h"

#include "fallback_trigger.h"
#include "ordered_hypotheses.h"

namespace skelgrasp::grasping {
namespace {

using skeleton::Skeleton;
using skeleton::VertexType;

// Vertices to visit: along every segment, at least `distance` apart (endpoints always), then the
// branch vertices (which no strategy applies to, reported as such).
std::vector<int> selectVertices(const Skeleton& skel, double distance) {
  std::vector<int> selected;
  for (const auto& seg : skel.segments) {
    double since = distance;  // the first vertex is always taken
    for (std::size_t i = 0; i < seg.vertices.size(); ++i) {
      const int v = seg.vertices[i];
      if (i > 0)
        since += (skel.vertices[v].position - skel.vertices[seg.vertices[i - 1]].position).norm();
      if (since >= distance || skel.vertices[v].type == VertexType::kEndpoint) {
        selected.push_back(v);
        since = 0;
      }
    }
  }
  for (std::size_t v = 0; v < skel.vertices.size(); ++v) {
    if (skel.vertices[v].type == VertexType::kBranch) selected.push_back(static_cast<int>(v));
  }
  return selected;
}

// The hand poses of one strategy (paper Sec. IV-C; counts as the issue and reference).
std::vector<Pose> hypothesisFrames(const Eigen::Vector3d& s, const LocalShape& shape, bool endpoint,
                                   const SkeletonPlannerParams& params) {
  std::vector<Pose> frames;
  const Eigen::Vector3d& t = shape.tangent;
  if (endpoint) {
    // The hand comes in along the skeleton from outside; rolls about that axis.
    if (shape.round) {
      for (int k = 0; k < params.round_endpoint_rolls; ++k) {
        const double a = kTwoPi * k / params.round_endpoint_rolls;
        frames.push_back(poseFromZY(s, t, std::cos(a) * shape.ev1 + std::sin(a) * shape.ev2));
      }
    } else {
      frames.push_back(poseFromZY(s, t, shape.ev1));
      frames.push_back(poseFromZY(s, t, -shape.ev1));
    }
    return frames;
  }
  // Connecting: approach within the grasping plane, fingers spread along the skeleton; the roll
  // alternates so both hand orientations are tried.
  if (shape.round) {
    const int n = params.round_connecting_directions;
    for (int k = 0; k < n; ++k) {
      const double a = kTwoPi * k / n;
      const Eigen::Vector3d approach = -(std::cos(a) * shape.ev1 + std::sin(a) * shape.ev2);
      frames.push_back(poseFromZY(s, approach, k % 2 == 0 ? t : Eigen::Vector3d(-t)));
    }
  } else {
    // Rectangular: approach along the long section axis so the hand closes across the thin one.
    for (const Eigen::Vector3d& approach :
         {Eigen::Vector3d(shape.ev1), Eigen::Vector3d(-shape.ev1)}) {
      frames.push_back(poseFromZY(s, approach, t));
      frames.push_back(poseFromZY(s, approach, -t));
    }
  }
  return frames;
}

// Mean of the surface points of the local interval (the refinement's lateral target); the
// interval's first vertex when it has none.
Eigen::Vector3d localCentroid(const Skeleton& skel, const TriangleMesh& mesh,
                              const LocalShape& shape) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  std::size_t count = 0;
  for (int v : shape.interval) {
    for (int p : skel.vertices[v].surface_points) {
      sum += mesh.vertices[p];
      ++count;
    }
  }
  if (count == 0) return skel.vertices[shape.interval.front()].position;
  return sum / static_cast<double>(count);
}

// Table II: the strategy that applies to this vertex and grasp type, or the failed property.
const char* strategyFor(GraspType type, bool endpoint, const LocalShape& shape,
                        const ShapeThresholds& limits, std::string& strategy) {
  const bool precision = type == GraspType::kPrecision;
  if (shape.lambda2 < limits.lambda2_min_m || shape.lambda2 > limits.lambda2_max_m)
    return reason::kThicknessOutOfRange;
  if (endpoint) {
    strategy = precision ? "3" : "4";
    return nullptr;
  }
  if (shape.round) {
    strategy = precision ? "1a" : "2a";
    return nullptr;
  }
  const bool length_ok =
      precision ? shape.lambda1 >= limits.lambda1_min_m && shape.lambda1 <= limits.lambda1_max_m
                : shape.lambda1 > limits.lambda1_min_m;
  if (!length_ok) return reason::kLengthOutOfRange;
  strategy = precision ? "1b" : "2b";
  return nullptr;
}

}  // namespace

PlanResult planSkeletonGrasps(const HandModel& hand, const GraspObject& object,
                              const Skeleton& skel, const SkeletonPlannerParams& params) {
  if (params.vertex_distance_m < 0 || params.round_connecting_directions < 1 ||
      params.round_endpoint_rolls < 1) {
    throw InvalidArgument("planSkeletonGrasps: negative vertex distance or no approach directions");
  }
  if (!(params.precision_retreat_m >= 0) || !std::isfinite(params.precision_retreat_m))
    throw InvalidArgument("planSkeletonGrasps: precision retreat must be finite and >= 0");
  for (const auto& v : skel.vertices) {
    for (int p : v.surface_points) {
      if (p < 0 || static_cast<std::size_t>(p) >= object.mesh().numVertices()) {
        throw InvalidArgument(
            "planSkeletonGrasps: skeleton surface points do not index the object mesh");
      }
    }
  }
  Stopwatch watch;
  PlanResult result;
  result.planner = "skeleton";
  auto& summary = result.summary;
  LocalShapeParams shape_params;
  shape_params.curvature_limit_per_m = params.curvature_limit_per_m;
  shape_params.round_ratio = params.round_ratio.value_or(hand.thresholds().round_ratio);

  std::vector<int> order = selectVertices(skel, params.vertex_distance_m);
  if (params.shuffle_vertices)
    std::shuffle(order.begin(), order.end(), std::mt19937_64(params.seed));
  auto reject = [&](const char* why) {
    ++summary.hypotheses;
    ++summary.rejections[why];
  };
  const std::size_t grasp_limit = internal::skeletonGraspLimit(params);
  // What the strategies make of each visited vertex, in visiting order: a rejection (no pose), or
  // hand poses to close. Cheap; the closings are the plan's time and run on every core.
  struct Item {
    std::size_t visited = 0;  // vertices visited up to this one (progress)
    const char* rejection = nullptr;
    int vertex = -1;
    GraspType type = GraspType::kPrecision;
    std::string strategy;
    Pose frame = Pose::Identity();
    const Preshape* preshape = nullptr;
    RefinementFrame local;
  };
  std::vector<Item> items;
  // The hypothesis parameters of each grasp type (index 0 precision, 1 power).
  std::array<HypothesisParams, 2> hypothesis_params;
  for (GraspType type : {GraspType::kPrecision, GraspType::kPower}) {
    const bool precision = type == GraspType::kPrecision;
    HypothesisParams& hp = hypothesis_params[precision ? 0 : 1];
    hp = params.hypothesis;
    hp.quality = withHandContactModel(hp.quality, hand);
    hp.extra_retreat_m = precision ? params.precision_retreat_m : hand.thresholds().power_retreat_m;
  }
  std::size_t visited = 0;
  for (int vertex : order) {
    ++visited;
    const auto& v = skel.vertices[vertex];
    for (GraspType type : {GraspType::kPrecision, GraspType::kPower}) {
      const bool precision = type == GraspType::kPrecision;
      if ((precision && !params.precision) || (!precision && !params.power)) continue;
      Item item;
      item.visited = visited;
      item.vertex = vertex;
      item.type = type;
      if (v.type == VertexType::kBranch) {
        item.rejection = reason::kBranchVertex;
        items.push_back(std::move(item));
        continue;
      }
      const auto& limits = hand.thresholds().of(type);
      if (!limits) {
        item.rejection = reason::kGraspTypeDisabled;
        items.push_back(std::move(item));
        continue;
      }
      const double half = 0.5 * (precision ? hand.precisionIntervalM() : hand.powerIntervalM());
      const LocalShape shape =
          analyzeLocalShape(skel, object.mesh().vertices, vertex, half, shape_params);
      if (shape.reason) {
        item.rejection = shape.reason;
        items.push_back(std::move(item));
        continue;
      }
      const bool endpoint = v.type == VertexType::kEndpoint;
      if (const char* why = strategyFor(type, endpoint, shape, *limits, item.strategy)) {
        item.rejection = why;
        items.push_back(std::move(item));
        continue;
      }
      const std::vector<const Preshape*> preshapes = hand.plannerPreshapes(
          type, params.alternative_preshapes && !params.hypothesis.quality.reference_compat,
          object.principalLengthM());
      item.local = RefinementFrame{shape.tangent, localCentroid(skel, object.mesh(), shape)};
      for (const Pose& frame : hypothesisFrames(v.position, shape, endpoint, params)) {
        // Each preshape closed at the pose is a hand pose of its own.
        for (const Preshape* preshape : preshapes) {
          Item pose = item;
          pose.frame = frame;
          pose.preshape = preshape;
          items.push_back(std::move(pose));
        }
      }
    }
  }

  ProgressReporter progress("skeleton planner", order.size(), 5.0);
  internal::OrderedHypotheses run;
  run.count = items.size();
  run.evaluate = [&](GraspSimulator& simulator, std::size_t i) {
    const Item& item = items[i];
    if (item.rejection) return HypothesisOutcome{};
    const HypothesisParams& hp = hypothesis_params[item.type == GraspType::kPrecision ? 0 : 1];
    return evaluateRefinedHypothesis(simulator, item.frame, *item.preshape, hp, item.local,
                                     params.refinement);
  };
  run.stop = [&] {
    return internal::planLimitReached(watch, params.timeout_s, grasp_limit, result);
  };
  run.take = [&](std::size_t i, HypothesisOutcome&& outcome) {
    const Item& item = items[i];
    progress.step(item.visited);
    if (item.rejection) {
      reject(item.rejection);
      return;
    }
    ++summary.hypotheses;
    ++summary.poses;
    auto kept = countOutcome(std::move(outcome), summary);
    if (!kept) return;
    Grasp grasp = std::move(*kept);
    grasp.type = item.type;
    grasp.strategy = item.strategy;
    grasp.segment = skel.vertices[item.vertex].segment;
    grasp.skeleton_vertex = item.vertex;
    (item.type == GraspType::kPrecision ? summary.precision : summary.power) += 1;
    result.grasps.push_back(std::move(grasp));
  };
  internal::evaluateInOrder(hand, object, run);
  internal::addFallbackGrasps(hand, object, params, watch.seconds(), result);
  internal::addSurfaceCandidates(hand, object, params, watch.seconds(), result);
  finishPlan(result, watch.seconds());
  log().info(
      "skeleton planner ({}): {} hypotheses, {} generated, {} force closure ({:.0f}%), {} kept, "
      "{:.2f} s",
      hand.name(), summary.hypotheses, summary.generated, summary.force_closure,
      100 * summary.forceClosureRate(), result.grasps.size(), summary.planning_s);
  return result;
}

}  // namespace skelgrasp::grasping
