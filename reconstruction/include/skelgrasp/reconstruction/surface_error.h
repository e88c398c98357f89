#pragma once
// How far a reconstructed object's true surface may lie from its mesh: an error bound per vertex,
// from the sensor's noise where the vertex was observed and from the distance to the observed
// surface where it was filled in (docs/reconstruction.md, "Error bounds"). `run` keeps open hands
// that far from the mesh (HypothesisParams::clearance). Lengths in metres.
#include <cstdint>
#include <memory>
#include <vector>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/mesh.h"
#include "skelgrasp/geometry/point_index.h"

namespace skelgrasp::reconstruction {

struct SurfaceErrorParams {
  // Observed vertices: this many standard deviations of the sensor's axial noise at the vertex's
  // distance z from the sensor, sigma(z) = sigma_base_m + sigma_quadratic (z - sigma_z0_m)^2 (the
  // Primesense model's terms, perception::DepthNoiseParams): 2 x 1.5 mm = 3 mm at 0.8 m.
  double observed_sigmas = 2.0;
  double sigma_base_m = 0.0012;
  double sigma_quadratic = 0.0019;  // per m^2
  double sigma_z0_m = 0.4;
  // Filled-in vertices: the bound of the nearest observed vertex plus this share of the distance
  // to it (a completion guesses surface the farther from the data the worse), at most
  // max_bound_m.
  double filled_growth = 0.2;
  double max_bound_m = 0.01;
  // The clearance around a point (SurfaceClearance): the largest bound of the vertices no farther
  // than the nearest vertex plus this, the surface a hand placed there closes on.
  double neighbourhood_m = 0.02;
  // Throws InvalidArgument for a negative or non-finite value or a max_bound_m of 0.
  void validate() const;
};

struct SurfaceErrorResult {
  // kInvalidInput when the flags do not match the vertices; kNoResult when no vertex was
  // observed (every bound is then max_bound_m).
  Status status;
  std::vector<double> bound_m;                        // per vertex
  double observed_median_m = 0, filled_median_m = 0;  // 0 for a group without vertices
  std::size_t observed = 0, filled = 0;
};

// The bounds of `mesh` (the scan's frame, the sensor at `sensor_origin`) with its per-vertex
// observed flags. Throws InvalidArgument for bad parameters.
SurfaceErrorResult surfaceErrorBounds(const TriangleMesh& mesh,
                                      const std::vector<std::uint8_t>& observed,
                                      const Eigen::Vector3d& sensor_origin,
                                      const SurfaceErrorParams& params = {});

// The clearance a hand needs at a point: the largest bound among the vertices within
// params.neighbourhood_m beyond the nearest one. Thread-safe queries.
class SurfaceClearance {
 public:
  // `bounds` per vertex of `mesh`; throws InvalidArgument when the sizes differ.
  SurfaceClearance(const TriangleMesh& mesh, std::vector<double> bounds,
                   const SurfaceErrorParams& params = {});
  double at(const Eigen::Vector3d& point) const;

 private:
  std::shared_ptr<const geometry::PointIndex> index_;
  std::vector<double> bounds_;
  double neighbourhood_m_;
};

}  // namespace skelgrasp::reconstruction
