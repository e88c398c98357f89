#pragma once
// Oriented object points -> closed single-part mesh: optional completion down to the support
// plane, PCL Poisson reconstruction, trimming of surface the data does not support, regularisation
// (alpha wrap), and per-vertex observed / filled-in flags. Lengths in metres.
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/mesh.h"
#include "skelgrasp/common/point_cloud.h"
#include "skelgrasp/geometry/regularisation.h"
#include "skelgrasp/perception/scene.h"

namespace skelgrasp::reconstruction {

struct PoissonParams {
  // Octree depth: the finest cell is about 1.1 x the data's bounding box / 2^depth (0.9 mm for a
  // 10 cm object at depth 7). PCL's own default is 8.
  int depth = 7;
  // Weight of the interpolation term (screened Poisson): higher pulls the surface onto the points.
  double point_weight = 4.0;
  // Minimum number of samples per octree node: higher smooths noisy scans and stops refining
  // where the data is sparse. 3 instead of 1.5 halved Poisson's time and quartered the vertices
  // with the same accuracy (YCB round trips 0.22-0.35 mm vs 0.21-0.31 mm, docs/reconstruction.md).
  double samples_per_node = 3.0;
  double scale = 1.1;  // reconstruction cube / data bounding box
  // PCL's OpenMP solver busy-waits; on shared cores more threads made it 10x slower, not faster.
  int threads = 1;
};

// Peak memory of Poisson reconstruction (bytes) of `points` oriented points at `params.depth`:
//   bytes = kPoissonBytesPerPoint x points + kPoissonBytesPerNode x nodes,
//   nodes = min(8^depth, kPoissonSurfaceNodeFactor x 4^depth).
// A surface crosses about (its area in cells) ~ 4^depth of the 8^depth finest cells of the octree;
// the constants are fitted to the growth of /usr/bin/time -v peak RSS of `skelgrasp reconstruct`
// with the depth on a real scan (docs/limits.md).
double estimatePoissonBytes(std::size_t points, const PoissonParams& params);
// Throws ResourceLimitExceeded (common/resources.h) when that exceeds the memory limit.
void checkPoissonMemory(std::size_t points, const PoissonParams& params);

enum class TrimMode {
  kNone,
  kDistance,  // remove faces whose centroid is farther than the threshold from every data point
  kDensity,   // remove faces with fewer than min_density_points data points within the radius
};
TrimMode parseTrimMode(const std::string& text);  // none | distance | density
const char* toString(TrimMode mode);

struct TrimParams {
  TrimMode mode = TrimMode::kDistance;
  // Distance threshold = max(max_distance_m, max_distance_fraction x data bbox diagonal). Poisson
  // balloons far from the data; closing the back of a single view needs the surface within about
  // a fifth of the object size, which the default keeps.
  double max_distance_m = 0.005;
  double max_distance_fraction = 0.2;
  double density_radius_m = 0.01;
  std::size_t min_density_points = 3;
};

struct CompletionParams {
  // Single views see objects from one side only. With a support plane, the object is taken to fill
  // the space between the plane and its observed surface (perception/completion.h): footprint and
  // wall samples are added so Poisson closes the object on the table instead of ballooning.
  // Completion samples never count as observed.
  bool support_plane = true;
  double cell_m = 0.004;  // height-map cell
};

struct MeshingParams {
  CompletionParams completion;
  PoissonParams poisson;
  TrimParams trim;
  // Poisson surfaces are usually closed manifolds already; auto wraps only when they are not.
  geometry::RegularisationParams regularisation = [] {
    geometry::RegularisationParams p;
    p.method = geometry::RegularisationMethod::kAuto;
    return p;
  }();
  // A vertex is "observed" when an input (sensor) point lies within this distance, else it is
  // "filled-in" (Poisson extrapolation, completion, wrap closure).
  double observed_distance_m = 0.005;
};

struct MeshingReport {
  std::size_t input_points = 0;
  std::size_t completion_points = 0;
  std::size_t poisson_vertices = 0;
  std::size_t poisson_faces = 0;
  double trim_threshold_m = 0;
  std::size_t trimmed_faces = 0;
  std::size_t faces_after_trim = 0;
  geometry::RegularisationReport regularisation;
  std::size_t vertices = 0;
  std::size_t faces = 0;
  std::size_t observed_vertices = 0;
  double observed_fraction = 0;       // observed vertices / vertices
  double observed_area_fraction = 0;  // area of faces whose three vertices are observed / total
  double completion_s = 0;
  double poisson_s = 0;
  double trim_s = 0;
  double regularise_s = 0;
  double observed_s = 0;
  double total_s = 0;
};

struct MeshingResult {
  Status status;
  TriangleMesh mesh;                   // closed, single-part, outward 2-manifold when ok
  std::vector<std::uint8_t> observed;  // per mesh vertex: 1 observed, 0 filled-in
  MeshingReport report;
};

// `object` must carry normals pointing out of the object (towards the sensor for a single view).
// Throws InvalidArgument for bad parameters or a cloud without normals.
MeshingResult meshObject(const PointCloud& object,
                         const std::optional<perception::SupportPlane>& plane,
                         const MeshingParams& params = {});

// The meshing stage's entry in report.json ("objects", docs/reconstruction.md): parameters,
// measurements and the mesh; `mesh_file` is the written mesh, empty for none (null).
nlohmann::json toJson(const MeshingResult& meshing, const MeshingParams& params,
                      std::size_t cluster, const std::string& mesh_file);

// Observed flags of `mesh`'s vertices: 1 where an observed point lies within `distance`.
std::vector<std::uint8_t> observedFlags(const TriangleMesh& mesh,
                                        const std::vector<Eigen::Vector3d>& observed_points,
                                        double distance);

// The mesh as binary PLY with a `uchar observed` vertex property (1 observed, 0 filled-in), in the
// mesh's vertex order. Throws IoError / InvalidArgument (size mismatch).
void saveObservedMesh(const std::string& path, const TriangleMesh& mesh,
                      const std::vector<std::uint8_t>& observed);
// Reads the flags back; value i belongs to vertex i of loadMesh(path). Throws IoError.
std::vector<std::uint8_t> loadObservedFlags(const std::string& path);

}  // namespace skelgrasp::reconstruction
