// Hands, the planners, closing a hand at a pose, re-scoring grasps and pictures.
#include <pybind11/stl.h>

#include <optional>

#include "bindings.h"
#include "convert.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/evaluation/robust_ranking.h"
#include "skelgrasp/evaluation/robustness.h"
#include "skelgrasp/evaluation/score.h"
#include "skelgrasp/grasping/hand_render.h"
#include "skelgrasp/grasping/plan_output.h"
#include "skelgrasp/grasping/planners.h"
#include "skelgrasp/skeleton/output.h"

namespace skelgrasp::python {
namespace {

struct Plan {
  grasping::PlanResult result;
  HandPtr hand;
  std::string object;
  std::optional<SkeletonOutput> skeleton;
};

// A hand closed at a pose (``skelgrasp close --json``).
struct Closing {
  HandPtr hand;
  std::string preshape;
  Pose gcp_pose, hand_pose;
  grasping::ClosingResult closing;
  grasping::WrenchSpaceResult quality;

  // The CLI's close --json document; joints and contacts through the grasp writer.
  nlohmann::json json() const {
    grasping::Grasp g;
    g.joints = closing.joints;
    g.contacts = closing.contacts;
    const nlohmann::json written = grasping::graspToJson(g, *hand);
    return nlohmann::json{{"hand", hand->name()},
                          {"preshape", preshape},
                          {"gcp_pose", poseToJson(gcp_pose)},
                          {"hand_pose", poseToJson(hand_pose)},
                          {"status", closing.status.ok() ? "closed" : closing.reason},
                          {"message", closing.status.message},
                          {"colliding_link", closing.colliding_link},
                          {"joints", written["joints"]},
                          {"contacts", written["contacts"]},
                          {"force_closure", quality.force_closure},
                          {"epsilon", quality.epsilon},
                          {"closure_margin", quality.closure_margin},
                          {"volume", numberOrNull(quality.volume)},
                          {"hull_facets", quality.hull_facets}};
  }
};

py::list contactsList(const std::vector<grasping::Contact>& contacts) {
  py::list out;
  for (const auto& c : contacts) {
    py::dict d;
    d["point"] = fromPoints({c.point}).attr("reshape")(3);
    d["normal"] = fromPoints({c.normal}).attr("reshape")(3);
    d["link"] = c.link;
    d["palm"] = c.palm;
    out.append(d);
  }
  return out;
}

HandPtr builtinOrUrdf(const std::string& name) {
  py::gil_scoped_release release;
  return std::make_shared<grasping::HandModel>(grasping::resolveHand(name));
}

HandPtr handFromFiles(const std::string& urdf, const std::string& description) {
  py::gil_scoped_release release;
  return std::make_shared<grasping::HandModel>(grasping::loadHand(urdf, description));
}

grasping::QualityParams qualityParams(double mu, const std::string& fc_test,
                                      bool reference_compat) {
  grasping::QualityParams q;
  q.friction = mu;
  q.fc_test = grasping::parseForceClosureTest(fc_test);
  q.reference_compat = reference_compat;
  return q;
}

Plan plan(const Mesh& mesh, const HandPtr& hand, const std::string& planner, std::uint64_t seed,
          double timeout_s, std::size_t max_grasps, double min_epsilon, double mu,
          double vertex_distance_m, std::optional<double> round_ratio, bool reference_compat,
          const std::string& fc_test, const std::string& closing, std::size_t max_hypotheses,
          const std::string& regularisation, double alpha_divisor, double offset_divisor,
          double spur_radius_factor, bool robustness, int robustness_samples,
          const std::string& robustness_variant, std::size_t robustness_top_k,
          std::size_t robustness_screen, std::optional<double> robustness_mu, bool robust_refine,
          bool centre_candidates, std::size_t surface_candidates, bool wrench_volume) {
  if (planner != "skeleton" && planner != "surface")
    throw InvalidArgument("planner: '" + planner + "' is not skeleton or surface");
  grasping::HypothesisParams hypothesis;
  hypothesis.min_epsilon = min_epsilon;
  hypothesis.quality = qualityParams(mu, fc_test, reference_compat);
  hypothesis.quality.compute_volume = wrench_volume;
  hypothesis.closing.method = grasping::parseClosingMethod(closing);
  skeleton::SkeletonParams skeleton_params;
  skeleton_params.regularisation.method = geometry::parseRegularisationMethod(regularisation);
  skeleton_params.regularisation.alpha_divisor = alpha_divisor;
  skeleton_params.regularisation.offset_divisor = offset_divisor;
  skeleton_params.spur_radius_factor = spur_radius_factor;

  const auto ranking =
      robustRankingParams(robustness, robustness_samples, robustness_variant, robustness_top_k,
                          robustness_screen, robustness_mu, seed, robust_refine);
  Plan out{{}, hand, mesh.name, std::nullopt};
  py::gil_scoped_release release;
  const grasping::GraspObject object(mesh.mesh);
  if (planner == "skeleton") {
    out.skeleton = SkeletonOutput{skeleton::extractSkeleton(mesh.mesh, skeleton_params), mesh};
    // As the CLI: a mesh the skeleton stage cannot process is bad input.
    if (!out.skeleton->result.status.ok())
      throw InvalidArgument(mesh.name + ": " + out.skeleton->result.status.message);
    grasping::SkeletonPlannerParams p;
    p.timeout_s = timeout_s;
    p.max_grasps = max_grasps;
    p.seed = seed;
    p.vertex_distance_m = vertex_distance_m;
    p.round_ratio = round_ratio;
    p.centre_candidates = centre_candidates;
    p.surface_candidates = surface_candidates;
    p.hypothesis = hypothesis;
    out.result = grasping::planSkeletonGrasps(*hand, object, out.skeleton->result.skeleton, p);
  } else {
    grasping::SurfacePlannerParams p;
    p.timeout_s = timeout_s;
    p.max_hypotheses = max_hypotheses;
    p.max_grasps = max_grasps;
    p.seed = seed;
    p.hypothesis = hypothesis;
    out.result = grasping::planSurfaceGrasps(*hand, object, p);
  }
  // As `skelgrasp plan`: the best grasps scored by r and re-ranked (docs/planning.md).
  out.result.grasps =
      evaluation::rankByRobustness(*hand, object, std::move(out.result.grasps), hypothesis, ranking)
          .grasps;
  return out;
}

Closing closeHand(const Mesh& mesh, const HandPtr& hand, const std::string& preshape_name,
                  const py::object& gcp_pose, double mu, const std::string& fc_test,
                  const std::string& closing, bool reference_compat) {
  Closing out;
  out.hand = hand;
  out.gcp_pose = toPose(gcp_pose, "gcp_pose");
  const auto& preshape = hand->preshape(preshape_name);
  out.preshape = preshape.name;
  grasping::ClosingParams closing_params;
  closing_params.method = grasping::parseClosingMethod(closing);
  auto quality = qualityParams(mu, fc_test, reference_compat);
  quality.torsional_friction_m = hand->closingDefaults().torsional_friction_m;
  quality.compute_volume = true;  // one grasp: the whole hull is cheap
  py::gil_scoped_release release;
  const grasping::GraspObject object(mesh.mesh);
  grasping::GraspSimulator simulator(*hand, object);
  out.hand_pose = simulator.handPoseForGcp(out.gcp_pose, preshape);
  out.closing = simulator.close(out.hand_pose, preshape, closing_params);
  if (out.closing.status.ok())
    out.quality = grasping::evaluateGrasp(out.closing.contacts, object, quality);
  return out;
}

std::vector<Grasp> graspsOf(const py::object& grasps) {
  if (py::isinstance<Grasp>(grasps)) return {grasps.cast<Grasp>()};
  if (py::isinstance<Plan>(grasps)) {
    const auto& p = grasps.cast<const Plan&>();
    std::vector<Grasp> out;
    for (const auto& g : p.result.grasps) out.push_back({g, p.hand});
    return out;
  }
  try {
    return grasps.cast<std::vector<Grasp>>();
  } catch (const py::cast_error&) {
    throw InvalidArgument("grasps: expected a Grasp, a list of Grasps or a plan result");
  }
}

py::list score(const Mesh& mesh, const HandPtr& hand, const py::object& grasps, double mu,
               const std::string& fc_test, bool reference_compat, int robustness_samples,
               const std::string& robustness_variant, std::uint64_t seed) {
  const std::vector<Grasp> list = graspsOf(grasps);
  auto quality = qualityParams(mu, fc_test, reference_compat);
  quality.torsional_friction_m = hand->closingDefaults().torsional_friction_m;
  if (robustness_samples < 0) throw InvalidArgument("robustness_samples: must be >= 0");
  evaluation::RobustnessParams robustness;
  robustness.samples = robustness_samples;
  robustness.variant = evaluation::parseRobustnessVariant(robustness_variant);
  robustness.seed = seed;
  robustness.quality = quality;
  std::vector<grasping::WrenchSpaceResult> judged(list.size());
  std::vector<std::optional<evaluation::RobustnessResult>> robust(list.size());
  {
    py::gil_scoped_release release;
    const grasping::GraspObject object(mesh.mesh);
    grasping::GraspSimulator simulator(*hand, object);
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (list[i].hand->name() != hand->name())
        throw InvalidArgument("grasps: grasp " + std::to_string(i) + " was planned for hand '" +
                              list[i].hand->name() + "', not '" + hand->name() + "'");
      judged[i] = grasping::evaluateGrasp(list[i].grasp.contacts, object, quality);
      // grasp_index 0 for every grasp: the common random numbers plan's ranking and `skelgrasp
      // score` use (robust_ranking.h), so plan's r is reproduced for the same seed and samples.
      if (robustness_samples > 0)
        robust[i] = evaluation::evaluateRobustness(simulator, list[i].grasp, robustness, 0);
    }
  }
  py::list out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    py::dict d;
    d["force_closure"] = judged[i].force_closure;
    d["epsilon"] = judged[i].epsilon;
    d["closure_margin"] = judged[i].closure_margin;
    d["volume"] = py::cast(judged[i].volume);  // None when not computed
    if (robust[i]) {
      d["robustness"] = robust[i]->score;
      d["robustness_interval"] = py::make_tuple(robust[i]->wilson_low, robust[i]->wilson_high);
      d["robustness_samples"] = robust[i]->samples;
      d["robustness_collisions"] = robust[i]->collisions;
      d["robustness_closing_failures"] = robust[i]->closing_failures;
      d["robustness_no_force_closure"] = robust[i]->no_force_closure;
    } else {
      d["robustness"] = py::none();
    }
    out.append(d);
  }
  return out;
}

// `skelgrasp score` on a grasps.json given as a path or as the parsed document (a dict).
py::object scoreGraspsFile(const Mesh& mesh, const HandPtr& hand, const py::object& grasps,
                           const std::vector<double>& mu, int robustness_samples,
                           const std::string& robustness_variant, std::uint64_t seed,
                           const std::string& closing, const std::optional<long long>& object) {
  nlohmann::json file;
  std::string source = "grasps";
  if (py::isinstance<py::str>(grasps)) {
    source = grasps.cast<std::string>();
    file = readJsonFile(source);
  } else {
    const std::string text = py::module_::import("json").attr("dumps")(grasps).cast<std::string>();
    file = nlohmann::json::parse(text);
  }
  evaluation::ScoreParams params;
  params.frictions = mu;
  params.compute_robustness = robustness_samples > 0;
  if (robustness_samples < 0) throw InvalidArgument("robustness_samples: must be >= 0");
  if (params.compute_robustness) params.robustness.samples = robustness_samples;
  params.robustness.variant = evaluation::parseRobustnessVariant(robustness_variant);
  params.robustness.seed = seed;
  params.closing.method = grasping::parseClosingMethod(closing);
  const auto placements = grasping::readGraspPlacements(file, *hand, object);
  nlohmann::json out;
  {
    py::gil_scoped_release release;
    const grasping::GraspObject target(mesh.mesh);
    const auto result = evaluation::scoreGrasps(*hand, target, placements, params);
    out = evaluation::scoreToJson(result, params, *hand, mesh.name, source);
  }
  return fromJson(out);
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
          "search_samples, r_before, preshape_before, moves} where refinement for robustness "
          "searched near it.")
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
          [](const Plan& p) { return fromJson(grasping::planToJson(p.result, *p.hand, p.object)); },
          "grasps.json as ``skelgrasp plan`` writes it (schema skelgrasp.grasps/3).")
      .def("__len__", [](const Plan& p) { return p.result.grasps.size(); })
      .def("__repr__", [](const Plan& p) {
        return "<skelgrasp.PlanResult: " +
               grasping::planSummaryLine(p.result, p.hand->name(), p.object) + ">";
      });

  const grasping::SkeletonPlannerParams planner;
  const grasping::SurfacePlannerParams surface;
  const skeleton::SkeletonParams skel;
  const evaluation::RobustRankingParams ranking;
  m.def(
      "plan", &plan, py::arg("mesh"), py::arg("hand"), py::arg("planner") = "skeleton",
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
      py::arg("robustness_variant") = std::string(evaluation::toString(ranking.robustness.variant)),
      py::arg("robustness_top_k") = ranking.top_k, py::arg("robustness_screen") = ranking.screen_k,
      py::arg("robustness_mu") = ranking.friction,
      py::arg("robust_refine") = ranking.refinement.enabled,
      py::arg("centre_candidates") = planner.centre_candidates,
      py::arg("surface_candidates") = planner.surface_candidates,
      py::arg("wrench_volume") = planner.hypothesis.quality.compute_volume,
      R"doc(
Plans grasps for ``mesh`` with ``hand`` (``skelgrasp plan``): planner 'skeleton' (paper Alg. 1)
or 'surface' (surface-normal baseline). Deterministic for a seed. The defaults are the library's
SkeletonPlannerParams / SurfacePlannerParams (no time limit: ``timeout_s=0``; the command line
sets 30 s) and RobustRankingParams. ``max_hypotheses`` is the surface planner's. Robust ranking
(docs/planning.md): the best ``robustness_screen`` grasps by epsilon (0: all) are screened with a
cheap r, and the best ``robustness_top_k`` of them (0: all) get a robustness r from
``robustness_samples`` perturbed executions (``robustness_variant`` 'paper', 'guarded' or 'reference',
friction ``robustness_mu`` or ``mu``, samples seeded by ``seed``) and are ranked first by r;
``robustness=False`` keeps the epsilon order. ``robust_refine`` searches near the most robust
scored grasps for more robust poses (docs/planning.md, "Refinement for robustness"). ``centre_candidates`` (skeleton planner) also tries
power grasps about the object's centre on every object, the robust grasps the ranking chooses
from; ``surface_candidates`` (skeleton planner) adds that many surface-normal hypotheses to the
same pool (0: none; docs/planning.md, "Surface candidates"). ``wrench_volume`` also computes each
grasp's wrench space volume (the whole 6D hull, slower; else ``Grasp.volume`` is None). A mesh the skeleton stage cannot process raises ValueError.)doc");

  py::class_<Closing>(m, "CloseResult", "A hand closed at a pose, from :func:`close`.")
      .def_property_readonly(
          "closed", [](const Closing& c) { return c.closing.status.ok(); },
          "True when the fingers closed on the object with enough contacts.")
      .def_property_readonly(
          "status",
          [](const Closing& c) { return c.closing.status.ok() ? "closed" : c.closing.reason; },
          "'closed', 'start_collision' or 'too_few_contacts'.")
      .def_property_readonly(
          "hand_pose", [](const Closing& c) { return fromPose(c.hand_pose); },
          "4 x 4 hand root pose that puts the preshape's grasp centre point at gcp_pose.")
      .def_property_readonly(
          "gcp_pose", [](const Closing& c) { return fromPose(c.gcp_pose); }, "4 x 4 pose given.")
      .def_property_readonly(
          "joints", [](const Closing& c) { return jointsDict(*c.hand, c.closing.joints); },
          "{joint name: value} reached.")
      .def_property_readonly(
          "contacts", [](const Closing& c) { return contactsList(c.closing.contacts); },
          "List of {point, normal, link, palm}.")
      .def_property_readonly(
          "force_closure", [](const Closing& c) { return c.quality.force_closure; },
          "Force closure of the contacts.")
      .def_property_readonly(
          "epsilon", [](const Closing& c) { return c.quality.epsilon; }, "Ferrari-Canny epsilon.")
      .def(
          "to_dict", [](const Closing& c) { return fromJson(c.json()); },
          "The document of ``skelgrasp close --json``.");

  const grasping::QualityParams quality;
  m.def("close", &closeHand, py::arg("mesh"), py::arg("hand"), py::arg("preshape"),
        py::arg("gcp_pose"), py::kw_only(), py::arg("mu") = quality.friction,
        py::arg("fc_test") = std::string(toString(quality.fc_test)),
        py::arg("closing") = std::string(toString(grasping::ClosingParams{}.method)),
        py::arg("reference_compat") = quality.reference_compat, R"doc(
Closes ``hand`` in ``preshape`` with its grasp centre point at ``gcp_pose`` (4 x 4, or x y z qw qx
qy qz; object frame) and judges the contacts (``skelgrasp close``). Raises ValueError for an
unknown preshape or a pose that is not a rigid transform.)doc");

  const evaluation::RobustnessParams robustness;
  m.def("score", &score, py::arg("mesh"), py::arg("hand"), py::arg("grasps"), py::kw_only(),
        py::arg("mu") = quality.friction,
        py::arg("fc_test") = std::string(toString(quality.fc_test)),
        py::arg("reference_compat") = quality.reference_compat,
        py::arg("robustness_samples") = robustness.samples,
        py::arg("robustness_variant") = std::string(evaluation::toString(robustness.variant)),
        py::arg("seed") = robustness.seed, R"doc(
Re-scores grasps (a Grasp, a list of them or a PlanResult) planned with ``hand`` on ``mesh``:
force closure, epsilon, closure margin and volume of their contacts with these quality
parameters, and the robustness r (paper Sec. V-B: the share of ``robustness_samples`` perturbed
hand poses that still close to force closure, with its 95 % Wilson interval; 0 samples skips
it). Every grasp faces the same perturbations (as in :func:`plan`'s ranking), so a planned grasp's
r is reproduced with plan's seed and sample count. Returns one dict per grasp.)doc");

  const evaluation::ScoreParams score_params;
  m.def("score_grasps", &scoreGraspsFile, py::arg("mesh"), py::arg("hand"), py::arg("grasps"),
        py::kw_only(), py::arg("mu") = score_params.frictions,
        py::arg("robustness_samples") = robustness.samples,
        py::arg("robustness_variant") = std::string(evaluation::toString(robustness.variant)),
        py::arg("seed") = robustness.seed,
        py::arg("closing") = std::string(toString(score_params.closing.method)),
        py::arg("object") = py::none(), R"doc(
``skelgrasp score``: re-scores the grasps of a grasps.json (a path, or the parsed dict; schema
skelgrasp.grasps/N or skelgrasp.run/N, ``object`` selecting one object of a run file) by placing
``hand`` at each grasp's hand_pose, closing it on ``mesh`` and judging the contacts at every
friction in ``mu``: force closure, LP margin, epsilon and robustness r with its 95 % Wilson
interval (0 samples skips it). Returns the skelgrasp.score/1 document (docs/evaluation.md).)doc");

  m.def(
      "render_plan",
      [](const std::string& path, const Plan& p, const Mesh& mesh) {
        py::gil_scoped_release release;
        grasping::renderPlanPng(path, mesh.mesh,
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
        grasping::renderGraspPng(path, mesh.mesh, *g.hand, g.grasp.hand_pose, preshape.joints,
                                 g.grasp.joints, g.grasp.contacts);
      },
      py::arg("path"), py::arg("grasp"), py::arg("mesh"),
      "PNG of the object with the hand in its preshape and closed, from two sides.");
}

}  // namespace skelgrasp::python
