#pragma once
// Comparing surfaces: area-uniform surface samples and the symmetric Chamfer distance.
#include <cstdint>
#include <vector>

#include "skelgrasp/common/mesh.h"

namespace skelgrasp::geometry {

// `count` points distributed uniformly by area over the faces (seeded, deterministic).
std::vector<Eigen::Vector3d> sampleSurface(const TriangleMesh& mesh, std::size_t count,
                                           std::uint64_t seed = 1);

struct ChamferDistance {
  double a_to_b_mean_m = 0;  // mean distance from samples of a to the surface of b
  double b_to_a_mean_m = 0;
  double symmetric_m = 0;  // (a_to_b_mean + b_to_a_mean) / 2
  double a_to_b_p95_m = 0;
  double b_to_a_p95_m = 0;
  double max_m = 0;  // largest sample distance either way (a sampled Hausdorff distance)
};

// Point-to-surface distances (exact, AABB tree) from `samples` area-uniform points of each mesh.
ChamferDistance chamferDistance(const TriangleMesh& a, const TriangleMesh& b,
                                std::size_t samples = 20000, std::uint64_t seed = 1);

}  // namespace skelgrasp::geometry
