// Hands, the planners and pictures (closing and re-scoring: bind_scoring.cpp).
#include <pybind11/stl.h>

#include <map>
#include <optional>

#include "bindings.h"
#include "convert.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/evaluation/plan_record.h"
#include "skelgrasp/evaluation/score.h"
#include "skelgrasp/grasping/io/plan_output.h"
#include "skelgrasp/grasping/planning/planners.h"
#include "skelgrasp/presentation/hand_render.h"
#include "skelgrasp/presentation/plan_render.h"
#include "skelgrasp/ranking/plan_grasps.h"
#include "skelgrasp/ranking/robust_ranking.h"
#include "skelgrasp/ranking/robustness.h"
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

Plan plan(const Mesh& mesh, const HandPtr& hand, const std::string& planner, std::uint64_t seed,
          double timeout_s, std::size_t max_grasps, double min_epsilon, double mu,
          double vertex_distance_m, std::optional<double> round_ratio, bool reference_compat,
          const std::string& fc_test, const std::string& closing, std::size_t max_hypotheses,
          const std::string& regularisation, double alpha_divisor, double offset_divisor,
          double spur_radius_factor, bool robustness, int robustness_samples,
          const std::string& robustness_variant, std::size_t robustness_top_k,
          std::optional<std::size_t> robustness_screen,
          std::optional<int> robustness_screen_samples,
          const std::optional<std::string>& robustness_screen_by,
          std::optional<int> robustness_confirm_samples, std::optional<double> robustness_mu,
          bool robust_refine, std::optional<double> robust_refine_below_r, bool centre_candidates,
          std::size_t surface_candidates, bool wrench_volume,
          std::optional<double> torsional_friction, const std::string& contact_patch,
          bool alternative_preshapes) {
  if (planner != "skeleton" && planner != "surface")
    throw InvalidArgument("planner: '" + planner + "' is not skeleton or surface");
  checkTimeout(timeout_s);
  ranking::PlanOptions options;
  options.planner = ranking::parsePlanner(planner);
  grasping::HypothesisParams hypothesis;
  hypothesis.min_epsilon = min_epsilon;
  hypothesis.quality = qualityParams(mu, fc_test, reference_compat, torsional_friction);
  hypothesis.quality.compute_volume = wrench_volume;
  hypothesis.closing.method = grasping::parseClosingMethod(closing);
  hypothesis.closing.contact_patch = grasping::contactPatchFor(contact_patch, reference_compat);
  skeleton::SkeletonParams& skeleton_params = options.skeleton;
  skeleton_params.regularisation.method = geometry::parseRegularisationMethod(regularisation);
  skeleton_params.regularisation.alpha_divisor = alpha_divisor;
  skeleton_params.regularisation.offset_divisor = offset_divisor;
  skeleton_params.spur_radius_factor = spur_radius_factor;
  grasping::SkeletonPlannerParams& p = options.skeleton_planner;
  p.timeout_s = timeout_s;
  p.max_grasps = max_grasps;
  p.seed = seed;
  p.vertex_distance_m = vertex_distance_m;
  p.round_ratio = round_ratio;
  p.centre_candidates = centre_candidates;
  p.surface_candidates = surface_candidates;
  p.alternative_preshapes = alternative_preshapes;
  p.hypothesis = hypothesis;
  grasping::SurfacePlannerParams& q = options.surface_planner;
  q.timeout_s = timeout_s;
  q.max_hypotheses = max_hypotheses;
  q.max_grasps = max_grasps;
  q.seed = seed;
  q.hypothesis = hypothesis;
  // As `skelgrasp plan`: the best grasps scored by r and re-ranked (docs/planning.md).
  options.ranking = robustRankingParams(
      robustness, robustness_samples, robustness_variant, robustness_top_k, robustness_screen,
      robustness_screen_samples, robustness_screen_by, robustness_confirm_samples, robustness_mu,
      seed, robust_refine, robust_refine_below_r);
  Plan out;
  out.hand = hand;
  out.object = mesh.name;
  py::gil_scoped_release release;
  out.result = ranking::planGrasps(mesh.mesh, *hand, options);
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
          "Grasp wrench space volume, or None when not computed (``plan(..., "
          "wrench_volume=True)``).")
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

  const grasping::SkeletonPlannerParams planner;
  const grasping::SurfacePlannerParams surface;
  const skeleton::SkeletonParams skel;
  const ranking::RobustRankingParams ranking;
  m.def("plan", &plan, py::arg("mesh"), py::arg("hand"), py::arg("planner") = "skeleton",
        py::arg("seed") = planner.seed, py::kw_only(), py::arg("timeout_s") = planner.timeout_s,
        py::arg("max_grasps") = planner.max_grasps,
        py::arg("min_epsilon") = planner.hypothesis.min_epsilon,
        py::arg("mu") = planner.hypothesis.quality.friction,
        py::arg("vertex_distance_m") = planner.vertex_distance_m,
        py::arg("round_ratio") = planner.round_ratio,
        py::arg("reference_compat") = planner.hypothesis.quality.reference_compat,
        py::arg("fc_test") = std::string(toString(planner.hypothesis.quality.fc_test)),
        py::arg("closing") = std::string(toString(planner.hypothesis.closing.method)),
        py::arg("max_hypotheses") = surface.max_hypotheses,
        py::arg("regularisation") = std::string(toString(skel.regularisation.method)),
        py::arg("alpha_divisor") = skel.regularisation.alpha_divisor,
        py::arg("offset_divisor") = skel.regularisation.offset_divisor,
        py::arg("spur_radius_factor") = skel.spur_radius_factor,
        py::arg("robustness") = ranking.enabled,
        py::arg("robustness_samples") = ranking.robustness.samples,
        py::arg("robustness_variant") = std::string(ranking::toString(ranking.robustness.variant)),
        py::arg("robustness_top_k") = ranking.top_k,
        py::arg("robustness_screen") = ranking.screen_k,
        py::arg("robustness_screen_samples") = ranking.screen_samples,
        py::arg("robustness_screen_by") = py::none(),
        py::arg("robustness_confirm_samples") = ranking.confirm_samples,
        py::arg("robustness_mu") = ranking.friction,
        py::arg("robust_refine") = ranking.refinement.enabled,
        py::arg("robust_refine_below_r") = ranking.refinement.search_below_r,
        py::arg("centre_candidates") = planner.centre_candidates,
        py::arg("surface_candidates") = planner.surface_candidates,
        py::arg("wrench_volume") = planner.hypothesis.quality.compute_volume,
        py::arg("torsional_friction") = planner.hypothesis.quality.torsional_friction_m,
        py::arg("contact_patch") = std::string(toString(planner.hypothesis.closing.contact_patch)),
        py::arg("alternative_preshapes") = planner.alternative_preshapes,
        R"doc(
Plans grasps for ``mesh`` with ``hand`` (``skelgrasp plan``): planner 'skeleton' (paper Alg. 1)
or 'surface' (surface-normal baseline). Deterministic for a seed. The defaults are the library's
SkeletonPlannerParams / SurfacePlannerParams (no time limit: ``timeout_s=0``; the command line
sets 30 s) and RobustRankingParams. ``max_hypotheses`` is the surface planner's. Robust ranking
(docs/planning.md): ``robustness_screen`` grasps (0: all), each preshape's best by epsilon in turn
(``robustness_screen_by='preshapes'``; 'travel': each preshape's by least finger travel in turn;
'epsilon': the best by epsilon over all) are screened with a
cheap r from ``robustness_screen_samples`` executions each (None, for any of the three: the hand's
ranking budget, 60, 'preshapes' and 10 unless its description says otherwise; the SDH's
'travel'; the Shadow hand's 40, 'epsilon' and 8); the best 2 x ``robustness_top_k`` of those run
``robustness_confirm_samples`` more executions each (None: the hand's, 10 unless its description
says otherwise; the Shadow hand's 0; 0: none) before the best ``robustness_top_k`` of them (0: all)
get a robustness r from
``robustness_samples`` perturbed executions (``robustness_variant`` 'paper', 'guarded', 'settled' or 'reference',
friction ``robustness_mu`` or ``mu``, samples seeded by ``seed``) and are ranked first by r;
``robustness=False`` keeps the epsilon order. ``robust_refine`` searches near the most robust
scored grasps whose r is below ``robust_refine_below_r`` (None: the hand's, 0.7 or the SDH's
and the Shadow hand's 0.5) for more robust poses (docs/ranking.md, "Refinement for robustness"). ``centre_candidates`` (skeleton planner) also tries
power and precision grasps about the object's centre on every object, the robust grasps the
ranking chooses from; ``surface_candidates`` (skeleton planner) adds that many surface-normal hypotheses to the
same pool (0: none; docs/planning.md, "Surface candidates"). ``wrench_volume`` also computes each
grasp's wrench space volume (the whole 6D hull, slower; else ``Grasp.volume`` is None).
``torsional_friction`` (metres) judges contacts as soft fingers (docs/hands.md; None: the hand's
own model, point contacts for the built-in hands), in planning and in r. ``contact_patch``
'corners' lets a link touching over an area push through its patch's corners, 'centre' through its
centre only (the reference's model; implied by ``reference_compat``). ``alternative_preshapes``
(skeleton planner) also closes every pose with the hand's alternative preshapes of its grasp type,
the SDH's 'claw', 'precision_tripod' and (small objects only) 'narrow_tripod' tripods and its
'lateral_power' and 'lateral_precision' grips (docs/hands.md); False or ``reference_compat``:
'power' and 'precision' only. A mesh the skeleton stage cannot process raises ValueError.)doc");

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
