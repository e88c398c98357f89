#include "plan_options.h"

#include <fmt/format.h>

#include <cmath>
#include <optional>

#include "skelgrasp/common/error.h"
#include "skelgrasp/ranking/limits.h"

namespace skelgrasp::python {
namespace {

// Fewest vertices of a closed mesh (a tetrahedron): a smaller simplification budget is refused by
// the regularisation.
constexpr std::size_t kMinClosedMeshVertices = 4;

[[noreturn]] void refuse(const std::string& prefix, const char* field, const std::string& problem) {
  throw InvalidArgument(prefix + field + ": " + problem);
}

// A finite number in [min, max] (max infinite: no upper bound).
void checkFinite(const std::string& prefix, const char* field, double value, double min,
                 double max = INFINITY) {
  if (std::isfinite(value) && value >= min && value <= max) return;
  if (std::isinf(max))
    refuse(prefix, field, fmt::format("{} is not a finite number >= {}", value, min));
  refuse(prefix, field, fmt::format("{} is not a finite number in [{}, {}]", value, min, max));
}

// A finite number > 0.
void checkPositive(const std::string& prefix, const char* field, double value) {
  if (!(std::isfinite(value) && value > 0))
    refuse(prefix, field, fmt::format("{} is not a finite number > 0", value));
}

void checkOptionalFinite(const std::string& prefix, const char* field,
                         const std::optional<double>& value, double min, double max = INFINITY) {
  if (value) checkFinite(prefix, field, *value, min, max);
}

// A count of perturbed executions in [min, kMaxRobustnessSamples], the command line's range.
void checkSamples(const std::string& prefix, const char* field, int value, int min) {
  if (value < min || static_cast<std::uint64_t>(value) > ranking::kMaxRobustnessSamples)
    refuse(prefix, field,
           fmt::format("{} is outside [{}, {}]", value, min, ranking::kMaxRobustnessSamples));
}

}  // namespace

void validateQuality(const grasping::QualityParams& quality, const std::string& prefix) {
  checkFinite(prefix, "friction", quality.friction, 0, ranking::kMaxFriction);
  checkOptionalFinite(prefix, "torsional_friction_m", quality.torsional_friction_m, 0);
}

void validateSkeleton(const skeleton::SkeletonParams& skeleton, const std::string& prefix) {
  const auto& regularisation = skeleton.regularisation;
  checkPositive(prefix, "alpha_divisor", regularisation.alpha_divisor);
  checkPositive(prefix, "offset_divisor", regularisation.offset_divisor);
  checkFinite(prefix, "remesh_target_edge_m", regularisation.remesh_target_edge_m, 0);
  if (regularisation.max_vertices && *regularisation.max_vertices < kMinClosedMeshVertices)
    refuse(prefix, "max_vertices",
           fmt::format("{} is below the {} vertices of a closed mesh (None: never simplify)",
                       *regularisation.max_vertices, kMinClosedMeshVertices));
  checkFinite(prefix, "spur_radius_factor", skeleton.spur_radius_factor, 0);
  checkFinite(prefix, "curvature_stencil_m", skeleton.graph.curvature_stencil_m, 0);
}

void validateSkeletonPlanner(const grasping::SkeletonPlannerParams& planner,
                             const std::string& prefix) {
  checkFinite(prefix, "vertex_distance_m", planner.vertex_distance_m, 0);
  checkOptionalFinite(prefix, "round_ratio", planner.round_ratio, 0);
  checkFinite(prefix, "precision_retreat_m", planner.precision_retreat_m, 0);
  if (planner.refinement.max_evaluations < 0)
    refuse(prefix, "refine_evaluations",
           fmt::format("{} is negative", planner.refinement.max_evaluations));
}

void validateRobustness(const ranking::RobustnessParams& robustness, const std::string& prefix) {
  checkSamples(prefix, "samples", robustness.samples, 1);
}

void validateRobustRefinement(const ranking::RobustRefinementParams& refinement,
                              const std::string& prefix) {
  checkOptionalFinite(prefix, "search_below_r", refinement.search_below_r, 0, 1);
  checkSamples(prefix, "max_evaluations", refinement.max_evaluations, 0);
  checkSamples(prefix, "samples", refinement.samples, 1);
  checkFinite(prefix, "max_standoff_m", refinement.max_standoff_m, 0);
  checkSamples(prefix, "mean_shift_steps", refinement.mean_shift_steps, 0);
}

void validateRobustRanking(const ranking::RobustRankingParams& ranking, const std::string& prefix) {
  if (ranking.screen_samples) checkSamples(prefix, "screen_samples", *ranking.screen_samples, 1);
  if (ranking.confirm_samples) checkSamples(prefix, "confirm_samples", *ranking.confirm_samples, 0);
  checkOptionalFinite(prefix, "friction", ranking.friction, 0, ranking::kMaxFriction);
  validateRobustness(ranking.robustness, prefix + "robustness.");
  validateRobustRefinement(ranking.refinement, prefix + "refinement.");
}

ranking::PlanOptions PlanOptions::library() const {
  grasping::HypothesisParams hypothesis;
  hypothesis.min_epsilon = min_epsilon;
  hypothesis.quality = quality;
  hypothesis.closing = closing;
  if (quality.reference_compat) hypothesis.closing.contact_patch = grasping::ContactPatch::kCentre;

  ranking::PlanOptions options;
  options.planner = planner;
  options.skeleton = skeleton;
  options.skeleton_planner = skeleton_planner;
  options.skeleton_planner.timeout_s = timeout_s;
  options.skeleton_planner.max_grasps = max_grasps;
  options.skeleton_planner.seed = seed;
  options.skeleton_planner.hypothesis = hypothesis;
  options.surface_planner = surface_planner;
  options.surface_planner.timeout_s = timeout_s;
  options.surface_planner.max_grasps = max_grasps;
  options.surface_planner.seed = seed;
  options.surface_planner.hypothesis = hypothesis;
  options.ranking = ranking;
  options.ranking.robustness.seed = seed;
  ranking::setLoadCheck(options.ranking.robustness, ranking.robustness.load.has_value());
  return options;
}

void PlanOptions::validate() const {
  if (!(std::isfinite(timeout_s) && timeout_s >= 0 && timeout_s <= ranking::kMaxPlanTimeoutS))
    refuse("", "timeout_s",
           fmt::format("{} is not a finite number of seconds in [0, {}]", timeout_s,
                       ranking::kMaxPlanTimeoutS));
  checkFinite("", "min_epsilon", min_epsilon, 0);
  validateQuality(quality, "quality.");
  validateSkeleton(skeleton, "skeleton.");
  validateSkeletonPlanner(skeleton_planner, "skeleton_planner.");
  if (planner == ranking::Planner::kSurface && surface_planner.max_hypotheses == 0 &&
      timeout_s == 0)
    refuse("", "surface_planner.max_hypotheses", "0 (until the time limit) needs a timeout_s > 0");
  validateRobustRanking(ranking, "ranking.");
  library().validate();
}

}  // namespace skelgrasp::python
