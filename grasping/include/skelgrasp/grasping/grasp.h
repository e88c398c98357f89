#pragma once
// A planned grasp, the outcome of evaluating one hypothesis, and a planner's result.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/pose.h"
#include "skelgrasp/grasping/contact.h"

namespace skelgrasp::grasping {

enum class GraspType { kPrecision, kPower };
const char* toString(GraspType type);
// The type toString names ("power", "precision"); nullopt for any other text.
std::optional<GraspType> graspTypeNamed(const std::string& name);

// How refinement for robustness (ranking/robust_refinement.h) moved a scored grasp: the search
// for a more robust pose near it, with the pose it kept relative to the planner's.
struct GraspRobustRefinement {
  bool refined = false;    // the grasp is a moved pose (false: the planner's pose stayed best)
  int evaluations = 0;     // poses closed in the search besides the planner's
  int search_samples = 0;  // perturbed executions per pose in the search
  double r_before = 0;     // r of the planner's pose (same samples as GraspRobustness::r)
  // The moves, in the planner's grasp centre point frame (z = approach): shift across the
  // approach, extra standoff (added to the retreat; negative: closer), roll about the approach.
  double shift_x_m = 0, shift_y_m = 0, standoff_m = 0, roll_rad = 0;
  // Mean-shift steps taken after those moves (RobustRefinementParams::mean_shift_steps): how many,
  // how far they carried the contacts' centre (m) and the angle they turned the hand (rad).
  int mean_shift_steps = 0;
  double mean_shift_m = 0, mean_shift_rad = 0;
  std::string preshape_before;  // the planner's preshape (differs from the grasp's when switched)
  // The check of the pose the search found against the planner's, on samples of its own (not r's,
  // so that the r reported is not the one a pose was chosen for): samples (0: no check ran, the
  // search found nothing better), holds of the planner's pose, and of the found pose (none: its
  // check stopped once it had failed more often). refined == (holds_after >= holds_before).
  int check_samples = 0;
  int check_holds_before = 0;
  std::optional<int> check_holds_after;
};

// Robustness r of a grasp (ranking::evaluateRobustness): the share of `samples` perturbed
// executions (pose error with standard deviations sigma_m and sigma_rad) that still close to force
// closure at friction mu, with its 95 % Wilson interval. A plain record so the grasp stage can
// carry it without depending on evaluation.
struct GraspRobustness {
  double r = 0;
  double ci95_low = 0, ci95_high = 1;
  int samples = 0;
  double mu = 0;                    // friction coefficient of the force-closure test
  double torsional_friction_m = 0;  // its soft-finger torsion length (0: point contacts)
  std::string contact_patch;        // "corners" or "centre" (ContactPatch); empty: not recorded
  double sigma_m = 0;               // position error, standard deviation (m)
  double sigma_rad = 0;             // orientation error, standard deviation (rad)
  // "paper", "guarded" or "settled" (the hand moves), "reference" (the object moves)
  std::string variant;
  // Why the failed samples failed (they add up to samples - r * samples): the open hand started in
  // the object, the closing ended with too few contacts, or it closed without force closure.
  int start_collisions = 0, closing_failures = 0, no_force_closure = 0;
  // With the load check: force closure reached, but the contacts cannot carry the weight.
  int too_weak = 0;
  // The load check r counted (0: none, force closure alone): the object's mass and the share of
  // each joint's torque limit the contacts may draw on.
  double load_mass_kg = 0;
  double load_torque_share = 0;
  // Variant "settled": the holding samples that held only after the object moved in the hand.
  int settled_holds = 0;
  std::optional<GraspRobustRefinement> refinement;  // set when the search ran on this grasp
};

// How local refinement (refinement.h) changed a grasp: the moves of the pose it kept, relative to
// the hypothesis it started from, and the closure margin before and after.
struct GraspRefinement {
  bool refined = false;  // the kept pose differs from the seed (false: the seed was the best)
  int evaluations = 0;   // poses closed and judged besides the seed
  // Signed normalised LP margin n l* (solveClosureLp, quality.h): > 0 force closure, <= 0 not.
  double margin_before = 0, margin_after = 0;
  double tangent_m = 0;   // shift along the skeleton tangent
  double lateral_m = 0;   // shift across the approach, towards the local surface centroid
  double roll_rad = 0;    // roll about the approach axis
  double standoff_m = 0;  // extra retreat along the approach (negative: closer)
};

struct Grasp {
  int id = -1;
  GraspType type = GraspType::kPower;
  // "1a" "1b" "2a" "2b" "3" "4", "surface", fallback: "sphere" "rim" "axes" "top"
  std::string strategy;
  int segment = -1;  // skeleton segment (-1: none)
  int skeleton_vertex = -1;
  std::string preshape;
  Pose gcp_pose = Pose::Identity();   // grasp centre point in the object frame, after retreat
  Pose hand_pose = Pose::Identity();  // hand root in the object frame
  double retreat_m = 0;               // distance backed off from the hypothesis' GCP
  Eigen::VectorXd joints;             // closed configuration (all joints of the hand)
  std::vector<Contact> contacts;
  bool force_closure = false;
  double epsilon = 0;
  std::optional<double> volume;  // grasp wrench space volume, when computed (--wrench-volume)
  // Set for the grasps the robust ranking scored (ranking/robust_ranking.h), else unset.
  std::optional<GraspRobustness> robustness;
  std::optional<GraspRefinement> refinement;  // set when local refinement ran on this grasp
};

// Why a hypothesis did not become a grasp. Strategy-level codes (interval, thickness, ...) reject a
// (vertex, grasp type) pair before any pose is generated; pose-level codes reject one pose.
namespace reason {
inline constexpr const char* kBranchVertex = "branch_vertex";
inline constexpr const char* kGraspTypeDisabled = "grasp_type_disabled";
inline constexpr const char* kIntervalTooShort = "interval_too_short";
inline constexpr const char* kTooFewSurfacePoints = "too_few_surface_points";
inline constexpr const char* kThicknessOutOfRange = "thickness_out_of_range";  // lambda2
inline constexpr const char* kLengthOutOfRange = "length_out_of_range";        // lambda1
inline constexpr const char* kRetreatExhausted = "retreat_exhausted";
inline constexpr const char* kStartCollision = "start_collision";
inline constexpr const char* kTooFewContacts = "too_few_contacts";
inline constexpr const char* kNotForceClosure = "not_force_closure";
inline constexpr const char* kEpsilonBelowMinimum = "epsilon_below_minimum";
// Object-level: why the fallback strategies ran (fallback_planner.h), counted once per plan.
inline constexpr const char* kFallbackNoSegment = "fallback_no_segment";
inline constexpr const char* kFallbackFewGrasps = "fallback_few_grasps";
}  // namespace reason

struct PlanSummary {
  std::size_t hypotheses = 0;     // every (vertex, type) evaluation rejected + every pose tried
  std::size_t poses = 0;          // hand poses tried (hypotheses that got past the strategy test)
  std::size_t generated = 0;      // poses placed collision-free and closed (FC-rate denominator)
  std::size_t force_closure = 0;  // generated grasps with force closure
  double planning_s = 0;
  std::map<std::string, std::size_t> rejections;
  std::map<std::string, std::size_t> scene_collision_links;  // first colliding link per rejection
  // What that link hit, per rejection: "support_plane" or "octree" (SceneCheckResult::obstacle),
  // and the octree's rejections by the obstacle label of the cell hit (SceneOccupancy; 0: none).
  std::map<std::string, std::size_t> scene_collision_obstacles;
  std::map<std::uint32_t, std::size_t> scene_collision_labels;
  std::size_t precision = 0, power = 0;  // kept grasps by type
  bool timed_out = false;
  bool max_grasps_reached = false;

  // Adds another plan's counts (a fallback's, a scene object's): counts, rejections and time
  // summed, flags or-ed.
  void add(const PlanSummary& other);

  double forceClosureRate() const { return generated ? double(force_closure) / generated : 0.0; }
  double msPerValidGrasp() const {
    return force_closure ? 1000.0 * planning_s / force_closure : 0.0;
  }
};

struct PlanResult {
  Status status;  // kNoResult when no grasp was found (see summary.rejections for why)
  std::string planner;
  std::vector<Grasp> grasps;  // sorted by epsilon, best first
  PlanSummary summary;
};

}  // namespace skelgrasp::grasping
