#pragma once
// Grasp-wrench-space quality: force closure, the Ferrari-Canny epsilon (L1) and the hull volume,
// from point contacts with Coulomb friction. Force closure is decided by a linear program (GLPK)
// or by the convex hull (Qhull); epsilon and the volume always come from the hull.
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/common/error.h"
#include "skelgrasp/grasping/contact.h"
#include "skelgrasp/grasping/simulation/grasp_object.h"

namespace skelgrasp::grasping {

class HandModel;

using Wrench = Eigen::Matrix<double, 6, 1>;

// How force closure is decided (docs/hands.md, "Quality").
enum class ForceClosureTest {
  kHull,  // 6D convex hull of the wrenches: closure when every facet is > 1e-12 from the origin
  kLp,    // rank 6 and the min-weight LP's margin above kClosureMarginTolerance; no hull needed
};
const char* toString(ForceClosureTest test);
// "hull" or "lp"; throws InvalidArgument otherwise.
ForceClosureTest parseForceClosureTest(const std::string& text);

struct QualityParams {
  double friction = 0.35;  // Coulomb coefficient mu; cone half-angle atan(mu)
  int cone_edges = 8;
  // Soft-finger contacts: torsion about the normal up to this length times the normal force
  // (2/3 mu a for a circular patch of radius a); 0 = point contacts. Two point contacts can never
  // hold a torque about the line through them, so a parallel gripper needs this to reach closure.
  // nullopt: the hand's contact model (ClosingDefaults::torsional_friction_m) wherever a hand is
  // known (withHandContactModel below); the hand-free functions below, which cannot know it, take
  // nullopt as point contacts.
  std::optional<double> torsional_friction_m;
  // true: also the hull volume, which needs the whole 6D hull of the wrenches. false (default):
  // epsilon comes from the hulls of a growing subset of them, 2-3x faster (docs/hands.md).
  bool compute_volume = false;
  // kLp decides closure without a hull; reference_compat always uses the hull and its own rule.
  ForceClosureTest fc_test = ForceClosureTest::kLp;
  // false (with kLp): only the verdict and the margin, no Qhull at all (epsilon and volume stay
  // 0), e.g. for robustness samples. true: with kLp the hull is built only for closure grasps.
  // kHull always computes epsilon.
  bool compute_epsilon = true;
  // Reproduce the reference implementation (fact sheet §9): every cone edge 45 degrees off the
  // normal whatever mu, epsilon measured from the hull centre (mean of hull vertices), force
  // closure when every facet is within 1e-4 of containing the origin.
  bool reference_compat = false;
};

// `params` judged as `hand`'s contacts: an unset torsional_friction_m becomes the hand's contact
// model (ClosingDefaults); a value the caller set (0 = point contacts) stays. Every planner,
// ranker and scorer that knows the hand applies this one rule.
QualityParams withHandContactModel(QualityParams params, const HandModel& hand);

struct WrenchSpaceResult {
  bool force_closure = false;
  // Distance from the origin (reference_compat: the hull centre) to the nearest hull facet;
  // 0 without force closure.
  double epsilon = 0;
  // The min-weight LP's optimum l* (see solveClosureLp) when it decided force closure (kLp):
  // > kClosureMarginTolerance with force closure, 0 without. NaN when the LP did not run (kHull,
  // reference_compat).
  double closure_margin = std::numeric_limits<double>::quiet_NaN();
  // 6D volume of the hull when compute_volume (0 when no 6D hull was built); nullopt otherwise.
  std::optional<double> volume;
  int hull_facets = 0;  // of the last hull built (by expansion: the last subset's)
  int wrenches = 0;
  int rank = 0;      // dimension spanned by the wrenches (6 needed for force closure)
  std::string note;  // why the hull is degenerate, if it is
};

// The unit force vectors of one friction cone: edges at half-angle atan(mu) around -normal (the
// finger pushes into the object). The first edge leans towards `reference` projected on the tangent
// plane (contactWrenches passes p - center), so the discretised cone moves rigidly with the grasp
// and epsilon does not depend on how the grasp is oriented.
std::vector<Eigen::Vector3d> frictionConeEdges(
    const Eigen::Vector3d& outward_normal, const QualityParams& params,
    const Eigen::Vector3d& reference = Eigen::Vector3d::Zero());

// Wrenches (f, k (p - center) x f) of every cone edge of every contact; with torsional friction g
// each edge becomes two wrenches with an extra torque +-k g (f . n_in) n_in about the normal.
std::vector<Wrench> contactWrenches(const std::vector<Contact>& contacts,
                                    const Eigen::Vector3d& center, double torque_scale,
                                    const QualityParams& params);

// Min-weight force-closure LP over wrenches w_1..w_n: maximise l subject to
//   sum_i alpha_i w_i = 0,  sum_i alpha_i = 1,  alpha_i >= l  (l free).
// It is feasible iff the origin lies in the convex hull of the wrenches, and then
// 0 <= l* <= 1/n; l* > 0 iff some strictly positive weighting balances the wrenches, i.e. (with
// rank 6) iff the origin is interior: force closure. l* is the weight every wrench can carry at
// least: dimensionless, invariant to any invertible linear map of wrench space (torque scale,
// choice of centre) and to the order of the wrenches, but it depends on their number and relative
// magnitudes (unit cone edges here); n l* in [0, 1] compares sets of different sizes.
struct ClosureLpResult {
  bool feasible = false;  // origin in the hull of the wrenches
  double margin = 0;      // l* (0 when infeasible)
  int iterations = 0;     // simplex iterations
  std::string error;      // non-empty when GLPK failed (feasible and margin then mean nothing)
};
// Thread-safe (GLPK objects per call, GLPK's environment is thread-local). Throws InvalidArgument
// for an empty or non-finite wrench set.
ClosureLpResult solveClosureLp(const std::vector<Wrench>& wrenches);

// The squeeze a closing hand applies, balanced or not (settling.h): each pushing group (a finger)
// presses with a normal force of at least 1 in total over its contacts, passive contacts (the
// palm) push back with any force >= 0, every force inside its friction cone. Minimises the L1 norm
// of the unbalanced wrench
//   residual = sum_i lambda_i w_i,  lambda_i >= 0,  sum_{i in g} normal_i lambda_i >= 1 per group
//   g, residual . p_j >= 0 for every j
// over the cone-edge wrenches w_i (contactWrenches), where group[i] is wrench i's pushing group
// (-1: passive) and normal[i] its normal force per unit weight (cos of the cone's half-angle).
// p_j is the wrench of a unit inward normal force at contact j: moving the object along the
// residual (read as a twist in the same scaled units) then drives it into no contact, to first
// order. Without those rows an L1-minimal residual may point into a contact (adding a normal force
// there can leave its L1 norm unchanged); the L2-minimal residual satisfies them (its optimality
// conditions), so the LP stays feasible.
// residual = 0 (balanced) when the contacts can hold the squeeze still; otherwise the object is
// pushed along it. Thread-safe like solveClosureLp.
struct SqueezeLpResult {
  bool balanced = false;
  Wrench residual = Wrench::Zero();  // the unbalanced wrench, in the wrenches' scaled units
  std::string error;                 // non-empty when GLPK failed
};
// Throws InvalidArgument for sizes that differ, no wrench or non-finite input.
SqueezeLpResult solveSqueezeLp(const std::vector<Wrench>& wrenches, const std::vector<int>& group,
                               const std::vector<double>& normal,
                               const std::vector<Wrench>& pressing = {});
// The residual's L1 norm at or below this (relative to a squeeze of 1 per group) is balance.
constexpr double kSqueezeBalanceTolerance = 1e-7;

// The largest multiple `scale` of `load` (a wrench on the object) that non-negative weights x of
// `columns` (contact force edges as wrenches on the object, in physical units: N and N m) can
// balance, sum_c x_c columns_c + scale load = 0, while every row r of `limits` keeps
// lower[r] <= limits.row(r) x <= upper[r] (joint torques within their limits, and the torques a
// gripping joint keeps pressing with) and 0 <= scale <= max_scale. `feasible` is false when no
// weights balance even a scale of 0 (scale is then 0); error is non-empty when GLPK failed (scale
// then means nothing).
struct LoadLpResult {
  double scale = 0;
  bool feasible = true;
  std::string error;
};
LoadLpResult solveLoadLp(const std::vector<Wrench>& columns, const Wrench& load,
                         const Eigen::MatrixXd& limits, const Eigen::VectorXd& lower,
                         const Eigen::VectorXd& upper, double max_scale);

// Force closure by LP needs n l* > this (n wrenches; l* relative to its largest value 1/n). The
// band (0, tolerance] is where the origin is on the hull's boundary up to rounding (GLPK's
// simplex, Qhull's joggle); measurements: docs/hands.md.
constexpr double kClosureMarginTolerance = 1e-9;

// Wrenches contactWrenches makes: contacts x cone edges, twice that with torsional friction.
std::size_t wrenchCount(std::size_t contacts, const QualityParams& params);
// Memory estimate (bytes) of the 6D convex hull of `wrenches` wrenches. Qhull's facet count grows
// much faster than the input (up to W^3 in 6D by the upper bound theorem); measured on random
// contact sets it follows facets = kHullFacetsScale x W^kHullFacetsExponent, and
// bytes = kHullBytesPerFacet x facets (/usr/bin/time -v peak RSS of
// `skelgrasp quality`, docs/limits.md).
double estimateWrenchHullBytes(std::size_t wrenches);

// Throws InvalidArgument for mu < 0, < 3 cone edges or a non-positive torque scale, and
// ResourceLimitExceeded (common/resources.h) when estimateWrenchHullBytes exceeds the limit.
WrenchSpaceResult evaluateWrenchSpace(const std::vector<Contact>& contacts,
                                      const Eigen::Vector3d& center, double torque_scale,
                                      const QualityParams& params = {});

// Torque scale 1 / (maximum distance of the object's vertices from its centre of mass), the
// default: it makes unit torques comparable to unit forces and, unlike a bounding-box side, does
// not change when the object is rotated.
double torqueScaleMaxRadius(const GraspObject& object);
// Torque scale 2 / (longest side of the axis-aligned bounding box), as the reference code.
double torqueScaleLongestSide(const AxisAlignedBox& box);

// Quality of a grasp on an object with the object's centre and torque scale: centre of mass and
// max radius, or (reference_compat) vertex mean and 2 / longest bbox side. The hand's contact
// model (torsional friction) is taken from `params`.
WrenchSpaceResult evaluateGrasp(const std::vector<Contact>& contacts, const GraspObject& object,
                                const QualityParams& params = {});

}  // namespace skelgrasp::grasping
