#include "skelgrasp/grasping/planning/fallback_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>

#include "fallback_trigger.h"
#include "ordered_hypotheses.h"
#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/grasping/planning/scene.h"

namespace skelgrasp::grasping {
namespace {

// The golden angle (radians): successive Fibonacci directions turn by it about the polar axis,
// which spreads any number of them evenly over the sphere.
const double kGoldenAngleRad = kPi * (3.0 - std::sqrt(5.0));
// A principal axis this close to the support normal (sine of the angle) has no horizontal
// direction to speak of.
constexpr double kMinHorizontalComponent = 0.1;
// A top pose centred across its closing axis by less than this is the pose at the centre of mass
// again: no second pose.
constexpr double kMinCentringShiftM = 0.001;
// Poses this close (metres, and in rotation matrix entries) are the same pose: two strategies that
// propose one pose compute it by the same arithmetic, so they agree to rounding.
constexpr double kSamePoseTolerance = 1e-9;

struct FallbackPose {
  Pose gcp;
  const char* strategy;
};

// n unit vectors spread evenly over the sphere (Fibonacci lattice).
std::vector<Eigen::Vector3d> fibonacciDirections(int n) {
  std::vector<Eigen::Vector3d> directions;
  for (int k = 0; k < n; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / n;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = kGoldenAngleRad * k;
    directions.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
  }
  return directions;
}

void addSpherePoses(const Eigen::Vector3d& centre, const FallbackStrategyParams& p,
                    std::vector<FallbackPose>& poses) {
  const auto directions = fibonacciDirections(p.sphere_directions);
  for (std::size_t k = 0; k < directions.size(); ++k) {
    const Eigen::Vector3d approach = -directions[k];  // from outside towards the centre
    const Eigen::Vector3d u = anyPerpendicular(approach), w = approach.cross(u);
    // A per-direction phase so neighbouring directions do not all share the same rolls.
    const double phase = kGoldenAngleRad * static_cast<double>(k);
    for (int r = 0; r < p.sphere_rolls; ++r) {
      const double a = phase + kTwoPi * r / p.sphere_rolls;
      poses.push_back({poseFromZY(centre, approach, std::cos(a) * u + std::sin(a) * w), "sphere"});
    }
  }
}

void addRimPoses(const Eigen::Vector3d& centre, const PrincipalAxes& pa,
                 const FallbackStrategyParams& p, std::vector<FallbackPose>& poses) {
  const Eigen::Vector3d e1 = pa.axes.col(0), e2 = pa.axes.col(1), thin = pa.axes.col(2);
  // In the disc plane: the fingers close along x = thin (spread y = approach x thin), a pinch
  // across the thickness at the rim, with both thumb sides.
  for (int k = 0; k < p.rim_directions; ++k) {
    const double a = kTwoPi * k / p.rim_directions;
    const Eigen::Vector3d approach = -(std::cos(a) * e1 + std::sin(a) * e2);
    const Eigen::Vector3d spread = approach.cross(thin);
    poses.push_back({poseFromZY(centre, approach, spread), "rim"});
    poses.push_back({poseFromZY(centre, approach, -spread), "rim"});
  }
  // Across: along the thin axis (from both faces), rolls half-way between the axis-aligned rolls
  // of the "axes" strategy so the two do not repeat each other.
  for (const Eigen::Vector3d& approach : {Eigen::Vector3d(thin), Eigen::Vector3d(-thin)}) {
    for (int r = 0; r < p.rim_across_rolls; ++r) {
      const double a = kPi / 4 + kTwoPi * r / p.rim_across_rolls;
      poses.push_back({poseFromZY(centre, approach, std::cos(a) * e1 + std::sin(a) * e2), "rim"});
    }
  }
}

void addAxisPoses(const Eigen::Vector3d& centre, const PrincipalAxes& pa,
                  std::vector<FallbackPose>& poses) {
  for (int i = 0; i < 3; ++i) {
    for (double sign : {1.0, -1.0}) {
      const Eigen::Vector3d approach = sign * pa.axes.col(i);
      for (int j = 0; j < 3; ++j) {
        if (j == i) continue;
        poses.push_back({poseFromZY(centre, approach, pa.axes.col(j)), "axes"});
        poses.push_back({poseFromZY(centre, approach, -pa.axes.col(j)), "axes"});
      }
    }
  }
}

// The object's longest direction in the support plane: the horizontal principal axis along which
// its surface spreads most (the fingers spread along it and close across the narrow side).
Eigen::Vector3d longestHorizontalAxis(const PrincipalAxes& pa, const Eigen::Vector3d& up) {
  Eigen::Vector3d best = anyPerpendicular(up);
  double best_spread = -1;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d horizontal = pa.axes.col(i) - pa.axes.col(i).dot(up) * up;
    const double spread = pa.sd(i) * horizontal.norm();
    if (spread > best_spread && horizontal.norm() > kMinHorizontalComponent) {
      best_spread = spread;
      best = horizontal.normalized();
    }
  }
  return best;
}

void addTopPoses(const Eigen::Vector3d& centre, const PrincipalAxes& pa, const Eigen::Vector3d& up,
                 const FallbackStrategyParams& p, std::vector<FallbackPose>& poses) {
  const Eigen::Vector3d h1 = longestHorizontalAxis(pa, up), h2 = up.cross(h1);
  // Straight down, the first roll spreading the fingers along the longest horizontal axis (so
  // rolls at quarter turns are aligned with the object).
  for (int r = 0; r < p.top_rolls; ++r) {
    const double a = kTwoPi * r / p.top_rolls;
    poses.push_back({poseFromZY(centre, -up, std::cos(a) * h1 + std::sin(a) * h2), "top"});
  }
  // Tilted towards the object from several sides: the hand's body stays above the neighbours
  // while its fingers reach down a side that has room.
  for (int m = 0; m < p.top_tilted_azimuths; ++m) {
    const double b = kTwoPi * m / p.top_tilted_azimuths;
    const Eigen::Vector3d side = std::cos(b) * h1 + std::sin(b) * h2;
    const Eigen::Vector3d approach =
        -std::cos(p.top_tilt_rad) * up - std::sin(p.top_tilt_rad) * side;
    const Eigen::Vector3d s0 = side.cross(up).normalized(), s1 = approach.cross(s0);
    for (int r = 0; r < p.top_tilted_rolls; ++r) {
      const double a = kTwoPi * r / p.top_tilted_rolls;
      poses.push_back({poseFromZY(centre, approach, std::cos(a) * s0 + std::sin(a) * s1), "top"});
    }
  }
}

// Moves a pose along its closing axis x to the middle of the object's extent along x among the
// vertices within `band` of its centre across y and z
// (FallbackStrategyParams::top_centring_band_m). Unchanged when no vertex lies in that slab.
void centreAcrossClosingAxis(const TriangleMesh& mesh, double band, Pose& gcp) {
  const Eigen::Matrix3d frame = gcp.rotation();
  const Eigen::Vector3d centre = gcp.translation();
  double low = std::numeric_limits<double>::infinity();
  double high = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& v : mesh.vertices) {
    const Eigen::Vector3d local = frame.transpose() * (v - centre);
    if (std::abs(local.y()) > band || std::abs(local.z()) > band) continue;
    low = std::min(low, local.x());
    high = std::max(high, local.x());
  }
  if (low <= high) gcp.translation() += 0.5 * (low + high) * frame.col(0);
}

// Appends, for every pose from `first` on, its twin centred across the closing axis, where that
// moves it by more than kMinCentringShiftM.
void addCentredTwins(const TriangleMesh& mesh, double band, std::size_t first,
                     std::vector<FallbackPose>& poses) {
  const std::size_t end = poses.size();
  for (std::size_t i = first; i < end; ++i) {
    FallbackPose centred = poses[i];
    centreAcrossClosingAxis(mesh, band, centred.gcp);
    if ((centred.gcp.translation() - poses[i].gcp.translation()).norm() > kMinCentringShiftM)
      poses.push_back(centred);
  }
}

// Drops every pose that repeats an earlier one (the first strategy's name stays). On a disc the
// rim's in-plane approaches at quarter turns are also principal-axis approaches with the same roll:
// closed twice, such a pose is the same grasp twice in the plan, screened and scored twice by the
// robust ranking and returned twice among the best. Returns how many were dropped.
std::size_t dropRepeatedPoses(std::vector<FallbackPose>& poses) {
  std::vector<FallbackPose> distinct;
  distinct.reserve(poses.size());
  for (auto& pose : poses) {
    const bool repeated = std::any_of(distinct.begin(), distinct.end(), [&](const FallbackPose& d) {
      return (d.gcp.translation() - pose.gcp.translation()).cwiseAbs().maxCoeff() <=
                 kSamePoseTolerance &&
             (d.gcp.linear() - pose.gcp.linear()).cwiseAbs().maxCoeff() <= kSamePoseTolerance;
    });
    if (!repeated) distinct.push_back(std::move(pose));
  }
  const std::size_t dropped = poses.size() - distinct.size();
  poses = std::move(distinct);
  return dropped;
}

void validate(const FallbackStrategyParams& p) {
  if (p.sphere_directions < 1 || p.sphere_rolls < 1 || p.rim_directions < 1 ||
      p.rim_across_rolls < 1 || p.top_rolls < 1 || p.top_tilted_azimuths < 0 ||
      p.top_tilted_rolls < 1 || !(p.top_tilt_rad >= 0 && p.top_tilt_rad < kPi / 2) ||
      !(p.disc_ratio >= 0) || !(p.top_centring_band_m >= 0) || !(p.precision || p.power)) {
    throw InvalidArgument(
        "fallback strategies: direction and roll counts must be >= 1 (tilted top azimuths >= 0), "
        "the top tilt in [0, pi/2), disc_ratio and the top centring band >= 0 and at least one "
        "preshape");
  }
}

// Counts and grasps of `from` added to `into` (a plan in progress; finishPlan sorts later and sets
// the whole plan's time).
void appendPlan(PlanResult& into, PlanResult&& from) {
  into.summary.add(from.summary);
  for (auto& g : from.grasps) into.grasps.push_back(std::move(g));
}

}  // namespace

PlanResult planFallbackGrasps(const HandModel& hand, const GraspObject& object,
                              const FallbackPlannerParams& params) {
  const FallbackStrategyParams& sp = params.strategies;
  validate(sp);
  Stopwatch watch;
  PlanResult result;
  result.planner = "fallback";
  auto& summary = result.summary;

  const Eigen::Vector3d centre = object.centerOfMass();
  const PrincipalAxes& pa = object.principalAxes();
  const bool disc = pa.sd(1) > 0 && pa.sd(2) < sp.disc_ratio * pa.sd(1);
  std::vector<FallbackPose> poses;
  if (sp.sphere) addSpherePoses(centre, sp, poses);
  if (sp.rim && disc) addRimPoses(centre, pa, sp, poses);
  if (sp.axes) addAxisPoses(centre, pa, poses);
  const SceneChecker* scene = params.hypothesis.scene;
  const bool top = sp.top && scene != nullptr && scene->plane().has_value();
  if (top) {
    const std::size_t first_top = poses.size();
    addTopPoses(centre, pa, scene->plane()->coefficients.head<3>(), sp, poses);
    if (sp.top_centring_band_m > 0)
      addCentredTwins(object.mesh(), sp.top_centring_band_m, first_top, poses);
  }
  const std::size_t repeated = dropRepeatedPoses(poses);

  struct Trial {
    std::size_t pose;
    GraspType type;
    const Preshape* preshape;
  };
  // The grasp types the hand does (its thresholds say which), each with its preshapes, as the
  // skeleton planner.
  std::vector<std::pair<GraspType, const Preshape*>> closings;
  for (GraspType type : {GraspType::kPrecision, GraspType::kPower}) {
    const bool asked = type == GraspType::kPrecision ? sp.precision : sp.power;
    if (!asked || !hand.thresholds().of(type)) continue;
    for (const Preshape* preshape : hand.plannerPreshapes(
             type, sp.alternative_preshapes && !params.hypothesis.quality.reference_compat,
             object.principalLengthM()))
      closings.emplace_back(type, preshape);
  }
  std::vector<Trial> trials;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    for (const auto& [type, preshape] : closings) trials.push_back({i, type, preshape});
  }
  std::shuffle(trials.begin(), trials.end(), std::mt19937_64(params.seed));

  HypothesisParams hp = params.hypothesis;
  hp.quality = withHandContactModel(hp.quality, hand);
  HypothesisParams precision_hp = hp, power_hp = hp;
  precision_hp.extra_retreat_m = 0.0;
  power_hp.extra_retreat_m = hand.thresholds().power_retreat_m;

  ProgressReporter progress("fallback planner", trials.size(), 5.0);
  internal::OrderedHypotheses run;
  run.count = trials.size();
  run.evaluate = [&](GraspSimulator& simulator, std::size_t i) {
    const Trial& trial = trials[i];
    return evaluateHypothesis(simulator, poses[trial.pose].gcp, *trial.preshape,
                              trial.type == GraspType::kPrecision ? precision_hp : power_hp);
  };
  run.stop = [&] {
    return internal::planLimitReached(watch, params.timeout_s, params.max_grasps, result);
  };
  run.take = [&](std::size_t i, HypothesisOutcome&& outcome) {
    const Trial& trial = trials[i];
    ++summary.hypotheses;
    ++summary.poses;
    progress.step(summary.hypotheses);
    auto kept = countOutcome(std::move(outcome), summary);
    if (!kept) return;
    Grasp grasp = std::move(*kept);
    grasp.type = trial.type;
    grasp.strategy = poses[trial.pose].strategy;
    grasp.segment = -1;
    grasp.skeleton_vertex = -1;
    (trial.type == GraspType::kPrecision ? summary.precision : summary.power) += 1;
    result.grasps.push_back(std::move(grasp));
  };
  internal::evaluateInOrder(hand, object, run);
  finishPlan(result, watch.seconds());
  log().info("fallback planner ({}): {} poses{}{}{}, {} generated, {} force closure, {:.2f} s",
             hand.name(), summary.poses, disc ? " (disc)" : "", top ? " (top)" : "",
             repeated ? " (" + std::to_string(repeated) + " repeated poses dropped)" : "",
             summary.generated, summary.force_closure, summary.planning_s);
  return result;
}

namespace internal {

std::size_t skeletonGraspLimit(const SkeletonPlannerParams& params) {
  if (params.max_grasps == 0 || !params.fallback || !params.centre_candidates)
    return params.max_grasps;
  return (params.max_grasps + 1) / 2;
}

namespace {

// What a strategy run after the others may still spend: the time and grasp count the plan has left
// (0: no limit). nullopt when the caller's limit is reached (max_grasps_reached) or the time is up
// (timed_out); both flags are the plan's from here on.
struct Budget {
  double timeout_s = 0;
  std::size_t max_grasps = 0;
};
std::optional<Budget> budgetLeft(const SkeletonPlannerParams& params, double elapsed_s,
                                 PlanResult& result) {
  auto& summary = result.summary;
  summary.max_grasps_reached = params.max_grasps > 0 && result.grasps.size() >= params.max_grasps;
  if (summary.max_grasps_reached) return std::nullopt;
  Budget budget;
  if (params.timeout_s > 0) {
    budget.timeout_s = params.timeout_s - elapsed_s;
    if (budget.timeout_s <= 0) {
      summary.timed_out = true;
      return std::nullopt;
    }
  }
  if (params.max_grasps > 0) budget.max_grasps = params.max_grasps - result.grasps.size();
  return budget;
}

}  // namespace

void addFallbackGrasps(const HandModel& hand, const GraspObject& object,
                       const SkeletonPlannerParams& params, double elapsed_s, PlanResult& result) {
  auto& summary = result.summary;
  if (!params.fallback || summary.timed_out) return;
  // Skeleton strategies stopped by (their share of) a grasp limit have enough grasps: no fallback.
  const char* why = nullptr;
  if (!summary.max_grasps_reached) {
    if (summary.poses == 0) {
      why = reason::kFallbackNoSegment;
    } else if (result.grasps.size() < params.fallback_min_grasps) {
      why = reason::kFallbackFewGrasps;
    }
  }
  if (!why && !params.centre_candidates) return;
  const std::optional<Budget> budget = budgetLeft(params, elapsed_s, result);
  if (!budget) return;
  FallbackPlannerParams fp;
  fp.seed = params.seed;
  fp.strategies = params.fallback_strategies;
  fp.strategies.alternative_preshapes = params.alternative_preshapes;
  fp.hypothesis = params.hypothesis;
  fp.timeout_s = budget->timeout_s;
  fp.max_grasps = budget->max_grasps;
  if (why) {
    // The trigger is recorded as one more rejected hypothesis (the skeleton strategies as a
    // whole), so the rejection counts still add up to the hypotheses that were not kept.
    ++summary.hypotheses;
    ++summary.rejections[why];
    log().info("skeleton planner ({}): {} grasps from the skeleton, running the fallback ({})",
               hand.name(), result.grasps.size(), why);
  } else {
    // Centre candidates: the poses about the centre, closed with every preshape the hand plans
    // with (a type the hand does not do is skipped by the fallback). Since the settled judge the
    // precision ones add grasps the ranking picks: fingertip grasps that the object settles into,
    // on handles, small parts and round fruit (docs/results.md, "Centre candidates with their
    // precision grasps"). The rim poses are for discs, which the skeleton serves poorly anyway
    // and then get the whole fallback.
    fp.strategies.rim = false;
    fp.strategies.power = true;
    fp.strategies.precision = true;
    log().info("skeleton planner ({}): {} grasps from the skeleton, adding the centre candidates",
               hand.name(), result.grasps.size());
  }
  appendPlan(result, planFallbackGrasps(hand, object, fp));
}

void addSurfaceCandidates(const HandModel& hand, const GraspObject& object,
                          const SkeletonPlannerParams& params, double elapsed_s,
                          PlanResult& result) {
  if (params.surface_candidates == 0 || result.summary.timed_out) return;
  if (!hand.preshapes().count("power")) return;  // the surface planner closes the power preshape
  const std::optional<Budget> budget = budgetLeft(params, elapsed_s, result);
  if (!budget) return;
  SurfacePlannerParams sp;
  sp.max_hypotheses = params.surface_candidates;
  sp.seed = params.seed;
  sp.hypothesis = params.hypothesis;
  sp.timeout_s = budget->timeout_s;
  sp.max_grasps = budget->max_grasps;
  log().info("skeleton planner ({}): {} grasps so far, adding {} surface candidates", hand.name(),
             result.grasps.size(), params.surface_candidates);
  appendPlan(result, planSurfaceGrasps(hand, object, sp));
}

}  // namespace internal
}  // namespace skelgrasp::grasping
