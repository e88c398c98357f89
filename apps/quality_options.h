#pragma once
// --fc-test, shared by the commands that judge force closure (close, quality, plan, run,
// evaluate, bench plan).
#include <CLI/CLI.hpp>

#include <string>

#include "skelgrasp/grasping/quality.h"

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

}  // namespace skelgrasp::cli
