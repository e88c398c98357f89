// Error bounds of a reconstructed surface (surface_error.h).
#include "skelgrasp/reconstruction/surface_error.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace skelgrasp::reconstruction {
namespace {

void check(bool ok, const char* what) {
  if (!ok) throw InvalidArgument(std::string("surface error: ") + what);
}

bool nonNegative(double value) {
  return value >= 0 && std::isfinite(value);
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

}  // namespace

void SurfaceErrorParams::validate() const {
  check(nonNegative(observed_sigmas) && nonNegative(sigma_base_m) && nonNegative(sigma_quadratic) &&
            nonNegative(sigma_z0_m),
        "the sensor's noise terms must be finite and >= 0");
  check(nonNegative(filled_growth), "the growth of filled-in bounds must be finite and >= 0");
  check(max_bound_m > 0 && std::isfinite(max_bound_m), "the largest bound must be positive");
  check(nonNegative(neighbourhood_m), "the neighbourhood must be finite and >= 0");
}

SurfaceErrorResult surfaceErrorBounds(const TriangleMesh& mesh,
                                      const std::vector<std::uint8_t>& observed,
                                      const Eigen::Vector3d& sensor_origin,
                                      const SurfaceErrorParams& params) {
  params.validate();
  SurfaceErrorResult out;
  const std::size_t n = mesh.vertices.size();
  if (observed.size() != n) {
    out.status = Status::Make(StatusCode::kInvalidInput,
                              "observed flags for " + std::to_string(observed.size()) +
                                  " vertices, the mesh has " + std::to_string(n));
    return out;
  }
  out.bound_m.assign(n, params.max_bound_m);
  std::vector<Eigen::Vector3d> seen;
  std::vector<double> seen_bound;
  for (std::size_t i = 0; i < n; ++i) {
    if (!observed[i]) continue;
    const double z = (mesh.vertices[i] - sensor_origin).norm();
    const double dz = z - params.sigma_z0_m;
    const double sigma = params.sigma_base_m + params.sigma_quadratic * dz * dz;
    out.bound_m[i] = std::min(params.max_bound_m, params.observed_sigmas * sigma);
    seen.push_back(mesh.vertices[i]);
    seen_bound.push_back(out.bound_m[i]);
  }
  out.observed = seen.size();
  out.filled = n - seen.size();
  if (seen.empty()) {
    out.status = Status::Make(StatusCode::kNoResult, "no vertex was observed");
    out.filled_median_m = n ? params.max_bound_m : 0;
    return out;
  }
  const geometry::PointIndex index(seen);
  std::vector<double> observed_bounds, filled_bounds;
  for (std::size_t i = 0; i < n; ++i) {
    if (observed[i]) {
      observed_bounds.push_back(out.bound_m[i]);
      continue;
    }
    const auto [nearest, distance] = index.nearest(mesh.vertices[i]);
    out.bound_m[i] = std::min(params.max_bound_m, seen_bound[static_cast<std::size_t>(nearest)] +
                                                      params.filled_growth * distance);
    filled_bounds.push_back(out.bound_m[i]);
  }
  out.observed_median_m = median(std::move(observed_bounds));
  out.filled_median_m = median(std::move(filled_bounds));
  return out;
}

SurfaceClearance::SurfaceClearance(const TriangleMesh& mesh, std::vector<double> bounds,
                                   const SurfaceErrorParams& params)
    : bounds_(std::move(bounds)), neighbourhood_m_(params.neighbourhood_m) {
  params.validate();
  check(bounds_.size() == mesh.vertices.size(), "one bound per vertex");
  index_ = std::make_shared<const geometry::PointIndex>(mesh.vertices);
}

double SurfaceClearance::at(const Eigen::Vector3d& point) const {
  const auto [nearest, distance] = index_->nearest(point);
  if (nearest < 0) return 0;
  double most = 0;
  for (const int i : index_->within(point, distance + neighbourhood_m_)) {
    most = std::max(most, bounds_[static_cast<std::size_t>(i)]);
  }
  return most;
}

}  // namespace skelgrasp::reconstruction
