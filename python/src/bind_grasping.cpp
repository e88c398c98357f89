// Hands, the planners and pictures (closing and re-scoring: bind_scoring.cpp).
#include <pybind11/stl.h>

#include <map>
#include <optional>

#include "bindings.h"
#include "convert.h"
#include "plan_options.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/evaluation/plan_record.h"
#include "skelgrasp/evaluation/score.h"
#include "skelgrasp/grasping/io/plan_output.h"
#include "skelgrasp/grasping/planning/planners.h"
#include "skelgrasp/presentation/hand_render.h"
#include "skelgrasp/presentation/plan_render.h"
#include "skelgrasp/ranking/plan_grasps.h"
#include "skelgrasp/skeleton/output.h"

namespace skelgrasp::python {
namespace {

HandPtr builtinOrUrdf(const std::string& name) {
  py::gil_scoped_release release;
  return std::make_shared<grasping::HandModel>(grasping::resolveHand(name));
}

HandPtr handFromFiles(const std::string& urdf, const std::string& description) {
  py::gil_scoped_release release;
  return std::make_shared<grasping::HandModel>(grasping::loadHand(urdf, description));
}

// `options` (None: PlanOptions()) with the keyword shortcuts given, validated, planned.
Plan plan(const Mesh& mesh, const HandPtr& hand, const std::optional<PlanOptions>& given,
          std::optional<std::uint64_t> seed, std::optional<double> timeout_s,
          std::optional<std::size_t> max_grasps, std::optional<double> mu) {
  PlanOptions options = given.value_or(PlanOptions{});
  if (seed) options.seed = *seed;
  if (timeout_s) options.timeout_s = *timeout_s;
  if (max_grasps) options.max_grasps = *max_grasps;
  if (mu) options.quality.friction = *mu;
  options.validate();
  const ranking::PlanOptions library = options.library();
  Plan out;
  out.hand = hand;
  out.object = mesh.name;
  py::gil_scoped_release release;
  out.result = ranking::planGrasps(mesh.mesh, *hand, library);
  // As the CLI: a mesh the skeleton stage cannot process is bad input.
  if (out.result.skeleton_failed)
    throw InvalidArgument(mesh.name + ": " + out.result.status.message);
  if (out.result.skeleton) {
    out.skeleton = SkeletonOutput{std::move(*out.result.skeleton), mesh};
    out.result.skeleton.reset();
  }
  return out;
}

}  // namespace

void bindGrasping(py::module_& m) {
  py::class_<grasping::HandModel, std::shared_ptr<grasping::HandModel>>(m, "Hand", R"doc(
A robot hand: URDF kinematics and collision geometry plus its grasp description (fingers,
preshapes, planner thresholds; docs/hands.md). From :func:`hand` or :func:`load_hand`.)doc")
      .def_property_readonly("name", &grasping::HandModel::name, "Short name ('sdh', ...).")
      .def_property_readonly("title", &grasping::HandModel::title, "Descriptive title.")
      .def_property_readonly(
          "preshapes",
          [](const grasping::HandModel& h) {
            std::vector<std::string> names;
            for (const auto& [name, _] : h.preshapes()) names.push_back(name);
            return names;
          },
          "Preshape names (e.g. ['power', 'precision']).")
      .def_property_readonly(
          "preshape_length_limits",
          [](const grasping::HandModel& h) {
            std::map<std::string, double> limits;
            for (const auto& [name, preshape] : h.preshapes())
              if (preshape.max_object_length_m) limits[name] = *preshape.max_object_length_m;
            return limits;
          },
          "Preshapes made for small objects and the longest object (metres, along its longest "
          "principal axis) the planners close each on, e.g. {'narrow_tripod': 0.07} for the SDH; "
          "the others are closed on every object (docs/hands.md).")
      .def_property_readonly(
          "joints",
          [](const grasping::HandModel& h) {
            std::vector<std::string> names;
            for (const auto& j : h.joints())
              if (j.movable()) names.push_back(j.name);
            return names;
          },
          "Names of the movable joints (the keys of a grasp's ``joints``).")
      .def_property_readonly(
          "fingers", [](const grasping::HandModel& h) { return h.fingers().size(); },
          "Number of fingers.")
      .def_property_readonly("dof", &grasping::HandModel::numDrives,
                             "Actuated drives while closing.")
      .def("__repr__", [](const grasping::HandModel& h) {
        return "<skelgrasp.Hand '" + h.name() + "': " + h.title() + ">";
      });

  m.def("hands", &grasping::builtinHandNames, "Names of the built-in hands.");
  m.def("hand", &builtinOrUrdf, py::arg("name"), R"doc(
A built-in hand: 'armar3', 'sdh', 'shadow' or 'parallel_gripper'. Raises ValueError for another
name (the message lists the built-in hands).)doc");
  m.def("load_hand", &handFromFiles, py::arg("urdf"), py::arg("grasp_description"), R"doc(
A hand from a URDF file (meshes resolved relative to it) and a grasp description JSON
(docs/hands.md). Raises FileNotFoundError / OSError naming the file and the problem.)doc");

  py::class_<Grasp>(m, "Grasp", "A planned grasp on an object (object frame, metres, radians).")
      .def_property_readonly(
          "hand_pose", [](const Grasp& g) { return fromPose(g.grasp.hand_pose); },
          "4 x 4 pose of the hand's root link in the object frame.")
      .def_property_readonly(
          "gcp_pose", [](const Grasp& g) { return fromPose(g.grasp.gcp_pose); },
          "4 x 4 pose of the grasp centre point (z = approach direction) after the retreat.")
      .def_property_readonly(
          "joints", [](const Grasp& g) { return jointsDict(*g.hand, g.grasp.joints); },
          "{joint name: value} of the closed hand (radians or metres).")
      .def_property_readonly(
          "contacts", [](const Grasp& g) { return contactsList(g.grasp.contacts); },
          "List of {point, normal (object's outward unit normal), link, palm}.")
      .def_property_readonly(
          "force_closure", [](const Grasp& g) { return g.grasp.force_closure; },
          "Whether the contacts hold the object against any wrench.")
      .def_property_readonly(
          "epsilon", [](const Grasp& g) { return g.grasp.epsilon; },
          "Ferrari-Canny epsilon (L1) of the grasp wrench space.")
      .def_property_readonly(
          "volume", [](const Grasp& g) { return g.grasp.volume; },
          "Grasp wrench space volume, or None when not computed "
          "(``PlanOptions.quality.compute_volume``).")
      .def_property_readonly(
          "robustness",
          [](const Grasp& g) -> py::object {
            if (!g.grasp.robustness) return py::none();
            return fromJson(grasping::graspToJson(g.grasp, *g.hand)["robustness"]);
          },
          "{r, ci95, samples, mu, sigma_m, sigma_rad, variant, failures} when the robust ranking "
          "scored the grasp, else None (failures: {start_collision, closing, no_force_closure}, "
          "why the failed samples failed); with 'refinement' {refined, evaluations, "
          "search_samples, r_before, preshape_before, moves, mean_shift} where refinement for "
          "robustness searched near it, and there 'check' {samples, holds_before, holds_after} "
          "where it checked a pose it found against the planner's.")
      .def_property_readonly(
          "type", [](const Grasp& g) { return std::string(toString(g.grasp.type)); },
          "'power' or 'precision'.")
      .def_property_readonly(
          "strategy", [](const Grasp& g) { return g.grasp.strategy; },
          "Planner strategy: '1a' '1b' '2a' '2b' '3' '4' or 'surface'.")
      .def_property_readonly(
          "preshape", [](const Grasp& g) { return g.grasp.preshape; }, "Preshape name.")
      .def_property_readonly(
          "id", [](const Grasp& g) { return g.grasp.id; }, "Rank in its plan (0 = best).")
      .def_property_readonly(
          "observed_contact_ratio", [](const Grasp& g) { return g.observed_contact_ratio; },
          ":func:`run` only: share of contacts on surface the sensor saw (NaN otherwise).")
      .def_property_readonly(
          "rank_score", [](const Grasp& g) { return g.rank_score; },
          ":func:`run` only: the ranking score (NaN otherwise).")
      .def(
          "to_dict",
          [](const Grasp& g) {
            auto j = grasping::graspToJson(g.grasp, *g.hand);
            if (!std::isnan(g.rank_score)) {
              j["observed_contact_ratio"] = g.observed_contact_ratio;
              j["rank_score"] = g.rank_score;
            }
            return fromJson(j);
          },
          "The grasp as in grasps.json (docs/planning.md).")
      .def("__repr__", [](const Grasp& g) {
        return "<skelgrasp.Grasp " + std::string(toString(g.grasp.type)) + " strategy " +
               g.grasp.strategy + ", epsilon " + std::to_string(g.grasp.epsilon) + ">";
      });

  py::class_<Plan>(m, "PlanResult", "The result of :func:`plan`.")
      .def_property_readonly(
          "grasps",
          [](const Plan& p) {
            std::vector<Grasp> out;
            for (const auto& g : p.result.grasps) out.push_back({g, p.hand});
            return out;
          },
          "Kept grasps, best first (the robust ranking's order; by epsilon without it).")
      .def_property_readonly(
          "summary",
          [](const Plan& p) {
            return fromJson(grasping::planToJson(p.result, *p.hand, p.object)["summary"]);
          },
          "Counts, rejection reasons and time (grasps.json's summary).")
      .def_property_readonly(
          "status",
          [](const Plan& p) {
            return py::make_tuple(toString(p.result.status.code), p.result.status.message);
          },
          "(code, message): 'ok', or 'no_result' when no grasp was kept.")
      .def_property_readonly(
          "skeleton",
          [](const Plan& p) -> py::object {
            return p.skeleton ? py::cast(*p.skeleton) : py::none();
          },
          "The object's Skeleton (skeleton planner), else None.")
      .def(
          "to_dict",
          [](const Plan& p) {
            nlohmann::json document = grasping::planToJson(p.result, *p.hand, p.object);
            evaluation::addPlanRecords(document, p.result.ranking, p.result.timing);
            return fromJson(document);
          },
          "grasps.json as ``skelgrasp plan`` writes it (schema skelgrasp.grasps/3), with the "
          "robust ranking's record and the stages' times.")
      .def("__len__", [](const Plan& p) { return p.result.grasps.size(); })
      .def("__repr__", [](const Plan& p) {
        return "<skelgrasp.PlanResult: " +
               grasping::planSummaryLine(p.result, p.hand->name(), p.object) + ">";
      });

  m.def("plan", &plan, py::arg("mesh"), py::arg("hand"), py::arg("options") = py::none(),
        py::kw_only(), py::arg("seed") = py::none(), py::arg("timeout_s") = py::none(),
        py::arg("max_grasps") = py::none(), py::arg("mu") = py::none(),
        R"doc(
Plans grasps for ``mesh`` with ``hand`` and ranks them by robustness (``skelgrasp plan``;
docs/planning.md, docs/ranking.md). ``options``: a PlanOptions (None: PlanOptions(), the library's
defaults, no time limit); ``seed``, ``timeout_s``, ``max_grasps`` and ``mu`` (its
``quality.friction``) override its fields. Deterministic for a seed. Calls ``options.validate()``
first (ValueError naming the field); a mesh the skeleton stage cannot process raises ValueError.)doc");

  m.def(
      "render_plan",
      [](const std::string& path, const Plan& p, const Mesh& mesh) {
        py::gil_scoped_release release;
        presentation::renderPlanPng(path, mesh.mesh,
                                    p.skeleton ? &p.skeleton->result.skeleton : nullptr, p.result,
                                    *p.hand);
      },
      py::arg("path"), py::arg("plan"), py::arg("mesh"),
      "PNG of the object, its skeleton and every grasp's approach, plus the best grasp with the "
      "closed hand (``skelgrasp plan --render``).");
  m.def(
      "render_grasp",
      [](const std::string& path, const Grasp& g, const Mesh& mesh) {
        const auto& preshape = g.hand->preshape(g.grasp.preshape);
        py::gil_scoped_release release;
        presentation::renderGraspPng(path, mesh.mesh, *g.hand, g.grasp.hand_pose, preshape.joints,
                                     g.grasp.joints, g.grasp.contacts);
      },
      py::arg("path"), py::arg("grasp"), py::arg("mesh"),
      "PNG of the object with the hand in its preshape and closed, from two sides.");
}

}  // namespace skelgrasp::python
