#pragma once
// Private to reconstruction/: PCL Poisson surface reconstruction behind skelgrasp types.
#include "skelgrasp/reconstruction/meshing.h"

namespace skelgrasp::reconstruction::detail {

// Poisson surface of oriented points (normals required). Returns an empty mesh when PCL produces
// no surface.
TriangleMesh poissonSurface(const PointCloud& oriented, const PoissonParams& params);

}  // namespace skelgrasp::reconstruction::detail
