#pragma once
// Command-line options of the skeleton stage, shared by the commands that run it.
#include <CLI/CLI.hpp>

#include <vector>

#include "help_format.h"
#include "option_checks.h"

#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/skeleton/extraction.h"

namespace skelgrasp::cli {

struct SkeletonOptions {
  std::string units = "auto";
  std::string regularise = toString(skeleton::SkeletonParams{}.regularisation.method);
  double alpha_divisor = skeleton::SkeletonParams{}.regularisation.alpha_divisor;
  double offset_divisor = skeleton::SkeletonParams{}.regularisation.offset_divisor;
  double remesh_edge_m = skeleton::SkeletonParams{}.regularisation.remesh_target_edge_m;
  std::size_t max_vertices = skeleton::SkeletonParams{}.regularisation.max_vertices.value_or(0);
  double stencil_m = skeleton::GraphAnalysisParams{}.curvature_stencil_m;
  double spur_factor = skeleton::SkeletonParams{}.spur_radius_factor;
  bool write_regularised = false;
  std::string render_path;

  // `outputs`: also the options that write extra files (for the skeleton command itself). Without
  // them the skeleton is one stage of the command, and its tuning options (all but --units) are
  // in kSkeletonDetails (--help-all).
  void addTo(CLI::App& cmd, bool outputs = true) {
    cmd.add_option("--units", units, "Input length unit: auto (diagonal > 5 means mm), m or mm")
        ->check(CLI::IsMember({"auto", "m", "mm"}))
        ->capture_default_str();
    const auto as_is_floor = skeleton::SkeletonParams{}.regularisation.auto_min_vertices;
    const std::vector<CLI::Option*> tuning = {
        cmd.add_option("--regularise", regularise,
                       "auto (a closed, self-intersection-free manifold of at least " +
                           std::to_string(as_is_floor.value_or(0)) +
                           " vertices as it is, any other mesh alpha-wrapped), alpha_wrap, or none "
                           "(input must already be a closed single-part manifold)")
            ->check(CLI::IsMember({"alpha_wrap", "none", "auto"}))
            ->capture_default_str(),
        cmd.add_option("--alpha-divisor", alpha_divisor, "Alpha = bbox diagonal / this")
            ->check(positiveFinite(kMaxRatio))
            ->capture_default_str(),
        cmd.add_option("--offset-divisor", offset_divisor, "Wrap offset = bbox diagonal / this")
            ->check(positiveFinite(kMaxRatio))
            ->capture_default_str(),
        cmd.add_option("--remesh", remesh_edge_m,
                       "Isotropic remeshing target edge length in metres after wrapping (0 = off)")
            ->check(lengthOrZero())
            ->capture_default_str(),
        cmd.add_option("--max-vertices", max_vertices,
                       "Simplify the closed mesh by edge collapse to about this many vertices "
                       "before contraction when it has more (0 = never; docs/skeleton.md)")
            ->transform(vertexCountOrZero())
            ->capture_default_str(),
        cmd.add_option("--curvature-stencil", stencil_m,
                       "Arc length (m) over which skeleton curvature is differentiated")
            ->check(lengthOrZero())
            ->capture_default_str(),
        cmd.add_option("--spur-factor", spur_factor,
                       "Prune terminal branches shorter than this times the local radius (0 = off)")
            ->check(finiteIn(0, kMaxRatio))
            ->capture_default_str(),
    };
    if (!outputs) {
      for (CLI::Option* option : tuning) option->group(kSkeletonDetails);
      return;
    }
    cmd.add_flag("--write-regularised", write_regularised, "Also write regularised.ply");
    cmd.add_option("--render", render_path, "Also render segmentation and skeleton to this PNG");
  }

  MeshLoadOptions loadOptions() const {
    MeshLoadOptions o;
    o.units = parseLengthUnit(units);
    return o;
  }

  skeleton::SkeletonParams params() const {
    skeleton::SkeletonParams p;
    p.regularisation.method = geometry::parseRegularisationMethod(regularise);
    p.regularisation.alpha_divisor = alpha_divisor;
    p.regularisation.offset_divisor = offset_divisor;
    p.regularisation.remesh_target_edge_m = remesh_edge_m;
    p.regularisation.max_vertices =
        max_vertices > 0 ? std::optional<std::size_t>(max_vertices) : std::nullopt;
    p.graph.curvature_stencil_m = stencil_m;
    p.spur_radius_factor = spur_factor;
    return p;
  }
};

int runSkeletonOnFile(const std::string& mesh_path, const std::string& out_dir,
                      const SkeletonOptions& options);

}  // namespace skelgrasp::cli
