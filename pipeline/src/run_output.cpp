// Files of `skelgrasp run`: grasps.json, object.ply, skeleton.json, segmentation.ply, scene.bt and
// report.html with its pictures.
#include <fmt/format.h>

#include <filesystem>

#include "run_json.h"
#include "run_report_grasps.h"
#include "run_scene_view.h"
#include "skelgrasp/common/atomic_file.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/grasping/io/plan_output.h"
#include "skelgrasp/pipeline/run_output.h"
#include "skelgrasp/presentation/hand_render.h"
#include "skelgrasp/presentation/html_report.h"
#include "skelgrasp/presentation/plan_render.h"
#include "skelgrasp/presentation/render.h"
#include "skelgrasp/presentation/skeleton_render.h"
#include "skelgrasp/reconstruction/meshing.h"
#include "skelgrasp/skeleton/output.h"

namespace skelgrasp::pipeline {
// The pipeline composes the grasping stage's types throughout.
using namespace grasping;
namespace {
constexpr int kPanel = 480;
}  // namespace

namespace internal {

nlohmann::json sceneJson(const std::optional<Eigen::Vector4d>& plane, const perception::Scan& scan,
                         std::size_t obstacle_points,
                         const std::shared_ptr<SceneOccupancy>& occupancy) {
  return {
      {"frame", "scan"},
      {"plane", plane ? nlohmann::json({(*plane)[0], (*plane)[1], (*plane)[2], (*plane)[3]})
                      : nlohmann::json(nullptr)},
      {"sensor_origin", toJson(scan.cloud.sensor_origin)},
      {"obstacle_points", obstacle_points},
      {"occupancy", occupancy ? nlohmann::json({{"file", "scene.bt"},
                                                {"resolution_m", occupancy->resolution()},
                                                {"occupied_leaves", occupancy->occupiedLeaves()}})
                              : nlohmann::json(nullptr)}};
}

nlohmann::json timingJson(const std::vector<StageTime>& stages, double total_s) {
  nlohmann::json timing = nlohmann::json::object();
  for (const auto& s : stages) timing[s.stage] = s.seconds;
  timing["total_s"] = total_s;
  return timing;
}

void renderScanPng(const std::string& path, const perception::Scan& scan,
                   const perception::SceneResult& scene,
                   const std::vector<std::pair<std::size_t, Rgb>>& coloured_clusters,
                   const std::string& caption) {
  AxisAlignedBox box;
  for (const auto& p : scan.cloud.points) {
    if (p.allFinite()) box.extend(p);
  }
  if (box.empty()) return;
  const Eigen::Vector3d from = scan.cloud.sensor_origin - box.center();
  presentation::Canvas canvas(presentation::Camera::framing(
      box, from.norm() > 1e-6 ? from : Eigen::Vector3d(0, -1, 1), 2 * kPanel, kPanel));
  const std::size_t stride = std::max<std::size_t>(1, scan.cloud.size() / 120000);
  for (std::size_t i = 0; i < scan.cloud.size(); i += stride) {
    const auto& p = scan.cloud.points[i];
    if (!p.allFinite()) continue;
    canvas.drawPoint(p, scan.cloud.hasColors() ? scan.cloud.colors[i] : Rgb{90, 110, 160}, 1);
  }
  for (const auto& p : scene.plane_points.points) canvas.drawPoint(p, {170, 170, 170}, 1);
  for (const auto& [cluster, colour] : coloured_clusters) {
    for (const auto& p : scene.clusters[cluster].points) canvas.drawPoint(p, colour, 1);
  }
  canvas.drawText(8, 4, caption);
  canvas.savePng(path);
}

}  // namespace internal

namespace {

nlohmann::json runJson(const RunResult& r, const HandModel& hand, const perception::Scan& scan,
                       const std::string& name) {
  PlanResult header;
  header.status = r.status;
  header.planner = "skeleton";
  header.summary = r.plan.summary;
  nlohmann::json j = planToJson(header, hand, name);
  j["schema"] = internal::kRunSchema;
  j["summary"]["kept"] = r.ranked.size();
  nlohmann::json grasps = nlohmann::json::array();
  internal::appendGraspsJson(grasps, r.ranked, hand, 0, 0);
  j["grasps"] = grasps;
  const auto& scene = r.reconstruction.ingest.scene;
  const bool known = r.cluster < scene.cluster_info.size();
  const double observed_fraction =
      r.reconstruction.objects.empty()
          ? 0.0
          : r.reconstruction.objects.front().meshing.report.observed_fraction;
  nlohmann::json object = nullptr;
  if (known) {
    const auto& info = scene.cluster_info[r.cluster];
    object = {{"cluster", r.cluster},
              {"points", info.points},
              {"centroid", toJson(info.centroid)},
              {"box_min", toJson(info.box.min)},
              {"box_max", toJson(info.box.max)},
              {"mesh", "object.ply"},
              {"mesh_vertices", r.mesh.numVertices()},
              {"observed_fraction", observed_fraction}};
  }
  j["target"] = object;
  // The one target as the only entry of the scene runs' object list (schema run/2).
  nlohmann::json objects = nlohmann::json::array();
  if (known) {
    internal::ObjectEntry e;
    e.cluster = r.cluster;
    e.info = &scene.cluster_info[r.cluster];
    if (!r.mesh.empty()) e.mesh_file = "object.ply";
    e.mesh_vertices = r.mesh.numVertices();
    e.observed_fraction = observed_fraction;
    e.status = &r.status;
    if (r.mesh.empty()) {
      e.reason = object_reason::kMeshingFailed;
    } else if (!r.skeleton || !r.skeleton->status.ok()) {
      e.reason = object_reason::kSkeletonFailed;
    } else if (r.ranked.empty()) {
      e.reason = object_reason::kNoGrasp;
    }
    e.ranked = &r.ranked;
    if (r.skeleton && r.skeleton->status.ok()) e.plan = &r.plan.summary;
    e.time_s = r.total_s;
    objects.push_back(internal::objectJson(e));
  }
  j["objects"] = objects;
  j["scene"] = internal::sceneJson(r.plane, scan, r.obstacles.size(), r.occupancy);
  j["timing"] = internal::timingJson(r.stages, r.total_s);
  return j;
}

// The scan from the sensor's side: the target red, the support grey, everything else by colour
// or height.
void renderScan(const std::string& path, const RunResult& r, const perception::Scan& scan) {
  const auto& scene = r.reconstruction.ingest.scene;
  std::vector<std::pair<std::size_t, Rgb>> target;
  if (r.cluster < scene.clusters.size()) target.emplace_back(r.cluster, Rgb{220, 30, 30});
  internal::renderScanPng(path, scan, scene, target, "scan: target red, support plane grey");
}

void renderSegments(const std::string& path, const RunResult& r) {
  const TriangleMesh coloured = skeleton::colourBySegment(r.mesh, r.skeleton->skeleton);
  std::vector<presentation::Canvas> panels;
  for (const Eigen::Vector3d& view :
       {Eigen::Vector3d(1, -1.2, 0.8), Eigen::Vector3d(-1, 1.2, 0.5)}) {
    presentation::Canvas canvas(
        presentation::Camera::framing(r.mesh.bounds(), view, kPanel, kPanel));
    canvas.drawMesh(coloured, {200, 200, 200});
    canvas.drawText(8, 4, "reconstruction coloured by segment (grey: branching)");
    panels.push_back(std::move(canvas));
  }
  presentation::Canvas::saveGrid({&panels[0], &panels[1]}, 2, path);
}

// One grasp with the hand closed, in its surroundings (obstacle points within reach).
void renderBestGrasp(const std::string& path, const RunResult& r, const HandModel& hand,
                     const RankedGrasp& ranked) {
  const Grasp& g = ranked.grasp;
  const TriangleMesh hand_mesh = presentation::handMesh(hand, g.hand_pose, g.joints);
  AxisAlignedBox box = r.mesh.bounds();
  for (const auto& v : hand_mesh.vertices) box.extend(v);
  const Eigen::Vector3d approach = g.gcp_pose.rotation().col(2);
  const Eigen::Vector3d side = anyPerpendicular(approach);
  presentation::Canvas canvas(presentation::Camera::framing(
      box, side - 0.6 * approach + 0.4 * approach.cross(side), kPanel, kPanel));
  const Eigen::Vector3d centre = box.center();
  const double reach = 0.6 * box.diagonal();
  for (const auto& p : r.obstacles.points) {
    if ((p - centre).norm() < reach) canvas.drawPoint(p, {150, 150, 150}, 1, true);
  }
  TriangleMesh object = r.mesh;
  object.vertex_colors.clear();
  canvas.drawMesh(object, {215, 200, 170}, false);
  canvas.drawMesh(hand_mesh, {0, 0, 0});
  presentation::drawContacts(canvas, g.contacts, 0.02);
  canvas.drawText(
      8, 4,
      fmt::format("#{} {} {} eps {:.3f} observed {:.0f}% {}score {:.3f}", g.id, toString(g.type),
                  g.strategy, g.epsilon, 100 * ranked.observed_contact_ratio,
                  g.robustness ? fmt::format("r {:.2f} ", g.robustness->r) : "", ranked.score));
  canvas.savePng(path);
}

}  // namespace

nlohmann::json runToJson(const RunResult& result, const HandModel& hand,
                         const perception::Scan& scan, const std::string& input_name) {
  return runJson(result, hand, scan, input_name);
}

void writeRunOutputs(const std::string& dir, const RunResult& r, const HandModel& hand,
                     const perception::Scan& scan, const std::string& input_name,
                     const ExtraRunOutputs& extra) {
  // All files go to temporary names and are renamed into place together at the end, grasps.json
  // (the index of the others) last: a failure on the way leaves neither a partial set nor stray
  // temporaries, and a directory without grasps.json is visibly incomplete.
  OutputTransaction outputs;
  outputs.replacePreviousOutputsIn(dir);
  const auto staged = [&](const std::string& file) { return outputs.stage(dir + "/" + file); };
  presentation::HtmlReport report("skelgrasp run: " + input_name + " with " + hand.name());
  report.paragraph(r.status.ok()
                       ? fmt::format("{} ranked grasps on the target object.", r.ranked.size())
                       : "No grasp: " + r.status.message);
  // The interactive view first: it is what a reader turns to; the PNGs below stay for text-only
  // readers and tests.
  report.heading("3D view");
  report.rawHtml(runSceneView(r, hand, scan).html());
  report.heading("Stages");
  std::vector<std::vector<std::string>> rows;
  for (const auto& s : r.stages) rows.push_back({s.stage, fmt::format("{:.3f}", s.seconds)});
  rows.push_back({"total", fmt::format("{:.3f}", r.total_s)});
  report.table({"stage", "seconds"}, rows);

  if (!scan.cloud.empty()) {
    const std::string scan_png = staged("scan.png");
    renderScan(scan_png, r, scan);
    if (std::filesystem::exists(scan_png)) report.image("scan.png", "The scan");
  }
  if (!r.mesh.empty()) {
    reconstruction::saveObservedMesh(staged("object.ply"), r.mesh, r.observed);
  }
  if (r.occupancy) r.occupancy->writeBinary(staged("scene.bt"));
  if (r.skeleton && r.skeleton->status.ok()) {
    MeshLoadInfo info;
    info.path = "object.ply";
    info.format = "ply";
    writeJsonFile(staged("skeleton.json"), skeleton::skeletonToJson(*r.skeleton, r.mesh, info));
    saveMesh(staged("segmentation.ply"),
             skeleton::colourByVertexType(r.mesh, r.skeleton->skeleton));
    renderSegments(staged("reconstruction.png"), r);
    report.image("reconstruction.png", "Reconstruction coloured by skeleton segment");
    presentation::renderSkeletonPng(r.mesh, r.skeleton->skeleton, staged("skeleton.png"));
    report.image("skeleton.png", "Segmentation (paper colours) and skeleton");
    PlanResult shown;
    shown.planner = "skeleton";
    for (const auto& ranked : r.ranked) shown.grasps.push_back(ranked.grasp);
    presentation::renderPlanPng(staged("grasps.png"), r.mesh, &r.skeleton->skeleton, shown, hand);
    report.image("grasps.png", "Approach directions of all grasps; the best grasp closed");
  }
  report.heading("Grasps");
  internal::addGraspTable(report, r.ranked);
  report.heading("Robustness");
  internal::addRobustnessHistogram(report, r.ranked);
  report.heading("Best grasps");
  for (std::size_t k = 0; k < std::min<std::size_t>(3, r.ranked.size()); ++k) {
    const std::string file = fmt::format("best_{}.png", k);
    renderBestGrasp(staged(file), r, hand, r.ranked[k]);
    report.image(file, fmt::format("Grasp #{} with the hand closed", k));
  }
  report.heading("Why hypotheses were rejected");
  internal::addRejectionTable(report, r.plan.summary);
  report.write(staged("report.html"));
  const nlohmann::json grasps = runJson(r, hand, scan, input_name);
  if (extra) extra(outputs, grasps);
  writeJsonFile(staged("grasps.json"), grasps);
  outputs.commit();
}

}  // namespace skelgrasp::pipeline
