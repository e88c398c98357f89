// skelgrasp bench judge: the old judge (stepwise closing + 6D hull) and the new one (fast closing
// + force-closure LP) side by side in one process, on fixed real grasps (YCB objects), per hand.
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <chrono>
#include <filesystem>
#include <iostream>

#include "cli.h"
#include "mesh_list.h"
#include "option_checks.h"
#include "output_paths.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/grasping/quality/quality.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"
#include "skelgrasp/ranking/robustness.h"

namespace skelgrasp::cli {
namespace {

using grasping::ClosingMethod;
using grasping::ForceClosureTest;

struct BenchJudgeArgs {
  std::string hands = "armar3,sdh,shadow,parallel_gripper";
  std::string objects_dir = "../shared/data/objects/ycb";
  std::string json_out;
  int samples = 100;
  int repeat = 5;
  int threads = 1;
};

// The fixed grasps: a power grasp on the mustard bottle and a precision grasp on the soup can,
// both from the side (-x) at mid-height, backed off until the open hand is clear.
struct FixedGrasp {
  std::string object;
  std::string preshape;
};
const std::vector<FixedGrasp> kFixedGrasps = {{"006_mustard_bottle", "power"},
                                              {"005_tomato_soup_can", "precision"}};

Pose sideGraspPose(grasping::GraspSimulator& sim, const grasping::Preshape& preshape) {
  const auto& box = sim.object().bounds();
  Pose gcp = Pose::Identity();
  gcp.linear() = frameFromZY({-1, 0, 0}, {0, 0, 1});
  for (double d = 0; d < 0.2; d += 0.001) {
    gcp.translation() = box.center() + Eigen::Vector3d(d, 0, 0);
    const Pose hand = sim.handPoseForGcp(gcp, preshape);
    if (!sim.inCollision(hand, preshape.joints)) return hand;
  }
  return sim.handPoseForGcp(gcp, preshape);
}

template <typename F>
double medianSeconds(int repeat, F&& run) {
  std::vector<double> times;
  for (int i = 0; i < repeat; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    run();
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return median(times);
}

struct PathTimes {
  std::vector<double> close_ms, fc_ms, epsilon_ms, robustness_s;
  nlohmann::json medians() const {
    return {{"close_ms", median(close_ms)},
            {"fc_ms", median(fc_ms)},
            {"epsilon_ms", median(epsilon_ms)},
            {"robustness_s", median(robustness_s)}};
  }
};

// One grasp on one path (old: stepwise + hull; new: fast + LP).
void timeGrasp(grasping::GraspSimulator& sim, const grasping::Preshape& preshape,
               const Pose& hand_pose, bool old_path, const BenchJudgeArgs& args, PathTimes& out,
               bool& force_closure, double& score) {
  grasping::ClosingParams closing;
  closing.method = old_path ? ClosingMethod::kStepwise : ClosingMethod::kFast;
  grasping::QualityParams verdict = grasping::withHandContactModel({}, sim.hand());
  verdict.fc_test = old_path ? ForceClosureTest::kHull : ForceClosureTest::kLp;
  verdict.compute_volume = false;
  verdict.compute_epsilon = false;  // kHull builds the hull (and epsilon) anyway
  grasping::QualityParams epsilon = verdict;
  epsilon.compute_epsilon = true;
  grasping::ClosingResult closed;
  out.close_ms.push_back(
      1e3 * medianSeconds(args.repeat, [&] { closed = sim.close(hand_pose, preshape, closing); }));
  grasping::WrenchSpaceResult quality;
  out.fc_ms.push_back(1e3 * medianSeconds(args.repeat, [&] {
                        quality = grasping::evaluateGrasp(closed.contacts, sim.object(), verdict);
                      }));
  force_closure = closed.status.ok() && quality.force_closure;
  out.epsilon_ms.push_back(1e3 * medianSeconds(args.repeat, [&] {
                             grasping::evaluateGrasp(closed.contacts, sim.object(), epsilon);
                           }));
  grasping::Grasp grasp;
  grasp.preshape = preshape.name;
  grasp.hand_pose = hand_pose;
  grasp.joints = closed.joints;
  grasp.contacts = closed.contacts;
  score = 0;
  if (grasp.contacts.empty()) return;  // no robustness for a grasp without contacts
  ranking::RobustnessParams rp;
  rp.samples = args.samples;
  rp.quality = verdict;
  rp.closing = closing;
  ranking::RobustnessResult r;
  out.robustness_s.push_back(
      medianSeconds(1, [&] { r = ranking::evaluateRobustness(sim, grasp, rp); }));
  score = r.score;
}

double ratio(double old_value, double new_value) {
  return new_value > 0 ? old_value / new_value : 0.0;
}

int runBenchJudge(const BenchJudgeArgs& args) {
  checkOutputFileOption(args.json_out);
  setLogLevel(spdlog::level::warn);
  const auto hands = splitList(args.hands);
  if (hands.empty()) return fail("bench judge: --hands: no hand given");
  std::vector<std::unique_ptr<grasping::GraspObject>> objects;
  for (const auto& g : kFixedGrasps) {
    const std::string path = args.objects_dir + "/" + g.object + ".ply";
    if (!std::filesystem::exists(path))
      return fail(path +
                  ": not found (bench judge needs the YCB google_16k meshes; --objects DIR)");
    objects.push_back(std::make_unique<grasping::GraspObject>(loadMesh(path)));
  }
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, args.threads);
  std::cout << fmt::format("{:<17} {:>4} {:>9} {:>9} {:>9} {:>9} {:>10} {:>10} {:>7}\n", "hand",
                           "path", "close_ms", "fc_ms", "eps_ms", "close+fc", "robust_s",
                           "grasps/s", "r");
  nlohmann::json out_hands = nlohmann::json::object();
  for (const auto& hand_name : hands) {
    const auto hand = grasping::resolveHand(hand_name);
    PathTimes old_times, new_times;
    std::vector<double> old_scores, new_scores;
    for (std::size_t i = 0; i < kFixedGrasps.size(); ++i) {
      if (!hand.preshapes().count(kFixedGrasps[i].preshape)) continue;
      const auto& preshape = hand.preshape(kFixedGrasps[i].preshape);
      grasping::GraspSimulator sim(hand, *objects[i]);
      const Pose pose = sideGraspPose(sim, preshape);
      bool fc_old = false, fc_new = false;
      double r_old = 0, r_new = 0;
      timeGrasp(sim, preshape, pose, true, args, old_times, fc_old, r_old);
      timeGrasp(sim, preshape, pose, false, args, new_times, fc_new, r_new);
      old_scores.push_back(r_old);
      new_scores.push_back(r_new);
      if (fc_old != fc_new) {
        spdlog::warn("bench judge: {} {} on {}: the paths disagree on force closure", hand_name,
                     preshape.name, kFixedGrasps[i].object);
      }
    }
    const auto o = old_times.medians(), n = new_times.medians();
    const auto row = [&](const char* path, const nlohmann::json& m, double r) {
      const double judge_ms = m["close_ms"].get<double>() + m["fc_ms"].get<double>();
      std::cout << fmt::format(
          "{:<17} {:>4} {:>9.3f} {:>9.3f} {:>9.3f} {:>9.3f} {:>10.4f} {:>10.1f} {:>7.2f}\n",
          hand_name, path, m["close_ms"].get<double>(), m["fc_ms"].get<double>(),
          m["epsilon_ms"].get<double>(), judge_ms, m["robustness_s"].get<double>(),
          ratio(1.0, m["robustness_s"].get<double>()), r);
    };
    row("old", o, median(old_scores));
    row("new", n, median(new_scores));
    std::cout << fmt::format(
        "{:<17} {:>4} {:>8.1f}x {:>8.1f}x {:>8.1f}x {:>9} {:>9.1f}x\n", hand_name, "gain",
        ratio(o["close_ms"].get<double>(), n["close_ms"].get<double>()),
        ratio(o["fc_ms"].get<double>(), n["fc_ms"].get<double>()),
        ratio(o["epsilon_ms"].get<double>(), n["epsilon_ms"].get<double>()), "",
        ratio(o["robustness_s"].get<double>(), n["robustness_s"].get<double>()));
    out_hands[hand_name] = {{"old", o}, {"new", n}};
  }
  std::cout << fmt::format(
      "medians over the fixed grasps (power: mustard bottle, precision: soup can), {} robustness "
      "samples, {} thread(s); grasps/s = robustness scores per second\n",
      args.samples, args.threads);
  if (!args.json_out.empty())
    writeJsonFile(args.json_out, {{"hands", out_hands}, {"threads", args.threads}});
  return kExitOk;
}

}  // namespace

void registerBenchJudgeCommand(CLI::App& app, Action& action) {
  CLI::App* bench = app.get_subcommand("bench");  // created by registerBenchCommand
  auto* cmd = bench->add_subcommand(
      "judge",
      "Old judge (stepwise closing + hull) against the new one (fast closing + LP) per hand");
  auto args = std::make_shared<BenchJudgeArgs>();
  cmd->add_option("--hands", args->hands, "Comma-separated built-in hands")->capture_default_str();
  cmd->add_option("--objects", args->objects_dir,
                  "Directory with the YCB google_16k meshes (006_mustard_bottle.ply, "
                  "005_tomato_soup_can.ply)")
      ->capture_default_str();
  cmd->add_option("--samples", args->samples, "Robustness samples per grasp")
      ->transform(countIn(1, kMaxCount))
      ->capture_default_str();
  cmd->add_option("--repeat", args->repeat, "Timed runs of close and the tests; the median counts")
      ->transform(countIn(1, kMaxRepeat))
      ->capture_default_str();
  cmd->add_option("--threads", args->threads, "Threads for the robustness samples")
      ->transform(threadCount(1))
      ->capture_default_str();
  cmd->add_option("--json", args->json_out, "Also write the medians as JSON");
  cmd->callback([=, &action] { action = [=] { return runBenchJudge(*args); }; });
}

}  // namespace skelgrasp::cli
