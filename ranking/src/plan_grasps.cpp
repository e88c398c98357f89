#include "skelgrasp/ranking/plan_grasps.h"

#include <algorithm>
#include <numeric>

#include "skelgrasp/common/logging.h"
#include "skelgrasp/geometry/mesh_validity.h"

namespace skelgrasp::ranking {
namespace {

// A grasp refinement for robustness moved touches elsewhere: its rank score becomes r x its own
// trust, and the scored grasps (they lead) are sorted again by rank score, stably, so that grasps
// the new trust leaves in place keep the ranking's order; ids are renumbered.
void retrustMovedGrasps(GraspPlan& plan,
                        const std::function<double(const grasping::Grasp&)>& trust) {
  auto& scores = plan.ranking.scores;
  std::size_t scored = 0;
  for (std::size_t i = 0; i < plan.grasps.size(); ++i) {
    const auto& robustness = plan.grasps[i].robustness;
    if (!robustness) break;
    ++scored;
    if (robustness->refinement && robustness->refinement->refined)
      scores[i] = robustness->r * trust(plan.grasps[i]);
  }
  std::vector<std::size_t> by_score(scored);
  std::iota(by_score.begin(), by_score.end(), 0);
  std::stable_sort(by_score.begin(), by_score.end(),
                   [&](std::size_t a, std::size_t b) { return scores[a] > scores[b]; });
  std::vector<grasping::Grasp> grasps;
  std::vector<double> sorted_scores;
  std::vector<std::size_t> order;
  for (std::size_t k : by_score) {
    grasps.push_back(std::move(plan.grasps[k]));
    sorted_scores.push_back(scores[k]);
    order.push_back(plan.ranking.order[k]);
  }
  std::move(grasps.begin(), grasps.end(), plan.grasps.begin());
  std::copy(sorted_scores.begin(), sorted_scores.end(), scores.begin());
  std::copy(order.begin(), order.end(), plan.ranking.order.begin());
  for (std::size_t i = 0; i < plan.grasps.size(); ++i) plan.grasps[i].id = static_cast<int>(i);
}

}  // namespace

Planner parsePlanner(const std::string& name) {
  for (const Planner planner : {Planner::kSkeleton, Planner::kSurface}) {
    if (name == toString(planner)) return planner;
  }
  throw InvalidArgument("unknown planner '" + name + "' (use skeleton, surface)");
}

const char* toString(Planner planner) {
  switch (planner) {
    case Planner::kSkeleton:
      return "skeleton";
    case Planner::kSurface:
      break;
  }
  return "surface";
}

const grasping::HypothesisParams& PlanOptions::hypothesis() const {
  return planner == Planner::kSkeleton ? skeleton_planner.hypothesis : surface_planner.hypothesis;
}

void PlanOptions::validate() const {
  if (planner != Planner::kSkeleton && planner != Planner::kSurface)
    throw InvalidArgument("planGrasps: unknown planner");
  checkRobustRankingParams(ranking);
}

double PlanTiming::total_s() const {
  return regularise_s.value_or(0.0) + skeleton_s.value_or(0.0) + planning_s + ranking_s;
}

PlanTiming planTimingOf(const skeleton::SkeletonTimings* skeleton, double planning_s,
                        double ranking_s) {
  PlanTiming timing;
  if (skeleton) {
    timing.regularise_s = skeleton->regularise_s;
    // Both from stopwatches, the total's around the regularisation's: never below it but by
    // rounding.
    timing.skeleton_s = std::max(0.0, skeleton->total_s - skeleton->regularise_s);
  }
  timing.planning_s = planning_s;
  timing.ranking_s = ranking_s;
  return timing;
}

GraspPlan planGrasps(const TriangleMesh& mesh, const grasping::HandModel& hand,
                     const PlanOptions& options) {
  options.validate();
  const grasping::GraspObject object(mesh);
  return planGrasps(object, hand, options);
}

GraspPlan planGrasps(const grasping::GraspObject& object, const grasping::HandModel& hand,
                     const PlanOptions& options, const PlanInputs& inputs) {
  options.validate();
  GraspPlan plan;
  // A mesh without area is bad input for either planner (the alpha wrap crashed on it, the
  // surface planner sampled it until its time limit): refused as the skeleton stage refuses it.
  if (const std::string problem = geometry::degenerateMeshProblem(object.mesh());
      !problem.empty()) {
    plan.status = Status::Make(StatusCode::kInvalidInput, problem);
    plan.skeleton_failed = true;
    return plan;
  }
  grasping::PlanResult& planned = plan;
  const skeleton::SkeletonResult* skeleton = nullptr;
  if (options.planner == Planner::kSkeleton) {
    skeleton = inputs.skeleton;
    if (skeleton == nullptr) {
      plan.skeleton = skeleton::extractSkeleton(object.mesh(), options.skeleton);
      skeleton = &*plan.skeleton;
    }
    if (!skeleton->status.ok()) {
      plan.status = skeleton->status;
      plan.skeleton_failed = true;
      plan.timing = planTimingOf(&skeleton->timing, 0, 0);
      return plan;
    }
    planned =
        grasping::planSkeletonGrasps(hand, object, skeleton->skeleton, options.skeleton_planner);
  } else {
    planned = grasping::planSurfaceGrasps(hand, object, options.surface_planner);
  }

  const Stopwatch watch;
  std::vector<double> trust;
  if (inputs.trust) {
    for (const auto& grasp : plan.grasps) trust.push_back(inputs.trust(grasp));
  }
  plan.ranking = rankByRobustness(hand, object, std::move(plan.grasps), options.hypothesis(),
                                  options.ranking, trust);
  plan.grasps = std::move(plan.ranking.grasps);
  plan.ranking.grasps.clear();
  if (inputs.trust) retrustMovedGrasps(plan, inputs.trust);
  // The ranking's time with the trust's: the scan's observed contacts are a part of ranking.
  plan.timing = planTimingOf(skeleton ? &skeleton->timing : nullptr, plan.summary.planning_s,
                             watch.seconds());
  return plan;
}

}  // namespace skelgrasp::ranking
