#include "skelgrasp/reconstruction/meshing.h"

#include <algorithm>
#include <cmath>

#include "poisson.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/common/resources.h"
#include "skelgrasp/geometry/point_index.h"
#include "skelgrasp/perception/completion.h"

namespace skelgrasp::reconstruction {
namespace {

void validate(const PointCloud& object, const MeshingParams& p) {
  if (!object.hasNormals()) throw InvalidArgument("meshObject: the object cloud has no normals");
  if (p.poisson.depth < 2 || p.poisson.depth > 14 || !(p.poisson.point_weight >= 0) ||
      !(p.poisson.samples_per_node > 0) || !(p.poisson.scale >= 1.0)) {
    throw InvalidArgument(
        "meshObject: Poisson depth must be in [2, 14], point weight >= 0, samples per node > 0, "
        "scale >= 1");
  }
  if (p.trim.max_distance_m < 0 || p.trim.max_distance_fraction < 0 ||
      !(p.trim.density_radius_m > 0) || !(p.completion.cell_m > 0) ||
      !(p.observed_distance_m > 0)) {
    throw InvalidArgument(
        "meshObject: trimming, completion and observed distances must be positive");
  }
}

// Drops unreferenced vertices (so the regularisation's bounding box is the surface's own).
TriangleMesh compact(const TriangleMesh& mesh, const std::vector<char>& keep_face) {
  TriangleMesh out;
  std::vector<int> remap(mesh.vertices.size(), -1);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (!keep_face[f]) continue;
    Eigen::Vector3i t;
    for (int k = 0; k < 3; ++k) {
      int& r = remap[mesh.faces[f][k]];
      if (r < 0) {
        r = static_cast<int>(out.vertices.size());
        out.vertices.push_back(mesh.vertices[mesh.faces[f][k]]);
      }
      t[k] = r;
    }
    out.faces.push_back(t);
  }
  return out;
}

// Calibration of estimatePoissonBytes (docs/limits.md, "Poisson reconstruction"): peak RSS of
// `reconstruct osd_test2.pcd` (5565 object points) above its 167 MiB at depths <= 8 grew by 11,
// 63, 240 and 850 MiB at depths 9-12, i.e. 53-63 bytes per 4^depth. PCL's conversion copies
// cost about 100 bytes per point on top.
constexpr double kPoissonBytesPerPoint = 200;
constexpr double kPoissonBytesPerNode = 64;
constexpr double kPoissonSurfaceNodeFactor = 1;

}  // namespace

double estimatePoissonBytes(std::size_t points, const PoissonParams& params) {
  const double depth = params.depth;
  const double nodes =
      std::min(std::pow(8.0, depth), kPoissonSurfaceNodeFactor * std::pow(4.0, depth));
  return kPoissonBytesPerPoint * static_cast<double>(points) + kPoissonBytesPerNode * nodes;
}

void checkPoissonMemory(std::size_t points, const PoissonParams& params) {
  checkMemoryEstimate("Poisson reconstruction at depth " + std::to_string(params.depth) + " of " +
                          std::to_string(points) + " points",
                      estimatePoissonBytes(points, params), "--poisson-depth");
}

TrimMode parseTrimMode(const std::string& text) {
  if (text == "none") return TrimMode::kNone;
  if (text == "distance") return TrimMode::kDistance;
  if (text == "density") return TrimMode::kDensity;
  throw InvalidArgument("unknown trim mode '" + text + "' (use none, distance or density)");
}

const char* toString(TrimMode mode) {
  switch (mode) {
    case TrimMode::kNone:
      return "none";
    case TrimMode::kDistance:
      return "distance";
    case TrimMode::kDensity:
      return "density";
  }
  return "?";
}

std::vector<std::uint8_t> observedFlags(const TriangleMesh& mesh,
                                        const std::vector<Eigen::Vector3d>& observed_points,
                                        double distance) {
  std::vector<std::uint8_t> flags(mesh.vertices.size(), 0);
  const geometry::PointIndex index(observed_points);
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    flags[i] = index.nearest(mesh.vertices[i]).second <= distance ? 1 : 0;
  }
  return flags;
}

MeshingResult meshObject(const PointCloud& object,
                         const std::optional<perception::SupportPlane>& plane,
                         const MeshingParams& params) {
  validate(object, params);
  Stopwatch total, watch;
  MeshingResult result;
  auto& report = result.report;
  report.input_points = object.size();
  auto finish = [&](StatusCode code, const std::string& message) {
    result.status = Status::Make(code, message);
    report.total_s = total.seconds();
    return result;
  };
  if (object.size() < 10) {
    return finish(StatusCode::kInvalidInput,
                  "too few object points to mesh (" + std::to_string(object.size()) + ")");
  }

  PointCloud samples;
  samples.points = object.points;
  samples.normals = object.normals;
  if (params.completion.support_plane && plane) {
    perception::SupportCompletionParams completion;
    completion.cell_m = params.completion.cell_m;
    const auto generated = perception::completeOnSupport(object, *plane, completion).points;
    report.completion_points = generated.size();
    samples.points.insert(samples.points.end(), generated.points.begin(), generated.points.end());
    samples.normals.insert(samples.normals.end(), generated.normals.begin(),
                           generated.normals.end());
  }
  report.completion_s = watch.seconds();

  checkPoissonMemory(samples.size(), params.poisson);
  watch.restart();
  const TriangleMesh poisson = detail::poissonSurface(samples, params.poisson);
  report.poisson_s = watch.seconds();
  report.poisson_vertices = poisson.numVertices();
  report.poisson_faces = poisson.numFaces();
  if (poisson.empty())
    return finish(StatusCode::kFailed, "Poisson reconstruction produced no surface");

  watch.restart();
  std::vector<char> keep(poisson.faces.size(), 1);
  const auto& trim = params.trim;
  if (trim.mode != TrimMode::kNone) {
    const geometry::PointIndex data(samples.points);
    report.trim_threshold_m = trim.mode == TrimMode::kDistance
                                  ? std::max(trim.max_distance_m, trim.max_distance_fraction *
                                                                      samples.bounds().diagonal())
                                  : trim.density_radius_m;
    for (std::size_t f = 0; f < poisson.faces.size(); ++f) {
      const auto& t = poisson.faces[f];
      const Eigen::Vector3d c =
          (poisson.vertices[t[0]] + poisson.vertices[t[1]] + poisson.vertices[t[2]]) / 3.0;
      keep[f] = trim.mode == TrimMode::kDistance
                    ? data.nearest(c).second <= report.trim_threshold_m
                    : data.countWithin(c, trim.density_radius_m) >= trim.min_density_points;
      report.trimmed_faces += keep[f] ? 0 : 1;
    }
  }
  const TriangleMesh trimmed = compact(poisson, keep);
  report.faces_after_trim = trimmed.numFaces();
  report.trim_s = watch.seconds();
  if (trimmed.empty()) {
    return finish(StatusCode::kNoResult, "trimming removed the whole Poisson surface");
  }

  watch.restart();
  geometry::RegularisationResult regular = geometry::regularise(trimmed, params.regularisation);
  report.regularisation = regular.report;
  report.regularise_s = watch.seconds();
  if (!regular.status.ok()) {
    return finish(regular.status.code, "regularisation: " + regular.status.message);
  }
  result.mesh = std::move(regular.mesh);

  watch.restart();
  result.observed = observedFlags(result.mesh, object.points, params.observed_distance_m);
  report.vertices = result.mesh.numVertices();
  report.faces = result.mesh.numFaces();
  for (auto f : result.observed) report.observed_vertices += f;
  report.observed_fraction =
      report.vertices > 0 ? static_cast<double>(report.observed_vertices) / report.vertices : 0.0;
  double area = 0, observed_area = 0;
  for (std::size_t f = 0; f < result.mesh.faces.size(); ++f) {
    const double a = result.mesh.faceArea(f);
    const auto& t = result.mesh.faces[f];
    area += a;
    if (result.observed[t[0]] && result.observed[t[1]] && result.observed[t[2]]) observed_area += a;
  }
  report.observed_area_fraction = area > 0 ? observed_area / area : 0.0;
  report.observed_s = watch.seconds();
  report.total_s = total.seconds();
  log().info(
      "meshing: {} points (+{} completion) -> Poisson {} faces -> trimmed {} -> closed {} "
      "vertices, {:.0f}% observed, {:.3f} s",
      report.input_points, report.completion_points, report.poisson_faces, report.trimmed_faces,
      report.vertices, 100 * report.observed_fraction, report.total_s);
  return result;
}

void saveObservedMesh(const std::string& path, const TriangleMesh& mesh,
                      const std::vector<std::uint8_t>& observed) {
  saveMesh(path, mesh, {PlyVertexProperty{"observed", observed}});
}

std::vector<std::uint8_t> loadObservedFlags(const std::string& path) {
  return loadPlyVertexProperty(path, "observed");
}

}  // namespace skelgrasp::reconstruction
