#pragma once
// Regularisation: any triangle input (soup, open, non-manifold, multi-part, inverted) becomes a
// closed, single-part, outward-oriented 2-manifold, as mean-curvature-flow contraction requires.
#include <nlohmann/json.hpp>

#include <optional>
#include <string>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/mesh.h"
#include "skelgrasp/geometry/mesh_topology.h"

namespace skelgrasp::geometry {

enum class RegularisationMethod {
  kAlphaWrap,  // CGAL 3D alpha wrapping of the triangle soup (default; the skeleton stage: kAuto)
  kNone,       // use the input as is; it must already be a closed single-part 2-manifold
  // Use the input as is when it already is a closed, consistently oriented, self-intersection-free
  // 2-manifold of at least auto_min_vertices vertices (pinholes of at most auto_max_hole_edges
  // boundary edges in all are filled first; parts beyond the largest holding at most
  // join_area_fraction of the area are dropped as debris), else alpha wrap. For surfaces such as
  // Poisson's that usually need nothing, and for clean scans.
  kAuto,
};

RegularisationMethod parseRegularisationMethod(const std::string& text);  // alpha_wrap|none|auto
const char* toString(RegularisationMethod method);

struct RegularisationParams {
  RegularisationMethod method = RegularisationMethod::kAlphaWrap;
  // Alpha (radius of the carving ball) = bbox diagonal / alpha_divisor. Larger divisors keep more
  // detail but cost time and keep more spurious handles. Default chosen by measurement, see
  // docs/regularisation.md.
  double alpha_divisor = 50.0;
  // Offset of the wrap from the input surface = bbox diagonal / offset_divisor. Matters little for
  // the skeleton's topology but much for time (docs/regularisation.md).
  double offset_divisor = 500.0;
  // Isotropic remeshing after wrapping to this target edge length in metres; 0 = off.
  double remesh_target_edge_m = 0.0;
  int remesh_iterations = 3;
  // A closed result with more vertices than this is simplified by edge collapse (CGAL's
  // Lindstrom-Turk collapses with bounded normal change, which keep it closed and of the same
  // genus) down to about this many. The contraction's cost grows with the vertex count while its
  // skeleton depends on the shape, not the tessellation: a 0.9 mm Poisson mesh of a 10 cm object
  // (15k vertices) contracts in 1.5 s, the same shape at 4000 vertices in a fraction of it.
  // Unset: never.
  std::optional<std::size_t> max_vertices;
  // The wrap leaves several parts when input parts are farther apart than alpha. When the parts
  // other than the largest hold more than `join_area_fraction` of the area (a lid's knob, not
  // scan debris), the wrap is retried with alpha doubled, up to `join_attempts` times.
  double join_area_fraction = 0.02;
  int join_attempts = 2;
  // Parts still separate after that: the largest (by area) is kept when true, otherwise the result
  // is kInvalidInput.
  bool keep_largest_component = true;
  // kAuto: an input with at most this many boundary edges is closed by hole filling instead of
  // being wrapped.
  std::size_t auto_max_hole_edges = 64;
  // kAuto: an input with fewer vertices is wrapped even when it is a clean closed manifold. Mean-
  // curvature flow needs a fine, even tessellation: a dense scan has one (and is simplified to
  // max_vertices), a CAD model's few long triangles do not (a generated box's 98 vertices as they
  // are gave a skeleton without its principal axes). Unset: any size.
  std::optional<std::size_t> auto_min_vertices;
};

struct RegularisationReport {
  std::string method;  // as requested; kAuto reports "auto/as_is" or "auto/alpha_wrap"
  MeshTopology input;
  MeshTopology output;
  double bbox_diagonal_m = 0;
  double alpha_m = 0;
  double offset_m = 0;
  bool remeshed = false;
  std::size_t decimated_from = 0;    // vertices before edge collapse (0: not decimated)
  bool orientation_flipped = false;  // method none: inward input turned outward
  std::size_t filled_holes = 0;      // method auto: pinholes closed by hole filling
  std::size_t wrap_components = 0;   // parts the final wrap produced before selection
  int join_retries = 0;              // wraps repeated with a doubled alpha
  double dropped_area_fraction = 0;  // area of discarded parts / total wrap area
  double time_s = 0;
};

// The "regularisation" object of the skeleton and reconstruction reports.
nlohmann::json toJson(const RegularisationReport& report);

struct RegularisationResult {
  Status status;
  TriangleMesh mesh;  // closed, single-part, outward 2-manifold when status.ok()
  RegularisationReport report;
};

// Memory estimates (bytes) of regularising `input`, from its surface area A and bounding-box
// diagonal D. The wrap's facets are Delaunay facets no larger than about alpha = D / alpha_divisor,
// so it outputs about
//   triangles = kWrapTrianglesPerArea x A / alpha^2
// (the offset changes the time far more than the count, docs/regularisation.md),
// and isotropic remeshing to edge e about 2.8 A / e^2 (equilateral triangles of area 0.43 e^2 would
// give 2.3; CGAL's edges come out a little shorter than the target).
// bytes = kRegularisedBytesPerTriangle x triangles, fitted to /usr/bin/time -v peak RSS of
// `skelgrasp skeleton` on YCB meshes (docs/limits.md), so it also covers the skeleton's
// contraction of that mesh, the next allocation of every caller.
double estimateAlphaWrapTriangles(const TriangleMesh& input, const RegularisationParams& params);
double estimateRemeshTriangles(const TriangleMesh& input, const RegularisationParams& params);
double estimateRegularisedBytes(double triangles);

// Throws InvalidArgument for non-positive divisors and ResourceLimitExceeded (common/resources.h)
// when the estimated memory exceeds the limit; input problems go to the status.
RegularisationResult regularise(const TriangleMesh& input, const RegularisationParams& params = {});

}  // namespace skelgrasp::geometry
