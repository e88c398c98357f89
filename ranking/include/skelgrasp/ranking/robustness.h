#pragma once
// Robustness score r of a grasp (paper Sec. V-B, after Weisz & Allen): the fraction of perturbed
// hand poses that still close to a force-closure grasp.
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "skelgrasp/grasping/grasp.h"
#include "skelgrasp/grasping/hand/hand_strength.h"
#include "skelgrasp/grasping/quality/load_capacity.h"
#include "skelgrasp/grasping/quality/quality.h"
#include "skelgrasp/grasping/quality/settling.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"

namespace skelgrasp::ranking {

enum class RobustnessVariant {
  kPaper,      // the hand is moved; sigma 10 mm and 5 degrees; fresh samples per grasp
  kReference,  // the reference code: the object is moved; sigma 5 mm and 2.5 degrees; the same
               // samples for every grasp (fact sheet §11)
  kGuarded,    // the paper's samples, executed with a guarded approach: for a perturbed pose
               // whose open hand hits the object the hand comes in along its approach direction
               // from 150 mm out and stops before the first touch, then closes, instead of the
               // sample failing. The paper's Sec. V-B names this as the more detailed alternative
               // ("considering the approach movement"). Every sample that holds in kPaper holds
               // here too.
  kSettled,    // the guarded variant's executions, with the object free to move: a closing that
               // is not force closure settles (grasping/quality/settling.h), the object pushed
               // by the unbalanced squeeze until the contacts hold it, are balanced without
               // closure, or it is pushed out of the hand. Every sample that holds in kGuarded
               // holds here too.
};
// "paper" | "reference" | "guarded" | "settled"
RobustnessVariant parseRobustnessVariant(const std::string& text);
const char* toString(RobustnessVariant variant);

struct RobustnessParams {
  int samples = 100;
  RobustnessVariant variant = RobustnessVariant::kSettled;
  // Standard deviations of the pose error (>= 0); unset: the variant's defaults (paper and
  // guarded: 10 mm and 5 degrees, reference: 5 mm and 2.5 degrees), resolved in
  // evaluateRobustness.
  std::optional<double> position_sigma_m;
  std::optional<double> orientation_sigma_rad;
  std::uint64_t seed = 1;
  grasping::QualityParams quality;
  grasping::ClosingParams closing;
  grasping::SettlingParams settling;  // kSettled only
  // The load check: a sample that reaches force closure holds only when its contacts can also
  // carry the object's weight along +-x, +-y, +-z with every finger joint within this share of its
  // torque limit (grasping/load_capacity.h; capacity >= 1). Force closure alone assumes fingers of
  // unbounded strength. Unset: force closure alone (the paper's criterion).
  std::optional<grasping::LoadCapacityParams> load;
};

// The load check of the ranking's r: the contacts must carry the object's weight (the physics
// judge's 0.1 kg) in every direction with the fingers within their grip (kGripTorqueShare of their
// torque limits), as the physics judge's closed hand grips it (docs/ranking.md, "Load check").
inline grasping::LoadCapacityParams defaultLoadCheck() {
  grasping::LoadCapacityParams load;
  load.torque_share = grasping::kGripTorqueShare;
  return load;
}

// Sets `params.load` to the load check when `wanted` and the variant has one, else unsets it: the
// paper's criterion is force closure, so its variants (paper, reference) stay as published. The
// one rule plan, score, evaluate and Python follow.
inline void setLoadCheck(RobustnessParams& params, bool wanted) {
  const bool published = params.variant == RobustnessVariant::kPaper ||
                         params.variant == RobustnessVariant::kReference;
  if (wanted && !published)
    params.load = defaultLoadCheck();
  else
    params.load.reset();
}

// The pose error standard deviations `params` stands for: its own, or its variant's defaults.
double positionSigmaM(const RobustnessParams& params);
double orientationSigmaRad(const RobustnessParams& params);

struct RobustnessResult {
  int samples = 0;
  // Samples that held: closed to force closure (and, with the load check, carried the weight).
  int force_closure = 0;
  // Samples whose perturbed preshape pose hit the object: failures, except in kGuarded, which
  // backs them off and closes (guarded_holds of them then reached force closure).
  int collisions = 0;
  int guarded_holds = 0;
  // kSettled: samples that held only after the object settled (moved at least once); they are in
  // force_closure (and, when they started in collision, in guarded_holds too).
  int settled_holds = 0;
  // Why the other failed samples failed, for a user asking what to change: the closing from a
  // free start ended with fewer contacts than it needs, or it closed but not in force closure
  // (contacts that slip at this friction). With the samples that started in collision and did not
  // hold (collisions - guarded_holds) they add up to samples - force_closure, unless gave_up.
  int closing_failures = 0;
  int no_force_closure = 0;
  // With the load check: samples that reached force closure but whose contacts cannot carry the
  // object's weight in every direction (failures too, in the sum above).
  int too_weak = 0;
  // evaluateRobustness's max_failures was exceeded: the counts (and score, interval) cover only
  // the samples run, and all that is known is that r < 1 - max_failures / samples.
  bool gave_up = false;
  // Per sample, in sample order: whether it held (false also for a sample skipped after
  // max_failures). With samplePoseError this says where around the grasp the holds lie.
  std::vector<bool> held;
  double score = 0;  // r = force_closure / samples (held: force closure and, checked, the weight)
  double wilson_low = 0, wilson_high = 0;  // 95 % Wilson score interval of r
  double time_s = 0;
};

// One sample's pose error: a translation and a rotation (object-frame axes), applied about the
// centre of the grasp's contacts (evaluateRobustness).
struct PoseError {
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
};
// The error of sample `sample` of evaluateRobustness(..., params, grasp_index): a function of the
// seed, the variant, the sigmas, grasp_index and the sample index only.
PoseError samplePoseError(const RobustnessParams& params, std::uint64_t grasp_index, int sample);
// The point the errors act about: the mean of the grasp's contact points.
Eigen::Vector3d perturbationCentre(const grasping::Grasp& grasp);
// `pose` (of the hand, or of its grasp centre point) under `error` about `centre`:
// x -> c + R (x - c) + t moves the hand in the paper's variants; the reference moves the object
// by it, which is moving the hand by the inverse.
Pose perturbedPose(const Pose& pose, const PoseError& error, const Eigen::Vector3d& centre,
                   RobustnessVariant variant);

// Wilson score interval for k successes in n trials (z = 1.96).
std::pair<double, double> wilsonInterval(int successes, int trials, double z = 1.959964);

// The samples run in parallel (TBB, one simulator per thread built from `simulator`'s hand and
// object; a single sample, or every sample when only one thread may run, runs on `simulator`
// itself, so concurrent callers need a simulator each, as for any other use of a simulator); the
// result for a seed does not depend on the thread count.
// The perturbations are applied about the centre of the grasp's contacts (their mean point),
// rotation axes along the object frame. `grasp_index` decorrelates the paper variant's samples
// between grasps while keeping them a function of (seed, grasp_index). Throws InvalidArgument for
// samples < 1 or a grasp without contacts.
// max_failures: for a caller that only asks whether r reaches a bar (refinement's comparisons),
// the samples not yet started are skipped once more than this many have failed. Whether that
// happens (gave_up) does not depend on the thread count: it is exactly whether all samples
// together fail more often, since samples are skipped only after the bar is already missed.
RobustnessResult evaluateRobustness(grasping::GraspSimulator& simulator,
                                    const grasping::Grasp& grasp, const RobustnessParams& params,
                                    std::uint64_t grasp_index = 0,
                                    std::optional<int> max_failures = std::nullopt);

// Samples [begin, end) of evaluateRobustness(simulator, grasp, params, grasp_index): the same
// executions with the same outcomes, for a caller that runs a grasp's samples a few at a time
// (best-first screening, robust_ranking.h). `samples`, the counts, `held`, `score` and the
// interval cover these samples only. Throws
// InvalidArgument unless 0 <= begin < end <= params.samples, or for a grasp without contacts.
RobustnessResult evaluateRobustnessSamples(grasping::GraspSimulator& simulator,
                                           const grasping::Grasp& grasp,
                                           const RobustnessParams& params,
                                           std::uint64_t grasp_index, int begin, int end);

}  // namespace skelgrasp::ranking
