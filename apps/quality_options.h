#pragma once
// --fc-test, --closing and --contact-patch, shared by the commands that judge grasps (close,
// quality, plan, run, evaluate, bench plan; --closing and --contact-patch not on quality, which
// closes nothing), --torsional-friction (those that judge a hand's contacts: all of them but
// quality, which has no hand) and --wrench-volume (the commands that plan).
#include <CLI/CLI.hpp>

#include <optional>
#include <string>

#include "option_checks.h"
#include "skelgrasp/grasping/quality/quality.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"

namespace skelgrasp::cli {

// The library's default, never a typed copy.
inline std::string defaultForceClosureTest() {
  return grasping::toString(grasping::QualityParams{}.fc_test);
}

// `value` keeps "hull" or "lp" (grasping::parseForceClosureTest turns it into the enum).
inline CLI::Option* addForceClosureTestOption(CLI::App& cmd, std::string& value) {
  return cmd
      .add_option("--fc-test", value,
                  "Force-closure test: lp (linear program) or hull (6D convex hull, the old path)")
      ->check(CLI::IsMember({"hull", "lp"}))
      ->capture_default_str();
}

inline std::string defaultClosingMethod() {
  return grasping::toString(grasping::ClosingParams{}.method);
}

// `value` keeps "stepwise" or "fast" (grasping::parseClosingMethod turns it into the enum).
inline CLI::Option* addClosingMethodOption(CLI::App& cmd, std::string& value) {
  return cmd
      .add_option("--closing", value,
                  "Finger closing: fast (jumps over provably free steps) or stepwise (0.02 rad "
                  "steps, the old path)")
      ->check(CLI::IsMember({"stepwise", "fast"}))
      ->capture_default_str();
}

inline std::string defaultContactPatch() {
  return grasping::toString(grasping::ClosingParams{}.contact_patch);
}

// `value` keeps "corners" or "centre" (grasping::contactPatchFor turns it into the enum).
inline CLI::Option* addContactPatchOption(CLI::App& cmd, std::string& value) {
  return cmd
      .add_option("--contact-patch", value,
                  "Where a link touching the object over an area pushes: corners (the patch's "
                  "corners, up to four contacts per link) or centre (one contact at its centre, "
                  "the reference's model; implied by --reference-compat)")
      ->check(CLI::IsMember({"centre", "corners"}))
      ->capture_default_str();
}

// The grasp wrench space volume needs the whole 6D hull; epsilon alone does not (docs/hands.md).
inline CLI::Option* addWrenchVolumeFlag(CLI::App& cmd, bool& value) {
  return cmd.add_flag("--wrench-volume", value,
                      "Also compute each grasp's wrench space volume (the whole 6D hull: planning "
                      "takes up to twice as long; without it grasps.json has \"volume\": null)");
}

// Soft-finger contacts (docs/hands.md): unset means the hand's own contact model (point contacts
// for the built-in hands), so no default is shown.
inline CLI::Option* addTorsionalFrictionOption(CLI::App& cmd, std::optional<double>& value) {
  return cmd
      .add_option("--torsional-friction", value,
                  "Soft-finger contacts: torsional friction length in metres, about 2/3 mu times "
                  "the pad's contact radius (default: the hand's; 0, point contacts, for the "
                  "built-in hands)")
      ->check(lengthOrZero());
}

}  // namespace skelgrasp::cli
