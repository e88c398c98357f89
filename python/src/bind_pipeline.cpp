// The perception branch and the main job: reconstruct (scan -> closed meshes) and run (scan ->
// ranked collision-free grasps on one object).
#include <pybind11/stl.h>

#include <fmt/format.h>

#include <cmath>
#include <filesystem>

#include "bindings.h"
#include "convert.h"
#include "skelgrasp/pipeline/reconstruction_report.h"
#include "skelgrasp/pipeline/run_output.h"
#include "skelgrasp/pipeline/run_pipeline.h"

namespace skelgrasp::python {
namespace {

struct Reconstruction {
  pipeline::ReconstructionResult result;
  pipeline::ReconstructionParams params;
  perception::Scan scan;
};

struct Run {
  pipeline::RunResult result;
  HandPtr hand;
  perception::Scan scan;
  std::string name;
};

// run(objects='all'): every object of the scene in one run (pipeline::runScene).
struct SceneRun {
  pipeline::SceneRunResult result;
  HandPtr hand;
  perception::Scan scan;
  std::string name;
};

// "largest" | "all" | "nearest:x,y,z" | "index:k", or a point (x, y, z): the object nearest to it.
perception::TargetSpec targetOf(const py::object& objects) {
  if (py::isinstance<py::str>(objects))
    return perception::TargetSpec::parse(objects.cast<std::string>());
  const Matrix point = Matrix::ensure(objects);  // null when not numeric
  if (!point || point.size() != 3)
    throw InvalidArgument(
        "objects: expected 'largest', 'all', 'nearest:x,y,z', 'index:k' or a point x, y, z");
  const double* xyz = point.data();
  if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
    throw InvalidArgument("objects: the point is not finite");
  perception::TargetSpec spec;
  spec.mode = perception::TargetMode::kNearest;
  spec.point = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
  return spec;
}

// The scan's file name (as the CLI names the run) or the name the cloud was given.
std::string scanName(const perception::Scan& scan) {
  const auto name = std::filesystem::path(scan.source).filename().string();
  return name.empty() ? scan.source : name;
}

pipeline::ReconstructionParams reconstructionParams(
    const py::object& objects, const std::string& plane, double voxel_leaf_m,
    double cluster_tolerance_m, double plane_distance_m, double plane_hull_margin_m,
    int poisson_depth, double samples_per_node, double observed_distance_m, bool completion) {
  pipeline::ReconstructionParams p;
  p.ingest.filters.voxel_leaf_m = voxel_leaf_m;
  p.ingest.scene.plane = perception::parsePlaneRequirement(plane);
  p.ingest.scene.target = targetOf(objects);
  p.ingest.scene.cluster_tolerance_m = cluster_tolerance_m;
  p.ingest.scene.plane_distance_m = plane_distance_m;
  p.ingest.scene.plane_hull_margin_m = plane_hull_margin_m;
  p.meshing.poisson.depth = poisson_depth;
  p.meshing.poisson.samples_per_node = samples_per_node;
  p.meshing.observed_distance_m = observed_distance_m;
  p.meshing.completion.support_plane = completion;
  return p;
}

Reconstruction reconstruct(const Cloud& cloud, const py::object& objects, const std::string& plane,
                           double voxel_leaf_m, double cluster_tolerance_m, double plane_distance_m,
                           double plane_hull_margin_m, int poisson_depth, double samples_per_node,
                           double observed_distance_m, bool completion) {
  Reconstruction out;
  out.params = reconstructionParams(objects, plane, voxel_leaf_m, cluster_tolerance_m,
                                    plane_distance_m, plane_hull_margin_m, poisson_depth,
                                    samples_per_node, observed_distance_m, completion);
  out.scan = cloud.scan;
  py::gil_scoped_release release;
  out.result = pipeline::reconstructScan(out.scan, out.params);
  // As `skelgrasp reconstruct`: no plane, no object, an all-NaN cloud are bad input.
  if (!out.result.status.ok())
    throw InvalidArgument(out.scan.source + ": " + out.result.status.message);
  return out;
}

py::object run(const Cloud& cloud, const HandPtr& hand, const py::object& objects, bool scene_check,
               double timeout_s, std::size_t max_grasps, std::uint64_t seed, double mu,
               double observed_weight, double octree_resolution_m, const std::string& unknown_space,
               double pregrasp_distance_m, const std::string& plane, double voxel_leaf_m,
               int poisson_depth, bool robustness, int robustness_samples,
               const std::string& robustness_variant, std::size_t robustness_top_k,
               std::optional<std::size_t> robustness_screen,
               std::optional<int> robustness_screen_samples,
               const std::optional<std::string>& robustness_screen_by,
               std::optional<int> robustness_confirm_samples, std::optional<double> robustness_mu,
               bool robust_refine, std::optional<double> robust_refine_below_r) {
  checkTimeout(timeout_s);
  pipeline::RunParams p;
  p.robust_ranking = robustRankingParams(
      robustness, robustness_samples, robustness_variant, robustness_top_k, robustness_screen,
      robustness_screen_samples, robustness_screen_by, robustness_confirm_samples, robustness_mu,
      seed, robust_refine, robust_refine_below_r);
  p.reconstruction.ingest.filters.voxel_leaf_m = voxel_leaf_m;
  p.reconstruction.ingest.scene.plane = perception::parsePlaneRequirement(plane);
  p.reconstruction.ingest.scene.target = targetOf(objects);
  p.reconstruction.meshing.poisson.depth = poisson_depth;
  p.scene_check = scene_check;
  p.planner.timeout_s = timeout_s;
  p.planner.max_grasps = max_grasps;
  p.planner.seed = seed;
  p.planner.hypothesis.quality.friction = mu;
  p.observed_weight = observed_weight;
  p.occupancy.resolution_m = octree_resolution_m;
  if (unknown_space != "free" && unknown_space != "occupied")
    throw InvalidArgument("unknown_space: '" + unknown_space + "' is not free or occupied");
  p.occupancy.unknown = unknown_space == "occupied" ? grasping::UnknownSpace::kOccupied
                                                    : grasping::UnknownSpace::kFree;
  p.approach.pregrasp_distance_m = pregrasp_distance_m;
  if (p.reconstruction.ingest.scene.target.mode == perception::TargetMode::kAll) {
    SceneRun out{{}, hand, cloud.scan, scanName(cloud.scan)};
    {
      py::gil_scoped_release release;
      out.result = pipeline::runScene(out.scan, *hand, p);
    }
    // As `run --object all`: a scan without a plane or object is bad input; objects without
    // grasps are results that say why.
    const auto& ingest = out.result.reconstruction.ingest;
    if (!ingest.status.ok()) throw InvalidArgument(out.scan.source + ": " + ingest.status.message);
    return py::cast(std::move(out));
  }
  Run out{{}, hand, cloud.scan, scanName(cloud.scan)};
  {
    py::gil_scoped_release release;
    out.result = pipeline::runPipeline(out.scan, *hand, p);
  }
  if (!out.result.reconstruction.status.ok())
    throw InvalidArgument(out.scan.source + ": " + out.result.reconstruction.status.message);
  return py::cast(std::move(out));
}

py::array_t<std::uint8_t> flags(const std::vector<std::uint8_t>& values) {
  return py::array_t<std::uint8_t>(static_cast<py::ssize_t>(values.size()), values.data());
}

}  // namespace

void bindPipeline(py::module_& m) {
  py::class_<Reconstruction>(m, "Reconstruction", "The result of :func:`reconstruct`.")
      .def_property_readonly(
          "objects",
          [](const Reconstruction& r) {
            std::vector<Mesh> out;
            for (const auto& o : r.result.objects)
              out.push_back({o.meshing.mesh, {}, fmt::format("object_{}", o.cluster)});
            return out;
          },
          "One closed Mesh per selected object (scan frame, metres).")
      .def_property_readonly(
          "observed",
          [](const Reconstruction& r) {
            std::vector<py::array_t<std::uint8_t>> out;
            for (const auto& o : r.result.objects) out.push_back(flags(o.meshing.observed));
            return out;
          },
          "Per object: uint8 per mesh vertex, 1 where the sensor saw the surface, 0 filled in.")
      .def(
          "to_dict",
          [](const Reconstruction& r) {
            return fromJson(pipeline::reconstructionReport(r.scan, r.params, r.result));
          },
          "report.json of ``skelgrasp reconstruct`` (schema skelgrasp.reconstruction/1).");

  const pipeline::ReconstructionParams rec;
  m.def("reconstruct", &reconstruct, py::arg("cloud"), py::kw_only(),
        py::arg("objects") = rec.ingest.scene.target.toString(),
        py::arg("plane") = std::string(toString(rec.ingest.scene.plane)),
        py::arg("voxel_leaf_m") = rec.ingest.filters.voxel_leaf_m,
        py::arg("cluster_tolerance_m") = rec.ingest.scene.cluster_tolerance_m,
        py::arg("plane_distance_m") = rec.ingest.scene.plane_distance_m,
        py::arg("plane_hull_margin_m") = rec.ingest.scene.plane_hull_margin_m,
        py::arg("poisson_depth") = rec.meshing.poisson.depth,
        py::arg("samples_per_node") = rec.meshing.poisson.samples_per_node,
        py::arg("observed_distance_m") = rec.meshing.observed_distance_m,
        py::arg("completion") = rec.meshing.completion.support_plane, R"doc(
Scan to closed meshes (``skelgrasp reconstruct``): filters, support plane ('required',
'optional', 'none'), object clusters (inside the table points' hull grown by
``plane_hull_margin_m``), Poisson meshing with observed flags. ``objects``:
'largest', 'all', 'nearest:x,y,z' or a point (x, y, z). Defaults are the library's
ReconstructionParams (docs/reconstruction.md). No plane, no object or an all-NaN cloud raise
ValueError with the command line's message.)doc");

  py::class_<Run>(m, "RunResult", "The result of :func:`run` (scan frame, metres).")
      .def_property_readonly(
          "grasps",
          [](const Run& r) {
            std::vector<Grasp> out;
            for (const auto& g : r.result.ranked)
              out.push_back({g.grasp, r.hand, g.observed_contact_ratio, g.score});
            return out;
          },
          "Ranked collision-free grasps on the target, best first.")
      .def_property_readonly(
          "mesh",
          [](const Run& r) {
            return Mesh{r.result.mesh, {}, r.name + " (target)"};
          },
          "The target's closed mesh.")
      .def_property_readonly(
          "observed", [](const Run& r) { return flags(r.result.observed); },
          "uint8 per target mesh vertex: 1 observed, 0 filled in.")
      .def_property_readonly(
          "summary",
          [](const Run& r) {
            return fromJson(pipeline::runToJson(r.result, *r.hand, r.scan, r.name)["summary"]);
          },
          "Counts and rejection reasons of the planner (grasps.json's summary).")
      .def_property_readonly(
          "status",
          [](const Run& r) {
            return py::make_tuple(toString(r.result.status.code), r.result.status.message);
          },
          "(code, message): 'ok', or why there is no grasp.")
      .def(
          "to_dict",
          [](const Run& r) {
            return fromJson(pipeline::runToJson(r.result, *r.hand, r.scan, r.name));
          },
          "grasps.json as ``skelgrasp run`` writes it (schema skelgrasp.run/4).")
      .def("__len__", [](const Run& r) { return r.result.ranked.size(); });

  py::class_<pipeline::SceneObjectRun>(
      m, "SceneObject", "One object of a scene run (:func:`run` with objects='all').")
      .def_readonly("id", &pipeline::SceneObjectRun::id, "Its id in the outputs (0 = largest).")
      .def_property_readonly(
          "points", [](const pipeline::SceneObjectRun& o) { return o.info.points; },
          "Points of its cluster.")
      .def_property_readonly(
          "centroid",
          [](const pipeline::SceneObjectRun& o) {
            return py::make_tuple(o.info.centroid.x(), o.info.centroid.y(), o.info.centroid.z());
          },
          "Centroid of its points (scan frame, metres).")
      .def_readonly("reason", &pipeline::SceneObjectRun::reason,
                    "Empty when it has grasps, else meshing_failed, skeleton_failed, no_grasp or too_wide.")
      .def_property_readonly(
          "mesh",
          [](const pipeline::SceneObjectRun& o) {
            return Mesh{o.mesh, {}, fmt::format("object_{}", o.id)};
          },
          "Its closed mesh (empty when meshing failed).");

  py::class_<SceneRun>(m, "SceneRunResult",
                       "The result of :func:`run` with objects='all' (scan frame, metres).")
      .def_property_readonly(
          "objects",
          [](const SceneRun& r) {
            py::list out;
            for (const auto& o : r.result.objects) out.append(py::cast(o));
            return out;
          },
          "Every selected object, largest first, with its status.")
      .def(
          "grasps",
          [](const SceneRun& r, std::size_t object) {
            if (object >= r.result.objects.size())
              throw InvalidArgument("object " + std::to_string(object) + ": the scene has " +
                                    std::to_string(r.result.objects.size()) + " objects");
            std::vector<Grasp> out;
            for (const auto& g : r.result.objects[object].ranked)
              out.push_back({g.grasp, r.hand, g.observed_contact_ratio, g.score});
            return out;
          },
          py::arg("object"), "Ranked collision-free grasps of one object, best first.")
      .def_property_readonly(
          "status",
          [](const SceneRun& r) {
            return py::make_tuple(toString(r.result.status.code), r.result.status.message);
          },
          "(code, message): 'ok' when at least one object got grasps.")
      .def(
          "to_dict",
          [](const SceneRun& r) {
            return fromJson(pipeline::sceneRunToJson(r.result, *r.hand, r.scan, r.name));
          },
          "grasps.json as ``skelgrasp run --object all`` writes it (schema skelgrasp.run/4).")
      .def("__len__", [](const SceneRun& r) { return r.result.objects.size(); });

  const pipeline::RunParams run_defaults;
  m.def("run", &run, py::arg("cloud"), py::arg("hand"), py::kw_only(),
        py::arg("objects") = run_defaults.reconstruction.ingest.scene.target.toString(),
        py::arg("scene_check") = run_defaults.scene_check,
        py::arg("timeout_s") = run_defaults.planner.timeout_s,
        py::arg("max_grasps") = run_defaults.planner.max_grasps,
        py::arg("seed") = run_defaults.planner.seed,
        py::arg("mu") = run_defaults.planner.hypothesis.quality.friction,
        py::arg("observed_weight") = run_defaults.observed_weight,
        py::arg("octree_resolution_m") = run_defaults.occupancy.resolution_m,
        py::arg("unknown_space") = std::string(
            run_defaults.occupancy.unknown == grasping::UnknownSpace::kOccupied ? "occupied"
                                                                                : "free"),
        py::arg("pregrasp_distance_m") = run_defaults.approach.pregrasp_distance_m,
        py::arg("plane") = std::string(toString(run_defaults.reconstruction.ingest.scene.plane)),
        py::arg("voxel_leaf_m") = run_defaults.reconstruction.ingest.filters.voxel_leaf_m,
        py::arg("poisson_depth") = run_defaults.reconstruction.meshing.poisson.depth,
        py::arg("robustness") = run_defaults.robust_ranking.enabled,
        py::arg("robustness_samples") = run_defaults.robust_ranking.robustness.samples,
        py::arg("robustness_variant") =
            std::string(ranking::toString(run_defaults.robust_ranking.robustness.variant)),
        py::arg("robustness_top_k") = run_defaults.robust_ranking.top_k,
        py::arg("robustness_screen") = run_defaults.robust_ranking.screen_k,
        py::arg("robustness_screen_samples") = run_defaults.robust_ranking.screen_samples,
        py::arg("robustness_screen_by") = py::none(),
        py::arg("robustness_confirm_samples") = run_defaults.robust_ranking.confirm_samples,
        py::arg("robustness_mu") = run_defaults.robust_ranking.friction,
        py::arg("robust_refine") = run_defaults.robust_ranking.refinement.enabled,
        py::arg("robust_refine_below_r") = run_defaults.robust_ranking.refinement.search_below_r,
        R"doc(
The main job (``skelgrasp run``): a scan of a table scene to ranked, collision-free grasps on one
object (``objects``: 'largest', 'nearest:x,y,z', 'index:k' or a point; a RunResult) or on every
object in one run (``objects='all'``: a SceneRunResult, as ``run --object all``). Defaults are the
library's RunParams (docs/pipeline.md); the robustness keywords are the CLI's ranking options
(``robustness_samples``: ``--robustness-samples``). A scan without a plane or object raises
ValueError; no grasp is a result with status 'no_result'.)doc");
}

}  // namespace skelgrasp::python
