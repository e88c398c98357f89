#include "skelgrasp/ranking/robustness.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <optional>
#include <random>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/grasping/planning/hypothesis.h"

namespace skelgrasp::ranking {

RobustnessVariant parseRobustnessVariant(const std::string& text) {
  if (text == "paper") return RobustnessVariant::kPaper;
  if (text == "reference") return RobustnessVariant::kReference;
  if (text == "guarded") return RobustnessVariant::kGuarded;
  if (text == "settled") return RobustnessVariant::kSettled;
  throw InvalidArgument("unknown robustness variant '" + text +
                        "' (use paper, reference, guarded or settled)");
}

const char* toString(RobustnessVariant variant) {
  switch (variant) {
    case RobustnessVariant::kPaper:
      return "paper";
    case RobustnessVariant::kReference:
      return "reference";
    case RobustnessVariant::kGuarded:
      return "guarded";
    case RobustnessVariant::kSettled:
      return "settled";
  }
  return "?";
}

std::pair<double, double> wilsonInterval(int successes, int trials, double z) {
  if (trials <= 0) return {0.0, 1.0};
  const double n = trials, p = successes / n, z2 = z * z;
  const double centre = (p + z2 / (2 * n)) / (1 + z2 / n);
  const double half = z * std::sqrt(p * (1 - p) / n + z2 / (4 * n * n)) / (1 + z2 / n);
  // The interval always contains p: at p = 0 or 1 the bound on that side is exactly 0 or 1, which
  // rounding in centre -/+ half would miss by an ulp.
  return {std::clamp(centre - half, 0.0, p), std::clamp(centre + half, p, 1.0)};
}

namespace {
// The guarded approach starts as far out as the planner backs a hypothesis off at most and comes
// in by its retreat steps (HypothesisParams::max_retreat_m, retreat_step_m: 150 mm, 1 mm), coarse
// steps of kGuardedCoarseSteps first and then fine ones within the last coarse step, as the
// planner searches. A hand link is thicker than a coarse step (8 mm) along its approach, so no
// coarse step passes through an obstacle unseen.
constexpr int kGuardedCoarseSteps = 8;

// Where a guarded approach aimed at `target` (a hand pose whose open hand intersects the object)
// stops: the last free pose before the first touch, coming in along `approach` (object frame,
// unit, into the object). Searching outwards from `target` instead could end in a free pocket
// (inside a mug, between a handle and the body) that no approach from outside reaches. nullopt
// when even the start pose collides.
std::optional<Pose> guardedApproachStop(grasping::GraspSimulator& simulator, const Pose& target,
                                        const Eigen::Vector3d& approach,
                                        const grasping::Preshape& preshape) {
  const grasping::HypothesisParams placement;
  const int steps =
      static_cast<int>(std::floor(placement.max_retreat_m / placement.retreat_step_m + 1e-9));
  const auto poseAt = [&](int steps_out) {
    return Pose(Eigen::Translation3d(-steps_out * placement.retreat_step_m * approach) * target);
  };
  const auto touches = [&](int steps_out) {
    return simulator.inCollision(poseAt(steps_out), preshape.joints);
  };
  if (touches(steps)) return std::nullopt;
  int last_free = steps;
  int first_touch = 0;  // the target itself touches
  for (int i = steps - kGuardedCoarseSteps; i > 0; i -= kGuardedCoarseSteps) {
    if (touches(i)) {
      first_touch = i;
      break;
    }
    last_free = i;
  }
  for (int i = last_free - 1; i > first_touch; --i) {
    if (touches(i)) break;
    last_free = i;
  }
  return poseAt(last_free);
}

// The variants' pose errors (standard deviations) when RobustnessParams leaves them unset.
constexpr double kPaperPositionSigmaM = 0.010;
constexpr double kPaperOrientationSigmaDeg = 5.0;
constexpr double kReferencePositionSigmaM = 0.005;
constexpr double kReferenceOrientationSigmaDeg = 2.5;
}  // namespace

double positionSigmaM(const RobustnessParams& params) {
  return params.position_sigma_m.value_or(params.variant == RobustnessVariant::kReference
                                              ? kReferencePositionSigmaM
                                              : kPaperPositionSigmaM);
}

double orientationSigmaRad(const RobustnessParams& params) {
  return params.orientation_sigma_rad.value_or(radiansFromDegrees(
      params.variant == RobustnessVariant::kReference ? kReferenceOrientationSigmaDeg
                                                      : kPaperOrientationSigmaDeg));
}

PoseError samplePoseError(const RobustnessParams& params, std::uint64_t grasp_index, int sample) {
  // Paper: fresh samples per grasp; reference: one default-seeded sequence for every grasp. Each
  // sample draws from its own generator (base seed + sample index), so the samples, and the
  // score, do not depend on how many threads run them.
  const bool paper_samples = params.variant != RobustnessVariant::kReference;
  const std::uint64_t base_seed =
      paper_samples ? params.seed * 0x9E3779B97F4A7C15ULL + grasp_index : params.seed;
  std::seed_seq sample_seed{static_cast<std::uint32_t>(base_seed),
                            static_cast<std::uint32_t>(base_seed >> 32),
                            static_cast<std::uint32_t>(sample)};
  std::mt19937_64 rng(sample_seed);
  std::normal_distribution<double> position(0.0, positionSigmaM(params)),
      angle(0.0, orientationSigmaRad(params));
  PoseError error;
  error.translation = Eigen::Vector3d(position(rng), position(rng), position(rng));
  const double roll = angle(rng), pitch = angle(rng), yaw = angle(rng);
  error.rotation = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                    Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                    Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                       .toRotationMatrix();
  return error;
}

Eigen::Vector3d perturbationCentre(const grasping::Grasp& grasp) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& c : grasp.contacts)
    centre += c.point / static_cast<double>(grasp.contacts.size());
  return centre;
}

Pose perturbedPose(const Pose& pose, const PoseError& error, const Eigen::Vector3d& centre,
                   RobustnessVariant variant) {
  Pose move = Pose::Identity();
  move.linear() = error.rotation;
  move.translation() = error.translation;
  const Pose about = Eigen::Translation3d(centre) * move * Eigen::Translation3d(-centre);
  return variant == RobustnessVariant::kReference ? about.inverse() * pose : about * pose;
}

namespace {

// Samples [begin, end) of evaluateRobustness: the counts, held and score cover these only.
RobustnessResult evaluateSampleRange(grasping::GraspSimulator& simulator,
                                     const grasping::Grasp& grasp, const RobustnessParams& params,
                                     std::uint64_t grasp_index, int begin, int end,
                                     std::optional<int> max_failures) {
  if (grasp.contacts.empty()) throw InvalidArgument("robustness: the grasp has no contacts");
  Stopwatch watch;
  // The guarded variant draws and applies the paper's samples; only their execution differs.
  const bool paper_samples = params.variant != RobustnessVariant::kReference;
  const bool settled = params.variant == RobustnessVariant::kSettled;
  const bool guarded = params.variant == RobustnessVariant::kGuarded || settled;
  if ((params.position_sigma_m && !(*params.position_sigma_m >= 0)) ||
      (params.orientation_sigma_rad && !(*params.orientation_sigma_rad >= 0))) {
    throw InvalidArgument("robustness: pose error sigmas must be >= 0");
  }
  const Eigen::Vector3d centre = perturbationCentre(grasp);
  const auto& preshape = simulator.hand().preshape(grasp.preshape);
  grasping::ClosingParams closing = params.closing;
  if (!paper_samples) closing.palm_contacts = false;  // the reference adds no palm contacts here
  grasping::QualityParams quality = params.quality;
  // Only the verdict counts: with the LP test (default) no hull is built at all.
  quality.compute_volume = false;
  quality.compute_epsilon = false;
  // Guarded execution: the hand comes in along the perturbed pose's approach direction.
  const Eigen::Vector3d approach_in_hand =
      simulator.handPoseForGcp(Pose::Identity(), preshape).inverse().linear().col(2);
  enum Outcome : char {
    kNoForceClosure,
    kClosingFailed,
    kCollision,
    kForceClosure,
    kGuardedForceClosure,
    kSettledForceClosure,         // held after the object moved, from a free start
    kGuardedSettledForceClosure,  // the same after a guarded start
    kTooWeak,                     // force closure, but the load check failed
    kSkipped
  };
  // The load check of a closing that reached force closure (params.load).
  const grasping::QualityParams load_quality = quality;
  const auto strongEnough = [&](const grasping::GraspSimulator& local, const Pose& hand_pose,
                                const grasping::ClosingResult& closed) {
    if (!params.load) return true;
    const auto capacity =
        grasping::loadCapacity(local.hand(), hand_pose, closed.joints, closed.contacts,
                               local.object().centerOfMass(), load_quality, *params.load);
    return capacity.carries();
  };
  const auto heldOutcome = [](char outcome) {
    return outcome == kForceClosure || outcome == kGuardedForceClosure ||
           outcome == kSettledForceClosure || outcome == kGuardedSettledForceClosure;
  };
  std::vector<char> outcomes(end - begin, kSkipped);
  std::atomic<int> failures{0};
  const auto missedBar = [&] { return max_failures && failures.load() > *max_failures; };
  // A simulator moves its hand's collision objects: one per thread, sharing hand and object.
  tbb::enumerable_thread_specific<std::unique_ptr<grasping::GraspSimulator>> simulators([&] {
    return std::make_unique<grasping::GraspSimulator>(simulator.hand(), simulator.object());
  });
  // One perturbed execution of the settled variant: the guarded start, then settling.
  const auto executeSettled = [&](grasping::GraspSimulator& local, const Pose& hand_pose,
                                  const Eigen::Vector3d& approach_in_hand) -> Outcome {
    auto settling =
        grasping::settleGrasp(local, hand_pose, preshape, closing, quality, params.settling);
    const bool collides = settling.outcome == grasping::SettlingOutcome::kStartCollision;
    if (collides) {
      const std::optional<Pose> start =
          guardedApproachStop(local, hand_pose, hand_pose.linear() * approach_in_hand, preshape);
      if (!start) return kCollision;
      settling = grasping::settleGrasp(local, *start, preshape, closing, quality, params.settling);
    }
    if (settling.force_closure()) {
      if (!strongEnough(local, settling.hand_pose, settling.closing)) return kTooWeak;
      if (settling.steps > 0) return collides ? kGuardedSettledForceClosure : kSettledForceClosure;
      return collides ? kGuardedForceClosure : kForceClosure;
    }
    if (collides) return kCollision;
    return settling.outcome == grasping::SettlingOutcome::kTooFewContacts ? kClosingFailed
                                                                          : kNoForceClosure;
  };
  // One perturbed execution.
  const auto execute = [&](grasping::GraspSimulator& local, int i) -> Outcome {
    const Pose hand_pose = perturbedPose(grasp.hand_pose, samplePoseError(params, grasp_index, i),
                                         centre, params.variant);
    if (settled) return executeSettled(local, hand_pose, approach_in_hand);
    // close() starts with the collision test of the open hand: one test per sample, not two.
    auto closed = local.close(hand_pose, preshape, closing);
    const bool collides = closed.reason == grasping::reason::kStartCollision;
    std::optional<Pose> guardedStart;
    if (collides) {
      if (!guarded) return kCollision;
      guardedStart =
          guardedApproachStop(local, hand_pose, hand_pose.linear() * approach_in_hand, preshape);
      if (!guardedStart) return kCollision;
      closed = local.close(*guardedStart, preshape, closing);
    }
    // A guarded start that then fails is still a start in collision: the paper's pose was.
    if (!closed.status.ok()) return collides ? kCollision : kClosingFailed;
    if (grasping::evaluateGrasp(closed.contacts, local.object(), quality).force_closure) {
      const Pose at = collides ? Pose(*guardedStart) : hand_pose;
      if (!strongEnough(local, at, closed)) return kTooWeak;
      return collides ? kGuardedForceClosure : kForceClosure;
    }
    return collides ? kCollision : kNoForceClosure;
  };
  const auto runSample = [&](grasping::GraspSimulator& local, int i) {
    if (missedBar()) return;  // stays kSkipped
    outcomes[i - begin] = execute(local, i);
    if (!heldOutcome(outcomes[i - begin])) ++failures;
  };
  if (end - begin == 1 || tbb::this_task_arena::max_concurrency() == 1) {
    // Nothing to share out (best-first screening runs one sample at a time): on the caller's
    // simulator, not on a new one per call.
    for (int i = begin; i < end; ++i) runSample(simulator, i);
  } else {
    tbb::parallel_for(begin, end, [&](int i) { runSample(*simulators.local(), i); });
  }

  RobustnessResult result;
  result.samples = end - begin;
  result.gave_up = missedBar();
  result.held.resize(outcomes.size());
  for (std::size_t i = 0; i < outcomes.size(); ++i) result.held[i] = heldOutcome(outcomes[i]);
  for (char outcome : outcomes) {
    const bool guarded_hold =
        outcome == kGuardedForceClosure || outcome == kGuardedSettledForceClosure;
    result.collisions += outcome == kCollision || guarded_hold;
    result.guarded_holds += guarded_hold;
    result.settled_holds +=
        outcome == kSettledForceClosure || outcome == kGuardedSettledForceClosure;
    result.force_closure += heldOutcome(outcome);
    result.closing_failures += outcome == kClosingFailed;
    result.no_force_closure += outcome == kNoForceClosure;
    result.too_weak += outcome == kTooWeak;
  }
  result.score = static_cast<double>(result.force_closure) / result.samples;
  std::tie(result.wilson_low, result.wilson_high) =
      wilsonInterval(result.force_closure, result.samples);
  result.time_s = watch.seconds();
  return result;
}

}  // namespace

RobustnessResult evaluateRobustness(grasping::GraspSimulator& simulator,
                                    const grasping::Grasp& grasp, const RobustnessParams& params,
                                    std::uint64_t grasp_index, std::optional<int> max_failures) {
  if (params.samples < 1) throw InvalidArgument("robustness: need at least one sample");
  return evaluateSampleRange(simulator, grasp, params, grasp_index, 0, params.samples,
                             max_failures);
}

RobustnessResult evaluateRobustnessSamples(grasping::GraspSimulator& simulator,
                                           const grasping::Grasp& grasp,
                                           const RobustnessParams& params,
                                           std::uint64_t grasp_index, int begin, int end) {
  if (!(begin >= 0 && begin < end && end <= params.samples))
    throw InvalidArgument("robustness: need 0 <= begin < end <= samples");
  return evaluateSampleRange(simulator, grasp, params, grasp_index, begin, end, std::nullopt);
}

}  // namespace skelgrasp::ranking
