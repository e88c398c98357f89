// Closing a hand at a pose and re-scoring grasps: close(), score() and score_grasps().
#include <pybind11/stl.h>

#include <optional>

#include "bindings.h"
#include "convert.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/evaluation/score.h"
#include "skelgrasp/grasping/io/grasps_file.h"
#include "skelgrasp/grasping/io/plan_output.h"
#include "skelgrasp/grasping/quality/quality.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"
#include "skelgrasp/ranking/robustness.h"

namespace skelgrasp::python {
namespace {

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

Closing closeHand(const Mesh& mesh, const HandPtr& hand, const std::string& preshape_name,
                  const py::object& gcp_pose, double mu, const std::string& fc_test,
                  const std::string& closing, bool reference_compat,
                  std::optional<double> torsional_friction, const std::string& contact_patch) {
  Closing out;
  out.hand = hand;
  out.gcp_pose = toPose(gcp_pose, "gcp_pose");
  const auto& preshape = hand->preshape(preshape_name);
  out.preshape = preshape.name;
  grasping::ClosingParams closing_params;
  closing_params.method = grasping::parseClosingMethod(closing);
  closing_params.contact_patch = grasping::contactPatchFor(contact_patch, reference_compat);
  auto quality = grasping::withHandContactModel(
      qualityParams(mu, fc_test, reference_compat, torsional_friction), *hand);
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
               const std::string& robustness_variant, std::uint64_t seed,
               std::optional<double> torsional_friction, const std::string& contact_patch,
               bool load_check) {
  const std::vector<Grasp> list = graspsOf(grasps);
  const auto quality = grasping::withHandContactModel(
      qualityParams(mu, fc_test, reference_compat, torsional_friction), *hand);
  checkSamples("robustness_samples", robustness_samples, 0);
  ranking::RobustnessParams robustness;
  robustness.samples = robustness_samples;
  robustness.variant = ranking::parseRobustnessVariant(robustness_variant);
  robustness.seed = seed;
  ranking::setLoadCheck(robustness, load_check);
  robustness.quality = quality;
  robustness.closing.contact_patch = grasping::contactPatchFor(contact_patch, reference_compat);
  std::vector<grasping::WrenchSpaceResult> judged(list.size());
  std::vector<std::optional<ranking::RobustnessResult>> robust(list.size());
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
        robust[i] = ranking::evaluateRobustness(simulator, list[i].grasp, robustness, 0);
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
      d["robustness_guarded_holds"] = robust[i]->guarded_holds;
      d["robustness_closing_failures"] = robust[i]->closing_failures;
      d["robustness_no_force_closure"] = robust[i]->no_force_closure;
      d["robustness_too_weak"] = robust[i]->too_weak;
      d["robustness_settled_holds"] = robust[i]->settled_holds;
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
                           const std::string& closing, const std::optional<long long>& object,
                           std::optional<double> torsional_friction,
                           const std::string& contact_patch, bool load_check) {
  nlohmann::json file;
  std::string source = "grasps";
  if (py::isinstance<py::str>(grasps)) {
    source = grasps.cast<std::string>();
    file = readJsonFile(source);
  } else {
    // allow_nan=False: NaN or infinity would be written as a bare NaN that no JSON parser reads
    // (nlohmann's raw parse error reached the caller as RuntimeError).
    std::string text;
    try {
      text = py::module_::import("json")
                 .attr("dumps")(grasps, py::arg("allow_nan") = false)
                 .cast<std::string>();
    } catch (py::error_already_set& e) {
      if (!e.matches(PyExc_ValueError)) throw;
      throw InvalidArgument("grasps: a number is not finite (NaN or infinity)");
    }
    file = nlohmann::json::parse(text);
  }
  evaluation::ScoreParams params;
  params.frictions = mu;
  params.compute_robustness = robustness_samples > 0;
  checkSamples("robustness_samples", robustness_samples, 0);
  if (params.compute_robustness) params.robustness.samples = robustness_samples;
  params.robustness.variant = ranking::parseRobustnessVariant(robustness_variant);
  params.robustness.seed = seed;
  ranking::setLoadCheck(params.robustness, load_check);
  params.closing.method = grasping::parseClosingMethod(closing);
  params.closing.contact_patch = grasping::parseContactPatch(contact_patch);
  checkTorsionalFriction(torsional_friction);
  params.quality.torsional_friction_m = torsional_friction;
  std::vector<grasping::GraspPlacement> placements;
  try {
    placements = grasping::readGraspPlacements(file, *hand, object);
    evaluation::checkScoreWork(placements.size(), params);  // before any closing
  } catch (const InvalidArgument& e) {
    // As `skelgrasp score`: a file's problems name the file.
    if (py::isinstance<py::str>(grasps)) throw IoError(source, e.what());
    throw;
  }
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

void bindScoring(py::module_& m) {
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
        py::arg("reference_compat") = quality.reference_compat,
        py::arg("torsional_friction") = quality.torsional_friction_m,
        py::arg("contact_patch") = std::string(toString(grasping::ClosingParams{}.contact_patch)),
        R"doc(
Closes ``hand`` in ``preshape`` with its grasp centre point at ``gcp_pose`` (4 x 4, or x y z qw qx
qy qz; object frame) and judges the contacts (``skelgrasp close``); ``torsional_friction``
(metres) judges them as soft fingers (None: the hand's model); ``contact_patch`` 'corners' or
'centre' says where a link touching over an area pushes (docs/hands.md, "Contacts"; 'centre' with
``reference_compat``). Raises ValueError for an unknown
preshape or a pose that is not a rigid transform.)doc");

  const ranking::RobustnessParams robustness;
  m.def("score", &score, py::arg("mesh"), py::arg("hand"), py::arg("grasps"), py::kw_only(),
        py::arg("mu") = quality.friction,
        py::arg("fc_test") = std::string(toString(quality.fc_test)),
        py::arg("reference_compat") = quality.reference_compat,
        py::arg("robustness_samples") = robustness.samples,
        py::arg("robustness_variant") = std::string(ranking::toString(robustness.variant)),
        py::arg("seed") = robustness.seed,
        py::arg("torsional_friction") = quality.torsional_friction_m,
        py::arg("contact_patch") = std::string(toString(grasping::ClosingParams{}.contact_patch)),
        py::arg("load_check") = true,
        R"doc(
Re-scores grasps (a Grasp, a list of them or a PlanResult) planned with ``hand`` on ``mesh``:
force closure, epsilon, closure margin and volume of their contacts with these quality
parameters, and the robustness r (paper Sec. V-B: the share of ``robustness_samples`` perturbed
hand poses that still close to force closure, with its 95 % Wilson interval; 0 samples skips
it). Every grasp faces the same perturbations (as in :func:`plan`'s ranking), so a planned grasp's
r is reproduced with plan's seed and sample count (and its ``torsional_friction``: soft-finger
contacts, None for the hand's model; and its ``contact_patch``). ``load_check`` (as plan's r): a
sample holds only when its contacts also carry the object's 0.1 kg weight in every direction
within half the fingers' torque limits (docs/ranking.md, "Load check"; never for the 'paper' and
'reference' variants). Returns one dict per grasp.)doc");

  const evaluation::ScoreParams score_params;
  m.def("score_grasps", &scoreGraspsFile, py::arg("mesh"), py::arg("hand"), py::arg("grasps"),
        py::kw_only(), py::arg("mu") = score_params.frictions,
        py::arg("robustness_samples") = robustness.samples,
        py::arg("robustness_variant") = std::string(ranking::toString(robustness.variant)),
        py::arg("seed") = robustness.seed,
        py::arg("closing") = std::string(toString(score_params.closing.method)),
        py::arg("object") = py::none(),
        py::arg("torsional_friction") = score_params.quality.torsional_friction_m,
        py::arg("contact_patch") = std::string(toString(score_params.closing.contact_patch)),
        py::arg("load_check") = true,
        R"doc(
``skelgrasp score``: re-scores the grasps of a grasps.json (a path, or the parsed dict; schema
skelgrasp.grasps/N or skelgrasp.run/N, ``object`` selecting one object of a run file) by placing
``hand`` at each grasp's hand_pose, closing it on ``mesh`` and judging the contacts at every
friction in ``mu``: force closure, LP margin, epsilon and robustness r with its 95 % Wilson
interval (0 samples skips it); ``torsional_friction`` (metres) judges soft-finger contacts (None:
the hand's model); ``contact_patch`` says where a link touching over an area pushes;
``load_check`` as in :func:`score`. Returns the skelgrasp.score/1 document (docs/evaluation.md).)doc");
}

}  // namespace skelgrasp::python
