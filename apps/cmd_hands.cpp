// skelgrasp hands: the built-in hands.
// skelgrasp close MESH --hand H --preshape P --pose "...": closes a hand on a mesh and scores it.
// skelgrasp quality CONTACTS.json: scores a given contact set.
#include <fmt/format.h>

#include <iostream>
#include <optional>

#include "cli.h"
#include "hand_options.h"
#include "option_checks.h"
#include "output_paths.h"
#include "quality_options.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/common/pose.h"
#include "skelgrasp/grasping/io/contacts_io.h"
#include "skelgrasp/grasping/quality/quality.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"
#include "skelgrasp/presentation/hand_render.h"
#include "skelgrasp/ranking/robust_ranking.h"

namespace skelgrasp::cli {
namespace {

nlohmann::json contactsToJson(const std::vector<grasping::Contact>& contacts) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& c : contacts) {
    out.push_back({{"point", toJson(c.point)},
                   {"normal", toJson(c.normal)},
                   {"link", c.link},
                   {"palm", c.palm}});
  }
  return out;
}

// The contact model the hand's grasps are judged with unless --torsional-friction says otherwise.
std::string contactModel(const grasping::HandModel& hand) {
  const double torsion_m = hand.closingDefaults().torsional_friction_m;
  return torsion_m > 0 ? fmt::format("soft {:.1f} mm", 1000 * torsion_m) : std::string("point");
}

// How a hand's screening takes its candidates, said only where it is not each preshape's best by
// epsilon in turn (the default).
const char* screenOrderSuffix(ranking::ScreenCandidates candidates) {
  switch (candidates) {
    case ranking::ScreenCandidates::kPreshapesInTurn:
      return "";
    case ranking::ScreenCandidates::kByPreScore:
      return " by eps";
    case ranking::ScreenCandidates::kPreshapesInTurnByTravel:
      return " by travel";
  }
  return "";
}

// The robust ranking's budget for the hand unless options say otherwise: candidates screened x
// samples each, and the r below which scored grasps are searched.
std::string rankingBudget(const grasping::HandModel& hand) {
  const auto used = ranking::rankingBudgetFor({}, hand.rankingBudget());
  return fmt::format(
      "{}x{}{}{}, r<{:g}", used.screen_k, used.screen_samples,
      used.confirm_samples > 0 ? fmt::format("+{}", used.confirm_samples) : std::string(),
      screenOrderSuffix(used.screen_candidates), used.search_below_r);
}

int runHands() {
  std::cout << fmt::format("{:<18} {:>7} {:>6} {:>7}  {:<13}  {:<26}  {}\n", "hand", "fingers",
                           "DOF", "joints", "contacts", "ranking", "preshapes");
  for (const auto& name : grasping::builtinHandNames()) {
    const auto hand = grasping::loadBuiltinHand(name);
    std::string preshapes;
    for (const auto& [p, preshape] : hand.preshapes()) {
      preshapes += (preshapes.empty() ? "" : ", ") + p;
      // A preshape for small objects says how small (Preshape::max_object_length_m).
      if (preshape.max_object_length_m)
        preshapes += fmt::format(" (<= {:g} mm)", 1000 * *preshape.max_object_length_m);
    }
    std::cout << fmt::format("{:<18} {:>7} {:>6} {:>7}  {:<13}  {:<26}  {}   ({})\n", name,
                             hand.fingers().size(), hand.numDrives(), hand.numMovingJoints(),
                             contactModel(hand), rankingBudget(hand), preshapes, hand.title());
  }
  std::cout << "DOF = actuated drives while closing; joints = joints those drives move; contacts = "
               "point, or soft fingers with their torsional friction (--torsional-friction); "
               "ranking = the robust ranking's budget: candidates screened x samples each "
               "(+N: the contenders' confirmation samples; each preshape's best by epsilon in "
               "turn, \"by eps\": the best by epsilon over all, \"by travel\": each "
               "preshape's by least finger travel in turn), and the r below which scored "
               "grasps are searched for a more robust pose (--robustness-screen, "
               "--robustness-screen-samples, --robustness-confirm-samples, "
               "--robustness-screen-by, --robust-refine-below-r); "
               "preshapes = those of the grasp description, with the largest object a preshape "
               "for small objects is closed on\n";
  return kExitOk;
}

struct CloseArgs {
  std::string mesh;
  std::string preshape = "power";
  std::string pose;
  std::string units = "auto";
  std::string render;
  double mu = grasping::QualityParams{}.friction;
  bool json = false;
  bool reference_compat = false;
  std::string fc_test = defaultForceClosureTest();
  std::string closing = defaultClosingMethod();
  std::string contact_patch = defaultContactPatch();
  std::optional<double> torsional_friction_m;  // unset: the hand's contact model
  HandOptions hand;
};

int runClose(const CloseArgs& args) {
  checkOutputFileOption(args.render);
  Pose gcp;
  try {
    gcp = parsePose(args.pose);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(std::string("--pose: ") + e.what());
  }
  const auto hand = args.hand.load();
  const auto& preshape = hand.preshape(args.preshape);
  MeshLoadOptions load;
  load.units = parseLengthUnit(args.units);
  const grasping::GraspObject object(loadMesh(args.mesh, load));
  grasping::GraspSimulator simulator(hand, object);
  const Pose hand_pose = simulator.handPoseForGcp(gcp, preshape);
  grasping::ClosingParams closing_params;
  closing_params.method = grasping::parseClosingMethod(args.closing);
  closing_params.contact_patch =
      grasping::contactPatchFor(args.contact_patch, args.reference_compat);
  const auto closing = simulator.close(hand_pose, preshape, closing_params);
  grasping::QualityParams quality_params;
  quality_params.friction = args.mu;
  quality_params.reference_compat = args.reference_compat;
  quality_params.fc_test = grasping::parseForceClosureTest(args.fc_test);
  quality_params.torsional_friction_m = args.torsional_friction_m;
  quality_params = grasping::withHandContactModel(quality_params, hand);
  quality_params.compute_volume = true;  // one grasp: the whole hull is cheap
  const auto quality = closing.status.ok()
                           ? grasping::evaluateGrasp(closing.contacts, object, quality_params)
                           : grasping::WrenchSpaceResult{};
  nlohmann::json joints;
  for (std::size_t j = 0; j < hand.joints().size(); ++j) {
    if (hand.joints()[j].movable())
      joints[hand.joints()[j].name] = closing.joints[static_cast<Eigen::Index>(j)];
  }
  const nlohmann::json out = {{"hand", hand.name()},
                              {"preshape", preshape.name},
                              {"gcp_pose", poseToJson(gcp)},
                              {"hand_pose", poseToJson(hand_pose)},
                              {"status", closing.status.ok() ? "closed" : closing.reason},
                              {"message", closing.status.message},
                              {"colliding_link", closing.colliding_link},
                              {"joints", joints},
                              {"contacts", contactsToJson(closing.contacts)},
                              {"force_closure", quality.force_closure},
                              {"epsilon", quality.epsilon},
                              {"closure_margin", quality.closure_margin},
                              {"volume", numberOrNull(quality.volume)},
                              {"hull_facets", quality.hull_facets}};
  if (!args.render.empty()) {
    presentation::renderGraspPng(args.render, object.mesh(), hand, hand_pose, preshape.joints,
                                 closing.joints, closing.contacts);
  }
  if (args.json) {
    std::cout << out.dump(2) << std::endl;
    return kExitOk;
  }
  if (!closing.status.ok()) {
    std::cout << fmt::format(
        "{} {}: not closed: {} ({}{})\n", hand.name(), preshape.name, closing.reason,
        closing.status.message,
        closing.colliding_link.empty() ? "" : ", link " + closing.colliding_link);
    return kExitOk;
  }
  std::cout << "joints reached:";
  for (const auto& [name, value] : joints.items())
    std::cout << fmt::format(" {}={:.3f}", name, value.get<double>());
  std::cout << "\n" << closing.contacts.size() << " contacts:\n";
  for (const auto& c : closing.contacts) {
    std::cout << fmt::format(
        "  {:<18} point [{:.4f} {:.4f} {:.4f}] normal [{:.3f} {:.3f} {:.3f}]{}\n", c.link,
        c.point.x(), c.point.y(), c.point.z(), c.normal.x(), c.normal.y(), c.normal.z(),
        c.palm ? " (palm)" : "");
  }
  std::cout << fmt::format("force closure: {}, epsilon {:.5f}, volume {:.3g}, {} hull facets\n",
                           quality.force_closure ? "yes" : "no", quality.epsilon,
                           quality.volume.value_or(0.0), quality.hull_facets);
  return kExitOk;
}

struct QualityArgs {
  std::string path;
  double mu = grasping::QualityParams{}.friction;
  int edges = grasping::QualityParams{}.cone_edges;
  std::optional<double> torsion_m;  // unset: point contacts (contact sets carry no hand)
  bool json = false;
  bool reference_compat = false;
  std::string fc_test = defaultForceClosureTest();
};

int runQuality(const QualityArgs& args) {
  const grasping::ContactSet set = grasping::readContactsFile(args.path);
  const auto& contacts = set.contacts;
  const Eigen::Vector3d& center = set.center;
  const double torque_scale = set.torque_scale;
  grasping::QualityParams params;
  params.friction = args.mu;
  params.cone_edges = args.edges;
  params.torsional_friction_m = args.torsion_m;
  params.reference_compat = args.reference_compat;
  params.fc_test = grasping::parseForceClosureTest(args.fc_test);
  params.compute_volume = true;  // one contact set: the whole hull is cheap
  const auto q = grasping::evaluateWrenchSpace(contacts, center, torque_scale, params);
  if (args.json) {
    std::cout << nlohmann::json({{"force_closure", q.force_closure},
                                 {"epsilon", q.epsilon},
                                 {"closure_margin", q.closure_margin},
                                 {"volume", numberOrNull(q.volume)},
                                 {"hull_facets", q.hull_facets},
                                 {"wrenches", q.wrenches},
                                 {"rank", q.rank},
                                 {"torque_scale", torque_scale},
                                 {"center", toJson(center)},
                                 {"note", q.note}})
                     .dump(2)
              << std::endl;
  } else {
    std::cout << fmt::format("force closure: {}, epsilon {:.6f}, volume {:.6g}, {} hull facets{}\n",
                             q.force_closure ? "yes" : "no", q.epsilon, q.volume.value_or(0.0),
                             q.hull_facets, q.note.empty() ? "" : " (" + q.note + ")");
  }
  return kExitOk;
}

}  // namespace

void registerHandCommands(CLI::App& app, Action& action) {
  auto* hands = app.add_subcommand("hands", "List the built-in hands");
  hands->callback([&action] { action = [] { return runHands(); }; });

  auto* close =
      app.add_subcommand("close", "Close a hand on a mesh at a given pose and score the grasp");
  auto c = std::make_shared<CloseArgs>();
  close->add_option("MESH", c->mesh, "Object mesh (object frame, metres)")->required();
  c->hand.addTo(*close);
  close->add_option("--preshape", c->preshape, "Preshape name (power, precision, ...)")
      ->capture_default_str();
  close
      ->add_option("--pose", c->pose,
                   "Grasp centre point pose in the object frame, metres: \"x y z qw qx qy qz\" "
                   "(unit quaternion) or 16 numbers of a row-major 4x4 matrix; |position| <= " +
                       fmt::format("{:g}", kMaxPoseDistanceM) + " m")
      ->required();
  close->add_option("--units", c->units, "Mesh length unit: auto, m or mm")->capture_default_str();
  close->add_option("--mu", c->mu, "Friction coefficient")
      ->check(finiteIn(0, kMaxFriction))
      ->capture_default_str();
  close->add_flag("--reference-compat", c->reference_compat,
                  "Quality as the reference code (fact sheet §9)");
  addForceClosureTestOption(*close, c->fc_test);
  addTorsionalFrictionOption(*close, c->torsional_friction_m);
  addClosingMethodOption(*close, c->closing);
  addContactPatchOption(*close, c->contact_patch);
  close->add_flag("--json", c->json, "Print JSON");
  close->add_option("--render", c->render, "Render object and hand (preshape, closed) to this PNG");
  close->callback([c, &action] { action = [c] { return runClose(*c); }; });

  auto* quality =
      app.add_subcommand("quality", "Force closure, epsilon and volume of a contact set");
  auto q = std::make_shared<QualityArgs>();
  quality
      ->add_option("CONTACTS", q->path,
                   "JSON: {\"contacts\": [{\"point\", \"normal\"}], \"center\", \"torque_scale\"}")
      ->required();
  quality->add_option("--mu", q->mu, "Friction coefficient")
      ->check(finiteIn(0, kMaxFriction))
      ->capture_default_str();
  quality->add_option("--cone-edges", q->edges, "Edges per friction cone")
      ->transform(countIn(3, 64))
      ->capture_default_str();
  quality
      ->add_option("--torsional-friction", q->torsion_m,
                   "Soft-finger contacts: torsional friction length in metres (default: point "
                   "contacts)")
      ->check(lengthOrZero());
  quality->add_flag("--reference-compat", q->reference_compat,
                    "Reproduce the reference code's quirks");
  addForceClosureTestOption(*quality, q->fc_test);
  quality->add_flag("--json", q->json, "Print JSON");
  quality->callback([q, &action] { action = [q] { return runQuality(*q); }; });
}

}  // namespace skelgrasp::cli
