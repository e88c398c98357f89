#pragma once
// Closing what a single view cannot see, from the support plane: the object is taken to fill the
// space between the plane and its observed surface (a height map over the plane, "2.5-D").
// Lengths in metres.
#include "skelgrasp/common/point_cloud.h"
#include "skelgrasp/perception/scene.h"

namespace skelgrasp::perception {

struct SupportCompletionParams {
  // Height-map cell on the plane; 4 mm is a little coarser than the default 3 mm voxel grid so
  // that neighbouring cells of an observed surface are all occupied.
  double cell_m = 0.004;
  // Morphological closing of the footprint (cells): bridges gaps of up to twice this many cells
  // between observed columns.
  int closing_cells = 1;
};

struct SupportCompletion {
  // Generated surface samples with outward normals: the footprint on the plane (normals into the
  // plane) and vertical walls along its outline up to the observed height (normals away from it).
  PointCloud points;
  std::size_t bottom_points = 0;
  std::size_t wall_points = 0;
  std::size_t footprint_cells = 0;
};

// Throws InvalidArgument for a non-positive cell or a negative closing.
SupportCompletion completeOnSupport(const PointCloud& object, const SupportPlane& plane,
                                    const SupportCompletionParams& params = {});

}  // namespace skelgrasp::perception
