// CGAL translation unit: alpha wrapping, component selection, isotropic remeshing and
// decimation.
#include "skelgrasp/geometry/regularisation.h"

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Bounded_normal_change_placement.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Edge_length_cost.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Midpoint_placement.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#include <CGAL/alpha_wrap_3.h>

#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/resources.h"
#include "skelgrasp/geometry/mesh_validity.h"
#include "skelgrasp/internal/cgal_conversions.h"

namespace skelgrasp::geometry {
namespace PMP = CGAL::Polygon_mesh_processing;
using internal::CgalMesh;

RegularisationMethod parseRegularisationMethod(const std::string& text) {
  if (text == "alpha_wrap") return RegularisationMethod::kAlphaWrap;
  if (text == "none") return RegularisationMethod::kNone;
  if (text == "auto") return RegularisationMethod::kAuto;
  throw InvalidArgument("unknown regularisation method '" + text +
                        "' (use alpha_wrap, none or auto)");
}

const char* toString(RegularisationMethod method) {
  switch (method) {
    case RegularisationMethod::kAlphaWrap:
      return "alpha_wrap";
    case RegularisationMethod::kNone:
      return "none";
    case RegularisationMethod::kAuto:
      return "auto";
  }
  return "?";
}

namespace {

// Keeps the largest part by area; returns (parts, dropped area fraction).
std::pair<std::size_t, double> keepLargestComponent(CgalMesh& mesh) {
  auto fcc = mesh.add_property_map<CgalMesh::Face_index, std::size_t>("f:cc", 0).first;
  const std::size_t parts = PMP::connected_components(mesh, fcc);
  if (parts <= 1) {
    mesh.remove_property_map(fcc);
    return {parts, 0.0};
  }
  std::vector<double> area(parts, 0.0);
  double total = 0;
  for (auto f : mesh.faces()) {
    const double a = PMP::face_area(f, mesh);
    area[fcc[f]] += a;
    total += a;
  }
  const std::size_t keep =
      static_cast<std::size_t>(std::max_element(area.begin(), area.end()) - area.begin());
  PMP::keep_connected_components(mesh, std::vector<std::size_t>{keep}, fcc);
  mesh.remove_property_map(fcc);
  mesh.collect_garbage();
  return {parts, total > 0 ? 1.0 - area[keep] / total : 0.0};
}

// kAuto: a closed, consistently oriented, self-intersection-free 2-manifold, fine enough
// (auto_min_vertices), whose parts other than the largest are debris (at most join_area_fraction
// of the area) needs no wrap.
bool acceptAsIs(const TriangleMesh& input, const RegularisationParams& params,
                RegularisationReport& report, CgalMesh& mesh) {
  const auto& t = report.input;
  if (params.auto_min_vertices && t.vertices < *params.auto_min_vertices) return false;
  if (t.non_manifold_edges > 0 || t.inconsistently_oriented_edges > 0) return false;
  if (t.boundary_edges > params.auto_max_hole_edges) return false;
  if (!internal::toCgalMesh(input, mesh)) return false;
  std::size_t filled = 0;
  if (t.boundary_edges > 0) {
    // Marching cubes leaves a few pinholes now and then (PCL's Poisson reports "vertex pair not
    // in list"); closing them costs microseconds, a wrap a second.
    std::vector<CgalMesh::Halfedge_index> holes;
    PMP::extract_boundary_cycles(mesh, std::back_inserter(holes));
    for (auto h : holes) {
      std::vector<CgalMesh::Face_index> patch;
      PMP::triangulate_hole(mesh, h, std::back_inserter(patch));
    }
    if (!CGAL::is_closed(mesh)) return false;
    filled = holes.size();
  }
  if (PMP::does_self_intersect(mesh)) return false;
  if (t.components > 1) {
    const auto [parts, dropped] = keepLargestComponent(mesh);
    if (dropped > params.join_area_fraction) return false;
    report.wrap_components = parts;
    report.dropped_area_fraction = dropped;
  }
  report.filled_holes = filled;
  return true;
}

// Edge collapse down to about `max_vertices` vertices: the shortest edge first, collapsed to its
// midpoint. A closed triangle mesh of genus g has 3 (V - 2 + 2g) edges, so the edge count is the
// stop criterion. The collapses keep the link condition (closed, same genus); bounding the change
// of the normals keeps faces from folding over. Lindstrom-Turk's volume-preserving placement kept
// the volume better but cost twice the time on scan meshes (0.24 s against 0.10 s for 15k
// vertices), and the contraction only needs the shape's proportions.
void decimate(CgalMesh& mesh, std::size_t max_vertices) {
  namespace SMS = CGAL::Surface_mesh_simplification;
  constexpr std::size_t kEdgesPerVertex = 3;
  SMS::Count_stop_predicate<CgalMesh> stop(kEdgesPerVertex * max_vertices);
  SMS::Edge_length_cost<CgalMesh> cost;
  SMS::Bounded_normal_change_placement<SMS::Midpoint_placement<CgalMesh>> placement;
  SMS::edge_collapse(mesh, stop, CGAL::parameters::get_cost(cost).get_placement(placement));
  mesh.collect_garbage();
}

// Calibration of the estimates (docs/limits.md, "The estimates"): `skeleton` on YCB
// 006_mustard_bottle (0.0455 m^2, 0.225 m diagonal) at alpha divisors 50, 100 and 200 output 4052,
// 12772 and 48282 triangles (1.8, 1.4, 1.3 x A / alpha^2) and its peak RSS grew by about 2.4-3.2
// KiB per output triangle (wrap, remesh and contraction together).
constexpr double kWrapTrianglesPerArea = 2.0;
// Isotropic remeshing: an equilateral triangle of edge e has area sqrt(3)/4 e^2 (2.3 A / e^2), but
// CGAL's edges come out shorter than the target: the mustard bottle at e = 2 mm gave 31360
// triangles, 2.76 A / e^2 (peak RSS +74 MiB, 2.4 KiB per triangle).
constexpr double kRemeshTrianglesPerArea = 2.8;
constexpr double kRegularisedBytesPerTriangle = 4096;

double surfaceArea(const TriangleMesh& mesh) {
  double area = 0;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) area += mesh.faceArea(f);
  return area;
}

std::string describeSize(const TriangleMesh& input) {
  return fmt::format("{:.3g} m^2 surface, {:.3g} m bounding-box diagonal", surfaceArea(input),
                     input.bounds().diagonal());
}

}  // namespace

double estimateAlphaWrapTriangles(const TriangleMesh& input, const RegularisationParams& params) {
  const double diagonal = input.bounds().diagonal();
  const double alpha = diagonal / params.alpha_divisor;
  return kWrapTrianglesPerArea * surfaceArea(input) / (alpha * alpha);
}

double estimateRemeshTriangles(const TriangleMesh& input, const RegularisationParams& params) {
  const double edge = params.remesh_target_edge_m;
  if (!(edge > 0)) return 0;
  return kRemeshTrianglesPerArea * surfaceArea(input) / (edge * edge);
}

double estimateRegularisedBytes(double triangles) {
  return kRegularisedBytesPerTriangle * triangles;
}

RegularisationResult regularise(const TriangleMesh& input, const RegularisationParams& params) {
  if (params.method != RegularisationMethod::kNone &&
      (!(params.alpha_divisor > 0) || !(params.offset_divisor > 0))) {
    throw InvalidArgument("regularise: alpha_divisor and offset_divisor must be positive");
  }
  if (params.remesh_target_edge_m < 0 || params.remesh_iterations < 0) {
    throw InvalidArgument("regularise: remeshing parameters must be non-negative");
  }
  // Fewer than a tetrahedron's vertices cannot stay closed.
  constexpr std::size_t kMinClosedVertices = 4;
  if (params.max_vertices && *params.max_vertices < kMinClosedVertices) {
    throw InvalidArgument("regularise: max_vertices must be at least 4");
  }
  // Degenerate input is the caller's data, not a failure: refused in the status, before the
  // memory estimates (which divide by its extent) and before CGAL.
  if (const std::string problem = degenerateMeshProblem(input); !problem.empty()) {
    RegularisationResult refused;
    refused.report.method = toString(params.method);
    refused.report.input = analyzeTopology(input);
    refused.status = Status::Make(StatusCode::kInvalidInput, problem);
    return refused;
  }
  if (!input.empty() && params.remesh_target_edge_m > 0) {
    checkMemoryEstimate(fmt::format("remeshing to {:g} m edges ({})", params.remesh_target_edge_m,
                                    describeSize(input)),
                        estimateRegularisedBytes(estimateRemeshTriangles(input, params)),
                        "--remesh");
  }
  Stopwatch watch;
  RegularisationResult result;
  auto& report = result.report;
  report.method = toString(params.method);
  report.input = analyzeTopology(input);
  report.bbox_diagonal_m = input.bounds().diagonal();
  if (input.empty()) {
    result.status = Status::Make(StatusCode::kInvalidInput, "input mesh is empty");
    return result;
  }

  CgalMesh mesh;
  bool as_is = false;
  if (params.method == RegularisationMethod::kAuto) {
    as_is = acceptAsIs(input, params, report, mesh);
    report.method = as_is ? "auto/as_is" : "auto/alpha_wrap";
    if (as_is && PMP::volume(mesh) < 0) {
      PMP::reverse_face_orientations(mesh);
      report.orientation_flipped = true;
    }
  }
  if (as_is) {
    // accepted above
  } else if (params.method == RegularisationMethod::kNone) {
    const auto& t = report.input;
    std::string problem;
    if (!t.closed) {
      problem = std::to_string(t.boundary_edges) + " boundary and " +
                std::to_string(t.non_manifold_edges) + " non-manifold edges";
    } else if (t.inconsistently_oriented_edges > 0) {
      problem = "inconsistent face orientation";
    } else if (t.components != 1) {
      problem = std::to_string(t.components) + " parts";
    } else if (!internal::toCgalMesh(input, mesh)) {
      problem = "non-manifold vertices";
    }
    if (!problem.empty()) {
      result.status =
          Status::Make(StatusCode::kInvalidInput, "mesh is not a closed single-part 2-manifold (" +
                                                      problem + "); use alpha_wrap");
      return result;
    }
    if (PMP::volume(mesh) < 0) {
      PMP::reverse_face_orientations(mesh);
      report.orientation_flipped = true;
    }
  } else {
    checkMemoryEstimate(
        fmt::format("alpha wrap with alpha {:.3g} m ({})",
                    report.bbox_diagonal_m / params.alpha_divisor, describeSize(input)),
        estimateRegularisedBytes(estimateAlphaWrapTriangles(input, params)), "--alpha-divisor");
    std::vector<internal::CgalPoint> points;
    std::vector<std::array<std::size_t, 3>> faces;
    internal::toCgalSoup(input, points, faces);
    report.alpha_m = report.bbox_diagonal_m / params.alpha_divisor;
    report.offset_m = report.bbox_diagonal_m / params.offset_divisor;
    std::size_t parts = 0;
    double dropped = 0;
    for (int attempt = 0;; ++attempt) {
      mesh.clear();
      // CGAL's spatial sorting draws from a per-thread default generator whose state carries over
      // between calls; reseeding makes the wrap depend on the input only.
      CGAL::get_default_random() = CGAL::Random(0);
      try {
        CGAL::alpha_wrap_3(points, faces, report.alpha_m, report.offset_m, mesh);
      } catch (const std::exception& e) {
        result.status =
            Status::Make(StatusCode::kFailed, std::string("alpha wrap failed: ") + e.what());
        return result;
      }
      if (mesh.number_of_faces() == 0) {
        result.status = Status::Make(StatusCode::kFailed, "alpha wrap produced an empty mesh");
        return result;
      }
      std::tie(parts, dropped) = keepLargestComponent(mesh);
      if (parts <= 1 || dropped <= params.join_area_fraction || attempt >= params.join_attempts)
        break;
      log().info(
          "regularise: wrap split into {} parts ({:.1f}% of area outside the largest); "
          "retrying with alpha {:.4f} m",
          parts, 100 * dropped, 2 * report.alpha_m);
      report.alpha_m *= 2;
      ++report.join_retries;
    }
    report.wrap_components = parts;
    report.dropped_area_fraction = dropped;
    if (parts > 1) {
      if (!params.keep_largest_component) {
        result.status = Status::Make(
            StatusCode::kInvalidInput,
            "wrap has " + std::to_string(parts) + " separate parts; increase alpha to join them");
        return result;
      }
      log().warn(
          "regularise: wrap has {} separate parts, kept the largest ({:.1f}% of area dropped)",
          parts, 100 * dropped);
    }
    if (PMP::volume(mesh) < 0) PMP::reverse_face_orientations(mesh);
  }

  if (params.remesh_target_edge_m > 0) {
    PMP::isotropic_remeshing(faces(mesh), params.remesh_target_edge_m, mesh,
                             CGAL::parameters::number_of_iterations(params.remesh_iterations));
    mesh.collect_garbage();
    report.remeshed = true;
  }
  if (params.max_vertices && mesh.number_of_vertices() > *params.max_vertices) {
    report.decimated_from = mesh.number_of_vertices();
    decimate(mesh, *params.max_vertices);
  }

  result.mesh = internal::fromCgalMesh(mesh);
  report.output = analyzeTopology(result.mesh);
  report.time_s = watch.seconds();
  SKELGRASP_DEMAND(report.output.closed && report.output.components == 1);
  log().debug("regularise ({}): {} -> {} vertices, genus {} -> {}, {:.2f} s", report.method,
              report.input.vertices, report.output.vertices,
              report.input.genus ? std::to_string(*report.input.genus) : "n/a",
              report.output.genus ? std::to_string(*report.output.genus) : "n/a", report.time_s);
  return result;
}

}  // namespace skelgrasp::geometry
