#include "skelgrasp/evaluation/batch.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <numeric>
#include <random>

#include "batch_store.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/grasping/planners.h"

namespace skelgrasp::evaluation {
namespace {

// Stable across builds and platforms (std::hash is not).
std::uint64_t fnv1a(const std::string& text, std::uint64_t seed) {
  std::uint64_t h = 1469598103934665603ULL ^ seed;
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ULL;
  return h;
}

struct ObjectOutcome {
  std::vector<nlohmann::json> runs, results;
  std::size_t failed = 0;
};

nlohmann::json runRecord(const std::string& object, const std::string& hand,
                         const std::string& planner) {
  return {{"object", object}, {"hand", hand}, {"planner", planner}};
}

class ObjectEvaluator {
 public:
  ObjectEvaluator(const BatchParams& p, const std::vector<grasping::HandModel>& hands)
      : p_(p), hands_(hands) {}

  ObjectOutcome evaluate(const std::string& path) const {
    ObjectOutcome out;
    const std::string name = std::filesystem::path(path).filename().string();
    auto failAll = [&](const std::string& error, const std::string& only_planner) {
      for (const auto& hand : hands_) {
        for (const auto& planner : p_.planners) {
          if (!only_planner.empty() && planner != only_planner) continue;
          auto r = runRecord(name, hand.name(), planner);
          r["status"] = "error";
          r["error"] = error;
          out.runs.push_back(r);
          ++out.failed;
        }
      }
    };
    std::unique_ptr<grasping::GraspObject> object;
    TriangleMesh mesh;
    try {
      mesh = loadMesh(path, p_.load);
      object = std::make_unique<grasping::GraspObject>(mesh);
    } catch (const std::exception& e) {
      log().warn("evaluate: {}", e.what());
      failAll(e.what(), "");
      return out;
    }
    const bool want_skeleton = std::count(p_.planners.begin(), p_.planners.end(), "skeleton") > 0;
    std::optional<skeleton::SkeletonResult> skel;
    if (want_skeleton) {
      skel = skeleton::extractSkeleton(mesh, p_.skeleton);
      if (!skel->status.ok()) {
        failAll(path + ": " + skel->status.message, "skeleton");
        skel.reset();
      }
    }
    for (const auto& hand : hands_) {
      std::size_t skeleton_poses = 0;
      for (const auto& planner : p_.planners) {
        if (planner == "skeleton" && !skel) continue;  // recorded as failed above
        const std::uint64_t seed = fnv1a(name + "|" + hand.name() + "|" + planner, p_.seed);
        grasping::PlanResult plan;
        grasping::HypothesisParams hypothesis;
        hypothesis.quality = p_.quality;
        if (planner == "skeleton") {
          grasping::SkeletonPlannerParams sp;
          sp.timeout_s = p_.timeout_s;
          sp.seed = seed;
          sp.vertex_distance_m = p_.vertex_distance_m;
          sp.hypothesis = hypothesis;
          plan = grasping::planSkeletonGrasps(hand, *object, skel->skeleton, sp);
          skeleton_poses = plan.summary.poses;
        } else {
          grasping::SurfacePlannerParams fp;
          fp.timeout_s = p_.timeout_s;
          fp.seed = seed;
          fp.max_hypotheses = skeleton_poses > 0 ? skeleton_poses : p_.surface_hypotheses;
          fp.hypothesis = hypothesis;
          plan = grasping::planSurfaceGrasps(hand, *object, fp);
        }
        record(name, hand, planner, seed, *object, plan,
               skel && planner == "skeleton" ? &*skel : nullptr, out);
      }
    }
    return out;
  }

 private:
  void record(const std::string& name, const grasping::HandModel& hand, const std::string& planner,
              std::uint64_t seed, const grasping::GraspObject& object,
              const grasping::PlanResult& plan, const skeleton::SkeletonResult* skel,
              ObjectOutcome& out) const {
    // Robustness of a seeded sample of the kept grasps.
    std::vector<std::size_t> chosen(plan.grasps.size());
    std::iota(chosen.begin(), chosen.end(), 0);
    std::shuffle(chosen.begin(), chosen.end(), std::mt19937_64(seed));
    if (p_.robustness_grasps > 0 && chosen.size() > p_.robustness_grasps)
      chosen.resize(p_.robustness_grasps);
    std::sort(chosen.begin(), chosen.end());
    grasping::GraspSimulator simulator(hand, object);
    RobustnessParams rp = p_.robustness;
    rp.quality = p_.quality;
    rp.quality.torsional_friction_m = hand.closingDefaults().torsional_friction_m;
    rp.seed = seed;
    std::map<std::size_t, RobustnessResult> robustness;
    double robustness_s = 0, robustness_sum = 0;
    for (std::size_t index : chosen) {
      robustness[index] = evaluateRobustness(simulator, plan.grasps[index], rp, index);
      robustness_s += robustness[index].time_s;
      robustness_sum += robustness[index].score;
    }
    const auto& s = plan.summary;
    auto run = runRecord(name, hand.name(), planner);
    run["status"] = plan.grasps.empty() ? "no_grasp" : "ok";
    run["error"] = "";
    run["seed"] = seed;
    run["hypotheses"] = s.hypotheses;
    run["poses"] = s.poses;
    run["generated"] = s.generated;
    run["force_closure"] = s.force_closure;
    run["force_closure_rate"] = s.forceClosureRate();
    run["kept"] = plan.grasps.size();
    run["power"] = s.power;
    run["precision"] = s.precision;
    run["rejections"] = s.rejections;
    run["timed_out"] = s.timed_out;
    run["planning_s"] = s.planning_s;
    run["ms_per_valid_grasp"] =
        s.force_closure ? nlohmann::json(s.msPerValidGrasp()) : nlohmann::json(nullptr);
    run["regularise_s"] = skel ? skel->timing.regularise_s : 0.0;
    run["skeleton_s"] = skel ? skel->timing.skeleton_s : 0.0;
    run["robustness_grasps"] = chosen.size();
    run["robustness_samples"] = rp.samples;
    run["robustness_s"] = robustness_s;
    run["robustness_mean"] =
        chosen.empty() ? nlohmann::json(nullptr) : nlohmann::json(robustness_sum / chosen.size());
    out.runs.push_back(run);
    for (std::size_t i = 0; i < plan.grasps.size(); ++i) {
      const auto& g = plan.grasps[i];
      auto r = runRecord(name, hand.name(), planner);
      r["grasp"] = g.id;
      r["type"] = grasping::toString(g.type);
      r["strategy"] = g.strategy;
      r["epsilon"] = g.epsilon;
      r["volume"] = g.volume;
      r["time_ms"] = s.msPerValidGrasp();
      const auto it = robustness.find(i);
      r["robustness"] =
          it != robustness.end() ? nlohmann::json(it->second.score) : nlohmann::json(nullptr);
      r["robustness_low"] =
          it != robustness.end() ? nlohmann::json(it->second.wilson_low) : nlohmann::json(nullptr);
      r["robustness_high"] =
          it != robustness.end() ? nlohmann::json(it->second.wilson_high) : nlohmann::json(nullptr);
      r["robustness_collisions"] =
          it != robustness.end() ? nlohmann::json(it->second.collisions) : nlohmann::json(nullptr);
      out.results.push_back(r);
    }
  }

  const BatchParams& p_;
  const std::vector<grasping::HandModel>& hands_;
};

}  // namespace

BatchStats runBatch(const BatchParams& p) {
  if (p.shard_count < 1 || p.shard_index < 0 || p.shard_index >= p.shard_count) {
    throw InvalidArgument("shard " + std::to_string(p.shard_index) + "/" +
                          std::to_string(p.shard_count) +
                          " out of range (use i/n with 0 <= i < n)");
  }
  if (p.jobs < 1) throw InvalidArgument("jobs must be at least 1");
  if (p.objects.empty()) throw InvalidArgument("no objects to evaluate");
  for (const auto& planner : p.planners) {
    if (planner != "skeleton" && planner != "surface") {
      throw InvalidArgument("unknown planner '" + planner + "' (use skeleton, surface)");
    }
  }
  std::vector<grasping::HandModel> hands;
  for (const auto& name : p.hands) hands.push_back(grasping::resolveHand(name));
  std::filesystem::create_directories(p.out_dir);
  Stopwatch watch;
  internal::BatchStore store(p.out_dir);

  BatchStats stats;
  std::vector<std::string> todo;
  for (std::size_t k = 0; k < p.objects.size(); ++k) {
    if (static_cast<int>(k % p.shard_count) != p.shard_index) continue;
    ++stats.objects_total;
    const std::string name = std::filesystem::path(p.objects[k]).filename().string();
    bool done = true;
    for (const auto& hand : hands) {
      for (const auto& planner : p.planners) {
        done = done && store.hasRun(name + "|" + hand.name() + "|" + planner);
      }
    }
    if (done) {
      ++stats.objects_skipped;
    } else {
      todo.push_back(p.objects[k]);
    }
  }
  if (p.max_objects > 0 && todo.size() > p.max_objects) todo.resize(p.max_objects);
  log().info("evaluate: {} object(s) in shard {}/{}, {} already done, {} to run with {} job(s)",
             stats.objects_total, p.shard_index, p.shard_count, stats.objects_skipped, todo.size(),
             p.jobs);

  const ObjectEvaluator evaluator(p, hands);
  ProgressReporter progress("evaluate objects", todo.size(), 10.0);
  std::atomic<std::size_t> finished{0}, failed{0};
  tbb::task_arena arena(p.jobs);
  arena.execute([&] {
    tbb::parallel_for(std::size_t(0), todo.size(), std::size_t(1), [&](std::size_t i) {
      ObjectOutcome outcome = evaluator.evaluate(todo[i]);
      store.add(outcome.runs, outcome.results);
      failed += outcome.failed;
      progress.step(++finished);
    });
  });
  stats.objects_run = finished;
  stats.runs_failed = failed;
  stats.time_s = watch.seconds();
  writeSummary(p.out_dir);
  return stats;
}

}  // namespace skelgrasp::evaluation
