// Files of `skelgrasp run --object all` (docs/pipeline.md): grasps.json with every object,
// object_<id>.ply and skeleton_<id>.json per meshed object, scene.bt, and report.html with a scene
// overview (3D view, object table, the scan coloured by object) and a section per object.
#include <fmt/format.h>
#include <limits>

#include <algorithm>
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
#include "skelgrasp/reconstruction/meshing.h"
#include "skelgrasp/skeleton/output.h"

namespace skelgrasp::pipeline {
using namespace grasping;

namespace internal {

nlohmann::json objectJson(const ObjectEntry& e) {
  nlohmann::json j = {{"id", e.id}, {"cluster", e.cluster}};
  if (e.info != nullptr) {
    j["points"] = e.info->points;
    j["centroid"] = toJson(e.info->centroid);
    j["box_min"] = toJson(e.info->box.min);
    j["box_max"] = toJson(e.info->box.max);
  }
  j["mesh"] = e.mesh_file.empty() ? nlohmann::json(nullptr) : nlohmann::json(e.mesh_file);
  j["mesh_vertices"] = e.mesh_vertices;
  j["observed_fraction"] = e.observed_fraction;
  j["status"] = e.status != nullptr ? toJson(*e.status) : nlohmann::json(nullptr);
  j["reason"] = e.reason.empty() ? nlohmann::json(nullptr) : nlohmann::json(e.reason);
  const std::size_t count = e.ranked != nullptr ? e.ranked->size() : 0;
  j["grasps"] = count;
  j["best_rank_score"] =
      count > 0 ? nlohmann::json(e.ranked->front().score) : nlohmann::json(nullptr);
  if (e.blocked_by != nullptr) {
    j["blocked_by"] = nlohmann::json::array();
    for (const auto& b : *e.blocked_by) {
      j["blocked_by"].push_back(
          {{"obstacle", b.obstacle},
           {"object", b.object ? nlohmann::json(*b.object) : nlohmann::json()},
           {"poses", b.poses}});
    }
  }
  j["time_s"] = e.time_s;
  j["timing"] = e.stages != nullptr ? timingJson(*e.stages, e.time_s) : nlohmann::json(nullptr);
  j["planning"] = e.plan != nullptr ? planSummaryJson(*e.plan) : nlohmann::json(nullptr);
  return j;
}

void appendGraspsJson(nlohmann::json& grasps, const std::vector<RankedGrasp>& ranked,
                      const HandModel& hand, std::size_t object_id, std::size_t first_id) {
  for (std::size_t k = 0; k < ranked.size(); ++k) {
    auto g = graspToJson(ranked[k].grasp, hand);
    g["id"] = first_id + k;
    g["object"] = object_id;
    g["rank_in_object"] = k;
    g["observed_contact_ratio"] = ranked[k].observed_contact_ratio;
    g["rank_score"] = ranked[k].score;
    grasps.push_back(std::move(g));
  }
}

}  // namespace internal

namespace {

// Object colours of the scan picture, cycled; the support plane is grey.
const std::array<Rgb, 8> kObjectColours = {{{220, 30, 30},
                                            {30, 130, 220},
                                            {40, 170, 60},
                                            {230, 150, 20},
                                            {150, 60, 200},
                                            {20, 180, 180},
                                            {200, 60, 140},
                                            {120, 120, 30}}};

Rgb objectColour(std::size_t id) {
  return kObjectColours[id % kObjectColours.size()];
}

std::string meshFile(std::size_t id) {
  return fmt::format("object_{}.ply", id);
}

nlohmann::json sceneRunJson(const SceneRunResult& r, const HandModel& hand,
                            const perception::Scan& scan, const std::string& name) {
  PlanResult header;  // the scene's summary: the sum of its planned objects'
  header.status = r.status;
  header.planner = "skeleton";
  nlohmann::json objects = nlohmann::json::array(), grasps = nlohmann::json::array();
  std::size_t kept = 0;
  for (const auto& o : r.objects) {
    internal::ObjectEntry e;
    e.id = o.id;
    e.cluster = o.cluster;
    e.info = &o.info;
    if (!o.mesh.empty()) e.mesh_file = meshFile(o.id);
    e.mesh_vertices = o.mesh.numVertices();
    e.observed_fraction = r.reconstruction.objects[o.id].meshing.report.observed_fraction;
    e.status = &o.status;
    e.reason = o.reason;
    e.ranked = &o.ranked;
    e.blocked_by = &o.blocked_by;
    if (o.skeleton && o.skeleton->status.ok()) {
      e.plan = &o.plan.summary;
      header.summary.add(o.plan.summary);
    }
    e.time_s = o.total_s;
    e.stages = &o.stages;
    objects.push_back(internal::objectJson(e));
    internal::appendGraspsJson(grasps, o.ranked, hand, o.id, kept);
    kept += o.ranked.size();
  }
  nlohmann::json j = planToJson(header, hand, name);
  j["schema"] = internal::kRunSchema;
  j["summary"]["kept"] = kept;
  j["objects"] = objects;
  j["target"] = nullptr;  // every object is a target: see "objects"
  j["grasps"] = grasps;
  j["scene"] = internal::sceneJson(r.plane, scan, r.obstacle_points, r.occupancy);
  j["timing"] = internal::timingJson(r.stages, r.total_s);
  return j;
}

// The scan from the sensor's side, each object in its colour, the support grey.
void renderSceneScan(const std::string& path, const SceneRunResult& r,
                     const perception::Scan& scan) {
  std::vector<std::pair<std::size_t, Rgb>> objects;
  for (const auto& o : r.objects) objects.emplace_back(o.cluster, objectColour(o.id));
  internal::renderScanPng(path, scan, r.reconstruction.ingest.scene, objects,
                          "scan: objects by colour (see the table), support plane grey");
}

void addObjectTable(presentation::HtmlReport& report, const SceneRunResult& r) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& o : r.objects) {
    const Rgb c = objectColour(o.id);
    rows.push_back({fmt::format("{} (#{:02x}{:02x}{:02x})", o.id, c[0], c[1], c[2]),
                    std::to_string(o.info.points), std::to_string(o.ranked.size()),
                    o.ranked.empty() ? "-" : fmt::format("{:.4f}", o.ranked.front().score),
                    fmt::format("{:.2f}", o.total_s),
                    o.reason.empty() ? "ok" : o.reason + ": " + o.status.message});
  }
  report.table({"object (colour)", "points", "grasps", "best score", "seconds", "status"}, rows);
  std::string links = "<p>Sections:";
  for (const auto& o : r.objects)
    links += fmt::format(" <a href=\"#object-{0}\">object {0}</a>", o.id);
  report.rawHtml(links + "</p>\n");
}

// Scenes with more objects show each object's first kRowsInLargeScenes grasps in its table.
constexpr std::size_t kFullTablesUpTo = 20;
constexpr std::size_t kRowsInLargeScenes = 5;

void addObjectSection(presentation::HtmlReport& report, OutputTransaction& outputs,
                      const std::string& dir, const SceneObjectRun& o, const HandModel& hand,
                      std::size_t objects) {
  // The id is the anchor the overview's links (and the demo's index) point to.
  report.rawHtml(fmt::format("<h2 id=\"object-{0}\">Object {0}</h2>\n", o.id));
  report.paragraph(fmt::format(
      "{} points, centroid ({:.3f}, {:.3f}, {:.3f}) m; {} ranked grasps in {:.2f} s{}.",
      o.info.points, o.info.centroid.x(), o.info.centroid.y(), o.info.centroid.z(), o.ranked.size(),
      o.total_s, o.reason.empty() ? "" : "; " + o.reason + ": " + o.status.message));
  if (o.mesh.empty() || !o.skeleton || !o.skeleton->status.ok()) return;
  PlanResult shown;
  shown.planner = "skeleton";
  for (const auto& ranked : o.ranked) shown.grasps.push_back(ranked.grasp);
  const std::string file = fmt::format("grasps_{}.png", o.id);
  presentation::renderPlanPng(outputs.stage(dir + "/" + file), o.mesh, &o.skeleton->skeleton, shown,
                              hand);
  report.image(file, fmt::format("Object {}: approach directions; the best grasp closed", o.id));
  // A large scene's report keeps to its budget (docs/report.md): fewer rows per object.
  internal::addGraspTable(
      report, o.ranked,
      objects > kFullTablesUpTo ? kRowsInLargeScenes : std::numeric_limits<std::size_t>::max());
  internal::addRobustnessHistogram(report, o.ranked);
  report.paragraph(fmt::format("Object {}: why hypotheses were rejected", o.id));
  internal::addRejectionTable(report, o.plan.summary);
}

}  // namespace

nlohmann::json sceneRunToJson(const SceneRunResult& result, const HandModel& hand,
                              const perception::Scan& scan, const std::string& input_name) {
  return sceneRunJson(result, hand, scan, input_name);
}

void writeSceneRunOutputs(const std::string& dir, const SceneRunResult& r, const HandModel& hand,
                          const perception::Scan& scan, const std::string& input_name,
                          const ExtraRunOutputs& extra) {
  // As writeRunOutputs: every file staged, renamed together, grasps.json last, a previous run's
  // files replaced.
  OutputTransaction outputs;
  outputs.replacePreviousOutputsIn(dir);
  const auto staged = [&](const std::string& file) { return outputs.stage(dir + "/" + file); };
  presentation::HtmlReport report("skelgrasp run: every object of " + input_name + " with " +
                                  hand.name());
  report.paragraph(fmt::format("{} of {} objects got grasps. {}", r.objectsWithGrasps(),
                               r.objects.size(), r.status.ok() ? "" : r.status.message));
  report.heading("3D view");
  report.rawHtml(sceneRunView(r, hand, scan).html());
  report.heading("Objects");
  addObjectTable(report, r);
  if (!scan.cloud.empty()) {
    const std::string scan_png = staged("scan.png");
    renderSceneScan(scan_png, r, scan);
    if (std::filesystem::exists(scan_png)) report.image("scan.png", "The scan by object");
  }
  report.heading("Stages");
  std::vector<std::vector<std::string>> rows;
  for (const auto& s : r.stages) rows.push_back({s.stage, fmt::format("{:.3f}", s.seconds)});
  for (const auto& o : r.objects) {
    rows.push_back({fmt::format("object {}", o.id), fmt::format("{:.3f}", o.total_s)});
  }
  rows.push_back({"total", fmt::format("{:.3f}", r.total_s)});
  report.table({"stage", "seconds"}, rows);
  if (r.occupancy) r.occupancy->writeBinary(staged("scene.bt"));
  for (const auto& o : r.objects) {
    if (!o.mesh.empty())
      reconstruction::saveObservedMesh(staged(meshFile(o.id)), o.mesh, o.observed);
    if (o.skeleton && o.skeleton->status.ok()) {
      MeshLoadInfo info;
      info.path = meshFile(o.id);
      info.format = "ply";
      writeJsonFile(staged(fmt::format("skeleton_{}.json", o.id)),
                    skeleton::skeletonToJson(*o.skeleton, o.mesh, info));
    }
    addObjectSection(report, outputs, dir, o, hand, r.objects.size());
  }
  report.write(staged("report.html"));
  const nlohmann::json grasps = sceneRunJson(r, hand, scan, input_name);
  if (extra) extra(outputs, grasps);
  writeJsonFile(staged("grasps.json"), grasps);
  outputs.commit();
}

}  // namespace skelgrasp::pipeline
