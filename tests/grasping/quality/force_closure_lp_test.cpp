// Force closure by the min-weight LP (GLPK) against the 6D hull (Qhull): the same verdict on
// random, analytic and real-grasp contact sets, except inside the documented tolerance band.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <thread>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/common/pose.h"
#include "skelgrasp/grasping/quality/quality.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"
#include "test_support.h"

namespace skelgrasp::grasping {
namespace {

// A disagreement is explained by rounding when the winning side is this close to the boundary:
// n l* (LP says closure, hull does not) or the hull's epsilon (hull says closure, LP does not).
constexpr double kBoundaryBand = 1e-8;
// Two joggled hulls (Qhull's QJ) of the same wrenches give epsilons this close (wrench units).
constexpr double kJoggledEpsilonTolerance = 1e-7;

Contact contact(const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
  Contact c;
  c.point = p;
  c.normal = n.normalized();
  return c;
}

struct ContactSet {
  std::vector<Contact> contacts;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double torque_scale = 1;
  QualityParams params;
  std::string kind;  // how a random set was made, for the disagreement listing
};

// Runs both tests on contact sets and keeps the counts and the disagreements.
struct Agreement {
  int sets = 0, closures = 0, disagreements = 0, outside_band = 0;
  double smallest_closure_margin = std::numeric_limits<double>::infinity();  // n l*
  double largest_open_margin = 0;  // n l* of feasible LPs that are not closure
  std::vector<std::string> examples;

  void compare(const ContactSet& set, const std::string& label) {
    QualityParams hull_params = set.params, lp_params = set.params;
    hull_params.fc_test = ForceClosureTest::kHull;
    hull_params.compute_volume = false;
    lp_params.fc_test = ForceClosureTest::kLp;
    lp_params.compute_epsilon = false;  // the verdict only (epsilon: LpOnlyMode... test)
    const auto hull = evaluateWrenchSpace(set.contacts, set.center, set.torque_scale, hull_params);
    const auto lp = evaluateWrenchSpace(set.contacts, set.center, set.torque_scale, lp_params);
    ++sets;
    closures += lp.force_closure;
    EXPECT_TRUE(std::isnan(hull.closure_margin)) << label;
    EXPECT_EQ(lp.closure_margin > 0, lp.force_closure) << label;
    const double n = lp.wrenches;
    if (lp.force_closure) {
      smallest_closure_margin = std::min(smallest_closure_margin, n * lp.closure_margin);
    } else if (lp.rank == 6) {
      std::vector<Wrench> wrenches =
          contactWrenches(set.contacts, set.center, set.torque_scale, set.params);
      const auto raw = solveClosureLp(wrenches);
      if (raw.feasible) largest_open_margin = std::max(largest_open_margin, n * raw.margin);
    }
    if (lp.force_closure == hull.force_closure) return;
    ++disagreements;
    const bool in_band =
        lp.force_closure ? n * lp.closure_margin <= kBoundaryBand : hull.epsilon <= kBoundaryBand;
    outside_band += !in_band;
    if (examples.size() < 20) {
      const auto raw =
          solveClosureLp(contactWrenches(set.contacts, set.center, set.torque_scale, set.params));
      char line[320];
      std::snprintf(line, sizeof line, "%s: LP %s (%s, n l* %.3g), hull %s (eps %.3g)%s",
                    label.c_str(), lp.force_closure ? "yes" : "no",
                    raw.feasible ? "feasible" : "infeasible", n * raw.margin,
                    hull.force_closure ? "yes" : "no", hull.epsilon, in_band ? "" : " OUTSIDE");
      examples.emplace_back(line);
    }
  }

  void report(const char* what) const {
    std::printf(
        "%s: %d sets, %d closures, %d disagreements (%d outside the band); smallest closure "
        "n l* %.3g, largest non-closure feasible n l* %.3g\n",
        what, sets, closures, disagreements, outside_band, smallest_closure_margin,
        largest_open_margin);
    for (const auto& e : examples) std::printf("  %s\n", e.c_str());
  }
};

Eigen::Vector3d randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> gauss(0, 1);
  Eigen::Vector3d v;
  do {
    v = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
  } while (v.norm() < 1e-6);
  return v.normalized();
}

// 2..10 contacts on a sphere or a box, normals the surface's plus noise of a random size (up to
// uniformly random directions), random mu, cone edges and contact model. Wrenches kept <= 48 so
// the hull stays affordable (10,000 hulls).
ContactSet randomSet(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0, 1);
  ContactSet set;
  const bool soft = unit(rng) < 0.25;
  const int contacts = 2 + static_cast<int>(unit(rng) * (soft ? 5 : 9));
  set.params.friction = 0.1 + 0.9 * unit(rng);
  const int edge_choices[] = {4, 6, 8};
  set.params.cone_edges = edge_choices[static_cast<int>(unit(rng) * 3)];
  while (contacts * set.params.cone_edges * (soft ? 2 : 1) > 48) set.params.cone_edges -= 2;
  set.params.torsional_friction_m = soft ? 0.002 + 0.01 * unit(rng) : 0;
  const double size = 0.02 + 0.1 * unit(rng);
  const bool sphere = unit(rng) < 0.5;
  const double noise_choices[] = {0, 0.2, 0.6, 3.0};
  const double noise = noise_choices[static_cast<int>(unit(rng) * 4)];
  const Eigen::Vector3d half = size * Eigen::Vector3d(0.5 + unit(rng), 0.5 + unit(rng), 1);
  for (int i = 0; i < contacts; ++i) {
    Eigen::Vector3d p, n;
    if (sphere) {
      n = randomUnit(rng);
      p = size * n;
    } else {
      const int axis = static_cast<int>(unit(rng) * 3);
      const double sign = unit(rng) < 0.5 ? -1 : 1;
      p = Eigen::Vector3d((2 * unit(rng) - 1) * half.x(), (2 * unit(rng) - 1) * half.y(),
                          (2 * unit(rng) - 1) * half.z());
      p[axis] = sign * half[axis];
      n = Eigen::Vector3d::Zero();
      n[axis] = sign;
    }
    set.contacts.push_back(contact(p, n + noise * randomUnit(rng)));
  }
  set.center = 0.2 * size * randomUnit(rng);
  set.kind = std::string(sphere ? "sphere" : "box") + (soft ? " soft" : "") + " noise " +
             std::to_string(noise).substr(0, 3) + " contacts " + std::to_string(contacts);
  set.torque_scale = 1 / size;
  return set;
}

TEST(ForceClosureLp, AgreesWithTheHullOnRandomContactSets) {
  std::mt19937_64 rng(20240615);
  Agreement agreement;
  for (int i = 0; i < 10000; ++i) {
    const ContactSet set = randomSet(rng);
    agreement.compare(set, "random " + std::to_string(i) + " (" + set.kind + ")");
  }
  agreement.report("random");
  EXPECT_EQ(agreement.outside_band, 0);
  EXPECT_GT(agreement.closures, 1000);  // both verdicts well represented
  EXPECT_GT(agreement.sets - agreement.closures, 1000);
}

// Two soft-finger contacts on the x axis whose normals lean by `lean` in the xy plane: their
// line lies in the discretised cone (an edge lies in that plane) iff lean < atan(mu).
ContactSet leaningPair(double lean, double torsion_m) {
  ContactSet set;
  const double d = 0.03;
  set.contacts = {contact({d, 0, 0}, {std::cos(lean), std::sin(lean), 0}),
                  contact({-d, 0, 0}, {-std::cos(lean), -std::sin(lean), 0})};
  set.torque_scale = 1 / d;
  set.params.torsional_friction_m = torsion_m;
  return set;
}

TEST(ForceClosureLp, AgreesWithTheHullOnAnalyticContactSets) {
  Agreement agreement;
  const double cone = std::atan(QualityParams{}.friction);
  for (double offset : {-1e-3, -1e-6, 0.0, 1e-6, 1e-3}) {
    const std::string tag = "lean atan(mu)" + std::to_string(offset);
    // Point contacts: never 6D closure (no torque about their line).
    const auto point = evaluateWrenchSpace(leaningPair(cone + offset, 0).contacts,
                                           Eigen::Vector3d::Zero(), 1 / 0.03);
    EXPECT_FALSE(point.force_closure) << tag;
    agreement.compare(leaningPair(cone + offset, 0), tag + " point");
    const ContactSet soft = leaningPair(cone + offset, 0.003);
    agreement.compare(soft, tag + " soft");
    if (offset != 0) {
      EXPECT_EQ(evaluateWrenchSpace(soft.contacts, soft.center, soft.torque_scale, soft.params)
                    .force_closure,
                offset < 0)
          << tag;
    }
  }
  // Coplanar: k contacts around a circle with in-plane normals (closure from 3 on), and the same
  // points all pushing from one side of their plane (never).
  for (int k = 2; k <= 8; ++k) {
    for (double mu : {0.1, 0.35, 1.0}) {
      ContactSet ring, face;
      ring.torque_scale = face.torque_scale = 1 / 0.03;
      ring.params.friction = face.params.friction = mu;
      for (int i = 0; i < k; ++i) {
        const double a = 2 * kPi * i / k;
        const Eigen::Vector3d radial(std::cos(a), std::sin(a), 0);
        ring.contacts.push_back(contact(0.03 * radial, radial));
        face.contacts.push_back(contact(0.03 * radial, {0, 0, 1}));
      }
      agreement.compare(ring, "ring " + std::to_string(k));
      agreement.compare(face, "face " + std::to_string(k));
      EXPECT_FALSE(evaluateWrenchSpace(face.contacts, face.center, face.torque_scale, face.params)
                       .force_closure);
    }
  }
  // Two point contacts anywhere: rank <= 5, never closure.
  std::mt19937_64 rng(7);
  for (int i = 0; i < 200; ++i) {
    ContactSet pair;
    pair.contacts = {contact(0.03 * randomUnit(rng), randomUnit(rng)),
                     contact(0.03 * randomUnit(rng), randomUnit(rng))};
    pair.torque_scale = 1 / 0.03;
    const auto r = evaluateWrenchSpace(pair.contacts, pair.center, pair.torque_scale);
    EXPECT_FALSE(r.force_closure);
    EXPECT_LE(r.rank, 5);
    agreement.compare(pair, "random point pair " + std::to_string(i));
  }
  agreement.report("analytic");
  EXPECT_EQ(agreement.outside_band, 0);
}

// Poses sampled on the surface (as the surface planner), backed off until the open hand is free,
// closed; every closing with contacts is compared.
void compareRealGrasps(const HandModel& hand, const GraspObject& object, std::uint64_t seed,
                       Agreement& agreement) {
  GraspSimulator simulator(hand, object);
  const auto& mesh = object.mesh();
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick_face(0, mesh.numFaces() - 1);
  std::uniform_real_distribution<double> unit(0, 1);
  QualityParams params;
  params.torsional_friction_m = hand.closingDefaults().torsional_friction_m;
  for (const auto& [name, preshape] : hand.preshapes()) {
    for (int k = 0; k < 12; ++k) {
      const std::size_t face = pick_face(rng);
      const Eigen::Vector3d normal = object.faceNormal(face);
      if (normal.isZero()) continue;
      const auto& t = mesh.faces[face];
      const Eigen::Vector3d point =
          (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3;
      const double roll = 2 * kPi * unit(rng);
      const Eigen::Vector3d u = anyPerpendicular(normal), w = normal.cross(u);
      Pose gcp = Pose::Identity();
      gcp.linear() = frameFromZY(-normal, std::cos(roll) * u + std::sin(roll) * w);
      Pose hand_pose = Pose::Identity();
      bool free = false;
      for (double retreat = 0; retreat < 0.15 && !free; retreat += 0.002) {
        gcp.translation() = point + retreat * normal;
        hand_pose = simulator.handPoseForGcp(gcp, preshape);
        free = !simulator.inCollision(hand_pose, preshape.joints);
      }
      if (!free) continue;
      const auto closing = simulator.close(hand_pose, preshape);
      if (closing.contacts.empty()) continue;
      ContactSet set;
      set.contacts = closing.contacts;
      set.center = object.centerOfMass();
      set.torque_scale = torqueScaleMaxRadius(object);
      set.params = params;
      agreement.compare(set, hand.name() + " " + name + " " + std::to_string(k));
    }
  }
}

TEST(ForceClosureLp, AgreesWithTheHullOnRealGraspsOfTheFourHands) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  setLogLevel(spdlog::level::warn);
  const std::vector<std::string> objects = {"006_mustard_bottle", "003_cracker_box", "011_banana",
                                            "025_mug", "005_tomato_soup_can"};
  std::vector<std::unique_ptr<GraspObject>> meshes;  // not movable
  for (const auto& name : objects) {
    const std::string path = test::sharedDataDir() + "/objects/ycb/" + name + ".ply";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not found";
    meshes.push_back(std::make_unique<GraspObject>(loadMesh(path)));
  }
  Agreement total;
  for (const auto& hand_name : builtinHandNames()) {
    const HandModel hand = loadBuiltinHand(hand_name);
    Agreement agreement;
    for (std::size_t i = 0; i < meshes.size(); ++i)
      compareRealGrasps(hand, *meshes[i], i, agreement);
    agreement.report(hand_name.c_str());
    EXPECT_GT(agreement.sets, 20) << hand_name;
    total.sets += agreement.sets;
    total.closures += agreement.closures;
    total.outside_band += agreement.outside_band;
  }
  EXPECT_EQ(total.outside_band, 0);
  EXPECT_GT(total.closures, 10);
}

TEST(ForceClosureLp, MarginIsInvariantToContactOrderAndTorqueScale) {
  std::mt19937_64 rng(99);
  int closures = 0;
  for (int i = 0; i < 500; ++i) {
    ContactSet set = randomSet(rng);
    set.params.compute_epsilon = false;  // the margin only
    const auto base = evaluateWrenchSpace(set.contacts, set.center, set.torque_scale, set.params);
    std::vector<Contact> shuffled = set.contacts;
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    const auto permuted = evaluateWrenchSpace(shuffled, set.center, set.torque_scale, set.params);
    EXPECT_EQ(permuted.force_closure, base.force_closure) << i;
    EXPECT_NEAR(permuted.closure_margin, base.closure_margin, 1e-9 / base.wrenches) << i;
    closures += base.force_closure;
    // Any invertible linear map of wrench space keeps l*: torque scale (a centre shift moves the
    // discretised cones' first edges, so it is not compared here).
    const auto rescaled =
        evaluateWrenchSpace(set.contacts, set.center, 3 * set.torque_scale, set.params);
    EXPECT_NEAR(rescaled.closure_margin, base.closure_margin, 1e-9 / base.wrenches) << i;
  }
  EXPECT_GT(closures, 50);
}

// kLp with epsilon: the hull only for closure sets, and then the same epsilon and volume as kHull;
// without the volume, epsilon by expansion (hulls of subsets) agrees with the whole hull's.
TEST(ForceClosureLp, LpOnlyModeRunsNoHullAndKeepsTheVerdict) {
  std::mt19937_64 rng(5);
  int compared = 0;
  for (int i = 0; i < 300; ++i) {
    ContactSet set = randomSet(rng);
    set.params.compute_volume = true;
    const auto full = evaluateWrenchSpace(set.contacts, set.center, set.torque_scale, set.params);
    QualityParams hull_params = set.params;
    hull_params.fc_test = ForceClosureTest::kHull;
    const auto hull = evaluateWrenchSpace(set.contacts, set.center, set.torque_scale, hull_params);
    QualityParams expansion_params = set.params;
    expansion_params.compute_volume = false;
    const auto expansion =
        evaluateWrenchSpace(set.contacts, set.center, set.torque_scale, expansion_params);
    EXPECT_EQ(expansion.force_closure, full.force_closure) << i;
    EXPECT_FALSE(expansion.volume.has_value()) << i;
    if (full.force_closure && hull.force_closure) {
      EXPECT_EQ(full.epsilon, hull.epsilon) << i;
      EXPECT_EQ(full.volume, hull.volume) << i;
      EXPECT_EQ(full.hull_facets, hull.hull_facets) << i;
      // Both hulls are joggled (QJ), by up to ~1e-9 of the wrenches' size.
      EXPECT_NEAR(expansion.epsilon, full.epsilon, kJoggledEpsilonTolerance) << i;
      EXPECT_GT(expansion.hull_facets, 0) << i;
      ++compared;
    }
    QualityParams verdict_only = set.params;
    verdict_only.compute_epsilon = false;
    const auto quick =
        evaluateWrenchSpace(set.contacts, set.center, set.torque_scale, verdict_only);
    EXPECT_EQ(quick.force_closure, full.force_closure);
    EXPECT_EQ(quick.closure_margin, full.closure_margin);
    EXPECT_EQ(quick.hull_facets, 0);  // no hull built
    EXPECT_EQ(quick.epsilon, 0.0);
    if (full.force_closure) {
      EXPECT_GT(full.hull_facets, 0);
    }
  }
  EXPECT_GT(compared, 50);
}

TEST(ForceClosureLp, GivesTheSameMarginsFromSeveralThreads) {
  std::mt19937_64 rng(11);
  std::vector<std::vector<Wrench>> sets;
  for (int i = 0; i < 200; ++i) {
    const ContactSet s = randomSet(rng);
    sets.push_back(contactWrenches(s.contacts, s.center, s.torque_scale, s.params));
  }
  std::vector<double> serial;
  for (const auto& w : sets) serial.push_back(solveClosureLp(w).margin);
  std::vector<std::vector<double>> parallel(4, std::vector<double>(sets.size()));
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (std::size_t i = 0; i < sets.size(); ++i) parallel[t][i] = solveClosureLp(sets[i]).margin;
    });
  }
  for (auto& thread : threads) thread.join();
  for (int t = 0; t < 4; ++t) EXPECT_EQ(parallel[t], serial) << "thread " << t;
}

TEST(ForceClosureLp, RejectsEmptyAndNonFiniteWrenches) {
  EXPECT_THROW(solveClosureLp({}), InvalidArgument);
  Wrench bad = Wrench::Zero();
  bad[2] = std::nan("");
  EXPECT_THROW(solveClosureLp({bad}), InvalidArgument);
  EXPECT_EQ(parseForceClosureTest("lp"), ForceClosureTest::kLp);
  EXPECT_EQ(parseForceClosureTest("hull"), ForceClosureTest::kHull);
  EXPECT_THROW(parseForceClosureTest("qhull"), InvalidArgument);
  EXPECT_STREQ(toString(QualityParams{}.fc_test), "lp");
}

}  // namespace
}  // namespace skelgrasp::grasping
