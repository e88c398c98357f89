#pragma once
// Writes a small synthetic capture in the YCB raw layout (see ycb_raw.h), rendered by the
// simulated depth camera: a known object on a turntable disc seen by a few NP units. It exists to
// test the loader without the 0.3-0.7 GB official archives.
#include <cstdint>
#include <string>
#include <vector>

#include "skelgrasp/common/mesh.h"

namespace skelgrasp::datasets {

struct YcbRawFixtureSpec {
  // Object in the turntable frame (z up, resting on z = 0). Empty: a 7 cm x 10 cm cylinder.
  TriangleMesh object;
  std::vector<int> cameras = {1, 3, 5};
  std::vector<int> angles = {0, 90, 180, 270};
  // Rig geometry: unit k sits at distance_m from the turntable centre, at elevation
  // elevation_deg[k-1] above the turntable plane. The IR camera is ir_offset_m to the left of the
  // unit's RGB camera (as in the Carmine).
  double distance_m = 0.65;
  std::vector<double> elevation_deg = {5, 25, 45, 65, 85};
  double ir_offset_m = 0.025;
  // Per-unit depth scales (NP{k}_ir_depth_scale); the loader must apply them.
  std::vector<double> depth_scale = {1.0, 1.01, 0.99, 1.02, 0.98};
  bool noise = false;  // Primesense-like errors from the simulated camera (seeded)
  std::uint64_t seed = 7;
};

// Writes calibration.h5, NP{k}_{angle}.h5, NP{k}_{angle}.jpg, masks/NP{k}_{angle}_mask.pbm,
// poses/NP5_{angle}_pose.h5 and poses/turntable.h5 into `folder`. Returns the object mesh used.
TriangleMesh writeYcbRawFixture(const std::string& folder, const YcbRawFixtureSpec& spec = {});

}  // namespace skelgrasp::datasets
