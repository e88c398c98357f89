#pragma once
// Command-line options of the perception and reconstruction stages, shared by `reconstruct`,
// `ingest` and `bench reconstruct`.
#include <CLI/CLI.hpp>

#include "option_checks.h"

#include <sstream>

#include "skelgrasp/datasets/input.h"
#include "skelgrasp/pipeline/reconstruct_scan.h"

namespace skelgrasp::cli {

// Statistical outlier removal looks at this many neighbours at most: beyond it the mean distance
// describes the cloud's extent rather than a point's neighbourhood.
constexpr int kMaxOutlierNeighbours = 1000;

struct ReconstructOptions {
  std::string object = "largest";
  std::string units = "auto";
  std::string plane = "required";
  std::string crop;
  double voxel_m = perception::FilterParams{}.voxel_leaf_m;
  int outlier_k = perception::FilterParams{}.sor_mean_k;
  double cluster_tolerance_m = perception::SceneParams{}.cluster_tolerance_m;
  std::string segmentation = perception::toString(perception::SceneParams{}.segmentation);
  double plane_distance_m = perception::SceneParams{}.plane_distance_m;
  double hull_margin_m = perception::SceneParams{}.plane_hull_margin_m;
  double normal_radius_m = perception::NormalParams{}.radius_m;
  int threads = 1;
  int poisson_depth = reconstruction::PoissonParams{}.depth;
  double point_weight = reconstruction::PoissonParams{}.point_weight;
  double samples_per_node = reconstruction::PoissonParams{}.samples_per_node;
  std::string trim = "distance";
  double trim_fraction = reconstruction::TrimParams{}.max_distance_fraction;
  double observed_m = reconstruction::MeshingParams{}.observed_distance_m;
  bool no_completion = false;
  std::string regularise = "auto";
  double alpha_divisor = reconstruction::MeshingParams{}.regularisation.alpha_divisor;
  double offset_divisor = reconstruction::MeshingParams{}.regularisation.offset_divisor;
  std::vector<int> cameras = datasets::YcbRawParams{}.cameras;
  int angle_step = datasets::YcbRawParams{}.angle_step_deg;

  void addInputOptions(CLI::App& cmd) {
    cmd.add_option("--units", units, "Input length unit: auto (diagonal > 20 means mm), m or mm")
        ->check(CLI::IsMember({"auto", "m", "mm"}))
        ->capture_default_str();
    cmd.add_option("--cameras", cameras,
                   "YCB raw: NP units to fuse, e.g. 1,3,5 (default: all present)")
        ->transform(countIn(1, 5))
        ->delimiter(',');
    cmd.add_option("--angle-step", angle_step,
                   "YCB raw: use turntable angles that are multiples (degrees)")
        ->transform(countIn(1, 360))
        ->capture_default_str();
  }

  void addIngestOptions(CLI::App& cmd) {
    cmd.add_option("--object", object,
                   "Target: largest, all, nearest:x,y,z (metres) or index:k (0 = largest)")
        ->capture_default_str();
    cmd.add_option("--plane", plane,
                   "Support plane: required (scenes), optional, none (single-object clouds)")
        ->check(CLI::IsMember({"required", "optional", "none"}))
        ->capture_default_str();
    cmd.add_option("--crop", crop, "Crop box xmin,ymin,zmin,xmax,ymax,zmax in metres");
    cmd.add_option("--voxel", voxel_m, "Voxel-grid leaf in metres (0 = off)")
        ->check(lengthOrZero())
        ->capture_default_str();
    cmd.add_option("--outlier-k", outlier_k, "Statistical outlier removal neighbours (0 = off)")
        ->transform(countIn(0, kMaxOutlierNeighbours))
        ->capture_default_str();
    cmd.add_option("--plane-distance", plane_distance_m, "RANSAC plane inlier distance (m)")
        ->check(positiveLength())
        ->capture_default_str();
    cmd.add_option("--hull-margin", hull_margin_m,
                   "Objects lie inside the table points' hull grown by this (m, 0 = the hull)")
        ->check(lengthOrZero())
        ->capture_default_str();
    cmd.add_option("--segmentation", segmentation,
                   "Objects above the support: lccp (supervoxels + locally convex patches: "
                   "separates touching objects; docs/perception.md) or euclidean (connected "
                   "components: touching objects stay one)")
        ->check(CLI::IsMember({"lccp", "euclidean"}))
        ->capture_default_str();
    cmd.add_option("--cluster-tolerance", cluster_tolerance_m, "Euclidean clustering distance (m)")
        ->check(positiveLength())
        ->capture_default_str();
    cmd.add_option("--normal-radius", normal_radius_m, "Normal estimation radius (m)")
        ->check(positiveLength())
        ->capture_default_str();
    cmd.add_option("--threads", threads,
                   "Threads for normals and Poisson (0 = all cores; PCL busy-waits, 1 is fastest "
                   "on shared cores)")
        ->transform(threadCount(0))
        ->capture_default_str();
  }

  void addMeshingOptions(CLI::App& cmd) {
    cmd.add_option("--poisson-depth", poisson_depth, "Poisson octree depth")
        ->transform(countIn(2, 14))
        ->capture_default_str();
    cmd.add_option("--point-weight", point_weight, "Poisson interpolation weight")
        ->check(finiteIn(0, kMaxRatio))
        ->capture_default_str();
    cmd.add_option("--samples-per-node", samples_per_node, "Poisson minimum samples per node")
        ->check(positiveFinite(kMaxRatio))
        ->capture_default_str();
    cmd.add_option("--trim", trim, "Trim unsupported surface: distance, density or none")
        ->check(CLI::IsMember({"distance", "density", "none"}))
        ->capture_default_str();
    cmd.add_option("--trim-fraction", trim_fraction,
                   "Distance trimming threshold as a fraction of the object's bbox diagonal")
        ->check(finiteIn(0, 1))
        ->capture_default_str();
    cmd.add_option("--observed-distance", observed_m,
                   "A vertex within this distance (m) of a sensor point is observed")
        ->check(positiveLength())
        ->capture_default_str();
    cmd.add_option("--regularise", regularise,
                   "auto (wrap only when Poisson's surface is not a closed manifold) or alpha_wrap")
        ->check(CLI::IsMember({"auto", "alpha_wrap"}))
        ->capture_default_str();
    cmd.add_option("--alpha-divisor", alpha_divisor, "Regularisation: alpha = bbox diagonal / this")
        ->check(positiveFinite(kMaxRatio))
        ->capture_default_str();
    cmd.add_option("--offset-divisor", offset_divisor,
                   "Regularisation: wrap offset = bbox diagonal / this")
        ->check(positiveFinite(kMaxRatio))
        ->capture_default_str();
    cmd.add_flag("--no-completion", no_completion,
                 "Do not close single views down to the support plane");
  }

  datasets::InputOptions inputOptions() const {
    datasets::InputOptions o;
    o.units.units = parseLengthUnit(units);
    o.ycb.cameras = cameras;
    o.ycb.angle_step_deg = angle_step;
    o.ycb.normals.radius_m = normal_radius_m;
    o.ycb.normals.threads = threads;
    return o;
  }

  pipeline::ReconstructionParams params() const {
    pipeline::ReconstructionParams p;
    auto& f = p.ingest.filters;
    f.voxel_leaf_m = voxel_m;
    f.sor_mean_k = outlier_k;
    if (!crop.empty()) f.crop_box = parseCrop(crop);
    auto& s = p.ingest.scene;
    s.plane = perception::parsePlaneRequirement(plane);
    s.target = perception::TargetSpec::parse(object);
    s.cluster_tolerance_m = cluster_tolerance_m;
    s.segmentation = perception::parseSegmentationMethod(segmentation);
    s.plane_distance_m = plane_distance_m;
    s.plane_hull_margin_m = hull_margin_m;
    p.ingest.normals.radius_m = normal_radius_m;
    p.ingest.normals.threads = threads;
    auto& m = p.meshing;
    m.poisson.depth = poisson_depth;
    m.poisson.point_weight = point_weight;
    m.poisson.samples_per_node = samples_per_node;
    m.poisson.threads = threads;
    m.trim.mode = reconstruction::parseTrimMode(trim);
    m.trim.max_distance_fraction = trim_fraction;
    m.observed_distance_m = observed_m;
    m.completion.support_plane = !no_completion;
    m.regularisation.method = geometry::parseRegularisationMethod(regularise);
    m.regularisation.alpha_divisor = alpha_divisor;
    m.regularisation.offset_divisor = offset_divisor;
    return p;
  }

  static AxisAlignedBox parseCrop(std::string text) {
    std::replace(text.begin(), text.end(), ',', ' ');
    std::istringstream in(text);
    AxisAlignedBox box;
    std::string extra;
    if (!(in >> box.min.x() >> box.min.y() >> box.min.z() >> box.max.x() >> box.max.y() >>
          box.max.z()) ||
        (in >> extra) || box.empty()) {
      throw InvalidArgument("--crop needs xmin,ymin,zmin,xmax,ymax,zmax with min <= max");
    }
    return box;
  }
};

}  // namespace skelgrasp::cli
