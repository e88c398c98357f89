#pragma once
// Grasps for objects whose skeleton says little: balls, discs, lids, short boxes. Their skeleton
// collapses to a few vertices whose grasping intervals are too short, so the skeleton strategies
// (paper Table II) yield few or no hand poses. These strategies place the hand about the object's
// centre and principal axes instead, and judge every pose with the skeleton planner's own
// hypothesis evaluation (back off until collision-free, close, contacts, force closure, epsilon,
// scene check), so their grasps are judged exactly as skeleton grasps (docs/planning.md,
// "Fallback strategies").
//
// Strategy names (Grasp::strategy; Grasp::segment and skeleton_vertex are -1):
//   "sphere"  approaches from Fibonacci directions on a sphere about the centre, pointing at it,
//             each with several hand rolls;
//   "rim"     disc-like objects only: approaches in the disc plane closing across the thickness
//             (a pinch on the rim), and approaches along the thin axis closing across the disc;
//   "axes"    approaches along +-each principal axis, the fingers spreading along the other axes;
//   "top"     scenes only (the hypothesis' scene check knows a support plane): approaches from
//             above, straight down and tilted towards the object from several sides, with rolls
//             aligned to the object's longest horizontal axis. Among touching neighbours only a
//             hand coming from above finds room (docs/planning.md, "The candidate pool beyond the
//             skeleton strategies").
// Every pose is tried with the precision and the power preshape where the hand does such grasps.
#include <cstdint>

#include "skelgrasp/geometry/principal_axes.h"
#include "skelgrasp/grasping/grasp.h"
#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/grasping/planning/hypothesis.h"
#include "skelgrasp/grasping/simulation/grasp_object.h"

namespace skelgrasp::grasping {

// Which strategies run and how densely they sample (a ball: 32 x 4 sphere poses + 24 axis poses,
// each with up to two preshapes).
struct FallbackStrategyParams {
  bool sphere = true;
  bool rim = true;
  bool axes = true;
  int sphere_directions = 32;  // Fibonacci directions on the sphere about the centre
  int sphere_rolls = 4;        // hand rolls about each sphere approach (evenly over a turn)
  int rim_directions = 16;     // approach directions in the disc plane (two rolls each)
  int rim_across_rolls = 4;    // rolls of each approach along the thin axis (between the axes')
  // "top" (only with a support plane): straight down with top_rolls rolls, plus approaches tilted
  // by top_tilt_rad from the plane's normal from top_tilted_azimuths sides, top_tilted_rolls each
  // (12 + 8 x 4 = 44 poses, and up to as many centred ones, below).
  bool top = true;
  int top_rolls = 12;
  int top_tilted_azimuths = 8;
  int top_tilted_rolls = 4;
  double top_tilt_rad = 0.5235987755982988;  // 30 degrees
  // Each top pose is also tried moved along its closing axis (the grasp centre point's x) to the
  // middle of the object's extent there: the extent of the mesh vertices within this distance of
  // the pose's centre across the other two axes (where it moves by more than a millimetre). The
  // centre of mass of a flat, irregular object is rarely midway between the faces the fingers
  // close on, and a parallel gripper opening 80 mm around a 66 mm flashlight head leaves 7 mm a
  // side. 0: only the poses at the centre of mass.
  double top_centring_band_m = 0.01;
  // The preshapes tried at every pose, where the hand does that grasp type (at least one).
  bool precision = true;
  bool power = true;
  // Also close the hand's alternative preshapes of each grasp type at every pose of that type
  // (HandModel::plannerPreshapes). false, or hypothesis.quality.reference_compat: "power" and
  // "precision" only, as the reference. The skeleton planner passes on its own flag.
  bool alternative_preshapes = true;
  // The object is a disc ("rim" applies) when the standard deviation of its surface along the
  // thinnest principal axis is below this fraction of that along the middle axis (a sphere: 1;
  // a disc 90 mm across and 15 mm thick: about 0.4).
  double disc_ratio = 0.6;
};

struct FallbackPlannerParams {
  double timeout_s = 0;        // 0: no limit
  std::size_t max_grasps = 0;  // 0: no limit
  // Order in which the poses of all strategies are tried (so an early stop samples every
  // strategy); results are deterministic for a seed.
  std::uint64_t seed = 1;
  FallbackStrategyParams strategies;
  // extra_retreat_m is the hand's power retreat for power grasps, 0 for precision grasps (as the
  // skeleton planner).
  HypothesisParams hypothesis;
};

// The object's principal axes, along which the "axes" and "rim" strategies place the hand.
using geometry::PrincipalAxes;
using geometry::surfacePrincipalAxes;

// The fallback strategies alone, about the object's centre of mass. Result as the other planners
// (planner "fallback"; rejections by reason, grasps sorted by epsilon).
PlanResult planFallbackGrasps(const HandModel& hand, const GraspObject& object,
                              const FallbackPlannerParams& params);

}  // namespace skelgrasp::grasping
