// skelgrasp bench segment SCANS...: scene segmentation scored against the clouds' per-point object
// labels (mOSD-style `label` field): objects labelled and found, mean precision, recall and IoU.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli.h"
#include "option_checks.h"
#include "output_paths.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/perception/cloud_io.h"
#include "skelgrasp/perception/ingest.h"
#include "skelgrasp/perception/label_score.h"

namespace skelgrasp::cli {
namespace {

constexpr int kBenchSegmentSchemaVersion = 1;

struct BenchSegmentArgs {
  std::vector<std::string> inputs;
  std::string json_out;
  std::string method = perception::toString(perception::SceneParams{}.segmentation);
  perception::IngestParams params;
};

nlohmann::json parametersJson(const perception::IngestParams& p) {
  const auto& s = p.scene;
  return {{"voxel_leaf_m", p.filters.voxel_leaf_m},
          {"cluster_tolerance_m", s.cluster_tolerance_m},
          {"min_cluster_points", s.min_cluster_points},
          {"plane_hull_margin_m", s.plane_hull_margin_m},
          {"lccp",
           {{"voxel_resolution_m", s.lccp.voxel_resolution_m},
            {"seed_resolution_m", s.lccp.seed_resolution_m},
            {"color_importance", s.lccp.color_importance},
            {"spatial_importance", s.lccp.spatial_importance},
            {"normal_importance", s.lccp.normal_importance},
            {"concavity_tolerance_deg", s.lccp.concavity_tolerance_deg},
            {"sanity_check", s.lccp.sanity_check},
            {"smoothness_check", s.lccp.smoothness_check},
            {"smoothness_threshold", s.lccp.smoothness_threshold},
            {"k_factor", s.lccp.k_factor},
            {"min_segment_points", s.lccp.min_segment_points},
            {"min_isolated_points", s.lccp.min_isolated_points},
            {"part_min_lift_m", s.lccp.part_min_lift_m},
            {"part_max_aspect", s.lccp.part_max_aspect},
            {"part_max_fraction", s.lccp.part_max_fraction},
            {"join_hidden_gaps", s.lccp.join_hidden_gaps},
            {"hidden_gap_max_m", s.lccp.hidden_gap_max_m},
            {"hidden_gap_step_m", s.lccp.hidden_gap_step_m},
            {"hidden_gap_ray_radius_rad", s.lccp.hidden_gap_ray_radius_rad},
            {"hidden_gap_min_depth_m", s.lccp.hidden_gap_min_depth_m},
            {"hidden_gap_max_colour_distance", s.lccp.hidden_gap_max_colour_distance}}}};
}

int runBenchSegment(BenchSegmentArgs args) {
  checkOutputFileOption(args.json_out);
  args.params.scene.segmentation = perception::parseSegmentationMethod(args.method);
  args.params.scene.target = perception::TargetSpec::parse("all");
  // Every input is loaded and checked for labels before anything is measured or written.
  std::vector<perception::Scan> scans;
  for (const auto& input : args.inputs) {
    perception::Scan scan;
    scan.cloud = perception::loadPointCloud(input);
    scan.source = input;
    if (!perception::hasObjectLabels(scan.cloud)) {
      return fail(input +
                  ": no per-point object labels (bench segment needs a `label` field with "
                  "mOSD object labels, 10 and above)");
    }
    scans.push_back(std::move(scan));
  }
  std::cout << fmt::format("{:<28} {:>8} {:>6} {:>9} {:>7} {:>6} {:>7} {:>7} {:>9}\n",
                           "scene (" + args.method + ")", "labelled", "found", "precision",
                           "recall", "iou", "merged", "dropped", "segment_s");
  nlohmann::json rows = nlohmann::json::array();
  double precision_sum = 0, recall_sum = 0, iou_sum = 0, time_sum = 0;
  std::size_t objects = 0, within_one = 0, failed = 0;
  double worst_precision = 1, worst_recall = 1;
  for (const auto& scan : scans) {
    const std::string name = std::filesystem::path(scan.source).filename().string();
    const auto ingest = perception::ingestScan(scan, args.params);
    if (!ingest.status.ok()) {
      ++failed;
      std::cout << fmt::format("{:<28} failed: {}\n", name, ingest.status.message);
      rows.push_back(
          {{"input", scan.source}, {"status", "failed"}, {"message", ingest.status.message}});
      continue;
    }
    const auto score = perception::scoreAgainstLabels(scan.cloud, ingest.scene.clusters);
    const double seconds = ingest.scene.cluster_time_s;
    std::cout << fmt::format("{:<28} {:>8} {:>6} {:>9.3f} {:>7.3f} {:>6.3f} {:>7} {:>7} {:>9.3f}\n",
                             name, score.objects.size(), score.segments, score.mean_precision,
                             score.mean_recall, score.mean_iou, ingest.scene.merged_fragments,
                             ingest.scene.dropped.size(), seconds);
    nlohmann::json per_object = nlohmann::json::array();
    for (const auto& o : score.objects) {
      per_object.push_back({{"object", o.object},
                            {"points", o.points},
                            {"segment", o.segment},
                            {"precision", o.precision},
                            {"recall", o.recall},
                            {"iou", o.iou}});
      precision_sum += o.precision;
      recall_sum += o.recall;
      iou_sum += o.iou;
    }
    nlohmann::json segments = nlohmann::json::array();
    for (std::size_t k = 0; k < score.segment_labels.size(); ++k) {
      const auto& l = score.segment_labels[k];
      segments.push_back({{"points", ingest.scene.clusters[k].size()},
                          {"labelled_points", l.points},
                          {"majority_object", l.majority},
                          {"majority_fraction", l.majority_fraction}});
    }
    nlohmann::json dropped = nlohmann::json::array();
    for (const auto& d : ingest.scene.dropped) {
      dropped.push_back({{"points", d.points},
                         {"centroid", {d.centroid.x(), d.centroid.y(), d.centroid.z()}},
                         {"reason", d.reason}});
    }
    const long difference =
        static_cast<long>(score.segments) - static_cast<long>(score.objects.size());
    within_one += std::abs(difference) <= 1;
    objects += score.objects.size();
    time_sum += seconds;
    worst_precision = std::min(worst_precision, score.mean_precision);
    worst_recall = std::min(worst_recall, score.mean_recall);
    rows.push_back({{"input", scan.source},
                    {"status", "ok"},
                    {"method", perception::toString(ingest.scene.segmentation)},
                    {"objects_labelled", score.objects.size()},
                    {"objects_found", score.segments},
                    {"mean_precision", score.mean_precision},
                    {"mean_recall", score.mean_recall},
                    {"mean_iou", score.mean_iou},
                    {"segment_s", seconds},
                    {"ingest_s", ingest.total_time_s},
                    {"candidate_points", ingest.scene.candidate_points},
                    {"merged_fragments", ingest.scene.merged_fragments},
                    {"segments", segments},
                    {"dropped", dropped},
                    {"objects", per_object}});
  }
  const std::size_t scored = scans.size() - failed;
  const double n = static_cast<double>(std::max<std::size_t>(objects, 1));
  std::cout << fmt::format(
      "all {} scenes, {} objects: precision {:.3f}, recall {:.3f}, iou {:.3f}; worst scene "
      "precision {:.3f}, recall {:.3f}; count within 1 on {}/{}; segmentation {:.3f} s\n",
      scored, objects, precision_sum / n, recall_sum / n, iou_sum / n, worst_precision,
      worst_recall, within_one, scored, time_sum);
  if (!args.json_out.empty()) {
    writeJsonFile(args.json_out, {{"schema", "skelgrasp.bench_segment"},
                                  {"schema_version", kBenchSegmentSchemaVersion},
                                  {"method", args.method},
                                  {"parameters", parametersJson(args.params)},
                                  {"scenes", rows},
                                  {"summary",
                                   {{"scenes", scored},
                                    {"failed", failed},
                                    {"objects", objects},
                                    {"mean_precision", precision_sum / n},
                                    {"mean_recall", recall_sum / n},
                                    {"mean_iou", iou_sum / n},
                                    {"worst_scene_precision", worst_precision},
                                    {"worst_scene_recall", worst_recall},
                                    {"count_within_one", within_one},
                                    {"segment_s", time_sum}}}});
  }
  return failed == 0 ? kExitOk : kExitBadInput;
}

}  // namespace

void registerBenchSegmentCommand(CLI::App& app, Action& action) {
  CLI::App* bench = app.get_subcommand("bench");  // created by registerBenchCommand
  auto* cmd = bench->add_subcommand(
      "segment", "Scene segmentation scored against per-point object labels (mOSD clouds)");
  auto args = std::make_shared<BenchSegmentArgs>();
  auto& scene = args->params.scene;
  auto& lccp = scene.lccp;
  cmd->add_option("SCANS", args->inputs, "Labelled point clouds (PCD/PLY with a label field)")
      ->required();
  cmd->add_option("--json", args->json_out, "Also write the rows as JSON");
  cmd->add_option("--method", args->method, "Segmentation: lccp or euclidean")
      ->check(CLI::IsMember({"lccp", "euclidean"}))
      ->capture_default_str();
  cmd->add_option("--voxel", args->params.filters.voxel_leaf_m,
                  "Voxel-grid leaf of the filters (m, 0 = off)")
      ->check(lengthOrZero())
      ->capture_default_str();
  cmd->add_option("--cluster-tolerance", scene.cluster_tolerance_m,
                  "Euclidean clustering distance (m)")
      ->check(positiveLength())
      ->capture_default_str();
  cmd->add_option("--min-points", scene.min_cluster_points, "Fewest points of an object")
      ->transform(countIn(1, kMaxCount))
      ->capture_default_str();
  cmd->add_option("--hull-margin", scene.plane_hull_margin_m,
                  "Objects lie inside the table points' hull grown by this (m, 0 = the hull)")
      ->check(lengthOrZero())
      ->capture_default_str();
  cmd->add_option("--min-segment-points", lccp.min_segment_points,
                  "LCCP: smaller segments are merged into a neighbour or dropped")
      ->transform(countIn(1, kMaxCount))
      ->capture_default_str();
  cmd->add_option("--voxel-resolution", lccp.voxel_resolution_m, "LCCP: supervoxel leaf (m)")
      ->check(positiveLength())
      ->capture_default_str();
  cmd->add_option("--seed-resolution", lccp.seed_resolution_m, "LCCP: supervoxel seed spacing (m)")
      ->check(positiveLength())
      ->capture_default_str();
  cmd->add_option("--concavity-tolerance", lccp.concavity_tolerance_deg,
                  "LCCP: concavity tolerance (degrees)")
      ->check(finiteIn(0, 179))
      ->capture_default_str();
  cmd->add_option("--color-importance", lccp.color_importance, "LCCP: supervoxel colour weight")
      ->check(finiteIn(0, kMaxRatio))
      ->capture_default_str();
  cmd->add_option("--spatial-importance", lccp.spatial_importance,
                  "LCCP: supervoxel spatial weight")
      ->check(finiteIn(0, kMaxRatio))
      ->capture_default_str();
  cmd->add_option("--normal-importance", lccp.normal_importance, "LCCP: supervoxel normal weight")
      ->check(finiteIn(0, kMaxRatio))
      ->capture_default_str();
  cmd->add_option("--smoothness-threshold", lccp.smoothness_threshold,
                  "LCCP: smoothness check threshold (0 = check off)")
      ->check(finiteIn(0, kMaxRatio))
      ->capture_default_str();
  cmd->add_option("--k-factor", lccp.k_factor, "LCCP: extended convexity k (0 = off)")
      ->transform(countIn(0, 4))
      ->capture_default_str();
  cmd->callback([=, &action] {
    action = [=] {
      BenchSegmentArgs copy = *args;
      copy.params.scene.lccp.smoothness_check = copy.params.scene.lccp.smoothness_threshold > 0;
      return runBenchSegment(copy);
    };
  });
}

}  // namespace skelgrasp::cli
