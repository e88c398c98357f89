#include "skelgrasp/evaluation/batch.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <optional>
#include <random>
#include <set>

#include "batch_physics.h"
#include "batch_setup.h"
#include "batch_store.h"
#include "skelgrasp/common/directory_lock.h"
#include "skelgrasp/common/logging.h"

namespace skelgrasp::evaluation {
namespace {

using internal::GraspRecord;
using internal::ObjectIdentity;
using internal::RunRecord;
using internal::RunStatus;

struct ObjectOutcome {
  std::vector<RunRecord> runs;
  std::vector<GraspRecord> results;
  std::size_t failed = 0;
};

// A run record of `object` with its key and content hash filled in.
RunRecord runRecord(const ObjectIdentity& object, const std::string& hand,
                    ranking::Planner planner) {
  RunRecord run;
  run.object = object.id;
  run.hand = hand;
  run.planner = planner;
  run.object_hash = object.hash;
  return run;
}

// The message of an object's error, naming its file once.
std::string objectError(const ObjectIdentity& object, const std::exception_ptr& error) {
  std::string what = "unknown error";
  try {
    std::rethrow_exception(error);
  } catch (const std::exception& e) {
    what = e.what();
  } catch (...) {
  }
  return what.find(object.path) == std::string::npos ? object.path + ": " + what : what;
}

class ObjectEvaluator {
 public:
  ObjectEvaluator(const BatchParams& p, const std::vector<grasping::HandModel>& hands)
      : p_(p), hands_(hands) {}

  // Never throws: whatever goes wrong for this object is recorded as failed runs.
  ObjectOutcome evaluate(const ObjectIdentity& id) const {
    ObjectOutcome out;
    auto fail = [&](const std::string& hand, ranking::Planner planner, const std::string& error) {
      RunRecord r = runRecord(id, hand, planner);
      r.status = RunStatus::kError;
      r.error = error;
      out.runs.push_back(std::move(r));
      ++out.failed;
    };
    // Fails the runs of every planner, or of `only_planner` when given.
    auto failAll = [&](const std::string& error, std::optional<ranking::Planner> only_planner) {
      log().warn("evaluate: {}", error);
      for (const auto& hand : hands_) {
        for (const ranking::Planner planner : p_.planners) {
          if (!only_planner || planner == *only_planner) fail(hand.name(), planner, error);
        }
      }
    };
    std::unique_ptr<grasping::GraspObject> object;
    std::shared_ptr<const physics::PhysicalObject> physical;
    TriangleMesh mesh;
    try {
      mesh = loadMesh(id.path, p_.load);
      object = std::make_unique<grasping::GraspObject>(mesh);
      if (p_.physics) physical = internal::physicalObject(mesh, *p_.physics);
    } catch (...) {
      failAll(objectError(id, std::current_exception()), std::nullopt);
      return out;
    }
    const bool want_skeleton =
        std::count(p_.planners.begin(), p_.planners.end(), ranking::Planner::kSkeleton) > 0;
    std::optional<skeleton::SkeletonResult> skel;
    if (want_skeleton) {
      try {
        skel = skeleton::extractSkeleton(mesh, p_.skeleton);
        if (!skel->status.ok()) {
          failAll(id.path + ": " + skel->status.message, ranking::Planner::kSkeleton);
          skel.reset();
        }
      } catch (...) {
        failAll(objectError(id, std::current_exception()), ranking::Planner::kSkeleton);
        skel.reset();
      }
    }
    // The skeleton planner runs first whatever the order of `planners`: its pose count is the
    // surface planner's budget, which must not depend on that order.
    std::vector<ranking::Planner> planners = p_.planners;
    std::stable_partition(planners.begin(), planners.end(), [](ranking::Planner planner) {
      return planner == ranking::Planner::kSkeleton;
    });
    for (const auto& hand : hands_) {
      // As many surface hypotheses as the skeleton planner's poses on this object and hand (the
      // paper's comparison), else surface_hypotheses.
      std::size_t surface_budget = p_.surface_hypotheses;
      for (const ranking::Planner planner : planners) {
        const bool skeleton_planner = planner == ranking::Planner::kSkeleton;
        if (skeleton_planner && !skel) continue;  // recorded as failed above
        try {
          const std::size_t poses = plan(id, hand, planner, surface_budget, *object, physical.get(),
                                         skeleton_planner ? &*skel : nullptr, out);
          if (skeleton_planner && poses > 0) surface_budget = poses;
        } catch (...) {
          const std::string error = objectError(id, std::current_exception());
          log().warn("evaluate: {} ({}, {})", error, hand.name(), toString(planner));
          fail(hand.name(), planner, error);
        }
      }
    }
    return out;
  }

 private:
  // One planner run and its records; returns the run's pose count. `surface_budget`: the surface
  // planner's number of hypotheses.
  std::size_t plan(const ObjectIdentity& id, const grasping::HandModel& hand,
                   ranking::Planner planner, std::size_t surface_budget,
                   const grasping::GraspObject& object, const physics::PhysicalObject* physical,
                   const skeleton::SkeletonResult* skel, ObjectOutcome& out) const {
    const std::uint64_t seed =
        internal::fnv1a(internal::runKey(id.id, hand.name(), planner), p_.seed);
    ranking::PlanOptions options;
    options.planner = planner;
    grasping::HypothesisParams hypothesis;
    hypothesis.quality = p_.quality;
    hypothesis.closing.method = p_.robustness.closing.method;  // --closing judges both
    hypothesis.closing.contact_patch = p_.robustness.closing.contact_patch;  // and --contact-patch
    grasping::SkeletonPlannerParams& sp = options.skeleton_planner;
    sp.timeout_s = p_.timeout_s;
    sp.seed = seed;
    sp.vertex_distance_m = p_.vertex_distance_m;
    sp.centre_candidates = p_.centre_candidates;
    sp.alternative_preshapes = p_.alternative_preshapes;
    sp.surface_candidates = p_.surface_candidates;
    sp.hypothesis = hypothesis;
    grasping::SurfacePlannerParams& fp = options.surface_planner;
    fp.timeout_s = p_.timeout_s;
    fp.seed = seed;
    fp.max_hypotheses = surface_budget;
    fp.hypothesis = hypothesis;
    // The grasps as `plan` returns them: ranked by robustness, r on the best (same seed); without
    // ranking, the planner's order.
    options.ranking = p_.ranking;
    options.ranking.robustness.seed = seed;
    ranking::PlanInputs inputs;
    inputs.skeleton = skel;
    const ranking::GraspPlan result = ranking::planGrasps(object, hand, options, inputs);
    RankingMeasures ranking;
    if (p_.ranking.enabled) {
      const ranking::RobustRankingResult& ranked = result.ranking;
      ranking.scored = ranked.scored;
      ranking.time_s = ranked.time_s;
      double sum = 0, sum_unrefined = 0;
      for (const auto& g : result.grasps) {
        if (!g.robustness) continue;
        sum += g.robustness->r;
        sum_unrefined +=
            g.robustness->refinement ? g.robustness->refinement->r_before : g.robustness->r;
        ranking.samples += g.robustness->samples;
        ranking.start_collisions += g.robustness->start_collisions;
        ranking.closing_failures += g.robustness->closing_failures;
        ranking.no_force_closure += g.robustness->no_force_closure;
        ranking.too_weak += g.robustness->too_weak;
      }
      if (ranked.scored > 0) {
        ranking.r_mean = sum / ranked.scored;
        ranking.r_mean_unrefined = sum_unrefined / ranked.scored;
      }
      ranking.refinement_s = ranked.refinement_s;
      if (!result.grasps.empty() && result.grasps.front().robustness)
        ranking.r_best = result.grasps.front().robustness->r;
      ranking.refined = ranked.refined;
    }
    // The physics judge on the grasps as the run returns them.
    std::optional<internal::PhysicsMeasures> physics;
    std::vector<std::optional<bool>> physics_holds;
    if (physical) {
      physics = internal::judgeGrasps(hand, object, *physical, result.grasps, p_.quality.friction,
                                      *p_.physics, physics_holds);
    }
    record(id, hand, planner, seed, object, result, ranking, physics, physics_holds, skel, out);
    return result.summary.poses;
  }

  // What robust ranking measured in a run (BatchParams::ranking).
  struct RankingMeasures {
    std::size_t scored = 0;
    std::optional<double> r_mean;  // of the scored grasps
    std::optional<double> r_best;  // of the first grasp (ranked first)
    std::size_t refined = 0;       // scored grasps moved by refinement for robustness
    // The mean r the scored grasps had before refinement for robustness (each grasp's r_before;
    // a grasp it did not search keeps its r): what the ranking returns without it, since the
    // refinement runs after the scoring and moves only the grasp it searches.
    std::optional<double> r_mean_unrefined;
    double refinement_s = 0;
    // The scored grasps' samples, and the failed ones by cause.
    std::size_t samples = 0, start_collisions = 0, closing_failures = 0, no_force_closure = 0,
                too_weak = 0;
    double time_s = 0;
  };

  void record(const ObjectIdentity& id, const grasping::HandModel& hand, ranking::Planner planner,
              std::uint64_t seed, const grasping::GraspObject& object,
              const grasping::PlanResult& plan, const RankingMeasures& ranking,
              const std::optional<internal::PhysicsMeasures>& physics,
              const std::vector<std::optional<bool>>& physics_holds,
              const skeleton::SkeletonResult* skel, ObjectOutcome& out) const {
    // Robustness of a seeded sample of the kept grasps.
    std::vector<std::size_t> chosen(plan.grasps.size());
    std::iota(chosen.begin(), chosen.end(), 0);
    std::shuffle(chosen.begin(), chosen.end(), std::mt19937_64(seed));
    if (p_.robustness_grasps > 0 && chosen.size() > p_.robustness_grasps)
      chosen.resize(p_.robustness_grasps);
    std::sort(chosen.begin(), chosen.end());
    grasping::GraspSimulator simulator(hand, object);
    ranking::RobustnessParams rp = p_.robustness;
    rp.quality = grasping::withHandContactModel(p_.quality, hand);
    rp.seed = seed;
    std::map<std::size_t, ranking::RobustnessResult> robustness;
    double robustness_s = 0, robustness_sum = 0;
    for (std::size_t index : chosen) {
      robustness[index] = ranking::evaluateRobustness(simulator, plan.grasps[index], rp, index);
      robustness_s += robustness[index].time_s;
      robustness_sum += robustness[index].score;
    }
    const auto& s = plan.summary;
    RunRecord run = runRecord(id, hand.name(), planner);
    run.status = plan.grasps.empty() ? RunStatus::kNoGrasp : RunStatus::kOk;
    internal::RunMeasures& m = run.measures.emplace();
    m.seed = seed;
    m.hypotheses = s.hypotheses;
    m.poses = s.poses;
    m.generated = s.generated;
    m.force_closure = s.force_closure;
    m.force_closure_rate = s.forceClosureRate();
    m.kept = plan.grasps.size();
    m.power = s.power;
    m.precision = s.precision;
    m.rejections = s.rejections;
    m.timed_out = s.timed_out;
    m.planning_s = s.planning_s;
    if (s.force_closure) m.ms_per_valid_grasp = s.msPerValidGrasp();
    m.regularise_s = skel ? skel->timing.regularise_s : 0.0;
    m.skeleton_s = skel ? skel->timing.skeleton_s : 0.0;
    m.robustness_grasps = chosen.size();
    m.robustness_samples = rp.samples;
    m.robustness_s = robustness_s;
    if (!chosen.empty()) m.robustness_mean = robustness_sum / chosen.size();
    m.ranked = p_.ranking.enabled;
    m.ranked_grasps = ranking.scored;
    m.ranked_r_mean = ranking.r_mean;
    m.ranking_s = ranking.time_s;
    m.ranked_r_best = ranking.r_best;
    m.ranked_refined = ranking.refined;
    m.ranked_r_mean_unrefined = ranking.r_mean_unrefined;
    m.ranked_refinement_s = ranking.refinement_s;
    m.ranked_samples = ranking.samples;
    m.ranked_start_collisions = ranking.start_collisions;
    m.ranked_closing_failures = ranking.closing_failures;
    m.ranked_no_force_closure = ranking.no_force_closure;
    m.ranked_too_weak = ranking.too_weak;
    m.physics = physics;
    out.runs.push_back(std::move(run));
    for (std::size_t i = 0; i < plan.grasps.size(); ++i) {
      const auto& g = plan.grasps[i];
      GraspRecord r;
      r.object = id.id;
      r.hand = hand.name();
      r.planner = planner;
      r.grasp = g.id;
      r.type = grasping::toString(g.type);
      r.strategy = g.strategy;
      r.epsilon = g.epsilon;
      r.volume = g.volume;
      r.time_ms = s.msPerValidGrasp();
      if (const auto it = robustness.find(i); it != robustness.end()) {
        r.robustness = internal::GraspRobustness{it->second.score, it->second.wilson_low,
                                                 it->second.wilson_high, it->second.collisions};
      }
      if (i < physics_holds.size()) r.physics_holds = physics_holds[i];
      out.results.push_back(std::move(r));
    }
  }

  const BatchParams& p_;
  const std::vector<grasping::HandModel>& hands_;
};

// Mistakes in the batch's own options, found before any work starts.
void checkBatchParams(const BatchParams& p) {
  if (p.shard_count < 1 || p.shard_index < 0 || p.shard_index >= p.shard_count) {
    throw InvalidArgument("shard " + std::to_string(p.shard_index) + "/" +
                          std::to_string(p.shard_count) +
                          " out of range (use i/n with 0 <= i < n)");
  }
  if (p.jobs < 1) throw InvalidArgument("jobs must be at least 1");
  if (p.objects.empty()) throw InvalidArgument("no objects to evaluate");
  if (p.hands.empty()) throw InvalidArgument("no hands to evaluate");
  if (p.planners.empty()) throw InvalidArgument("no planners to evaluate");
  auto nonNegative = [](double value, const char* what) {
    if (!(value >= 0) || !std::isfinite(value))
      throw InvalidArgument(std::string(what) + " must be a finite number >= 0");
  };
  nonNegative(p.timeout_s, "timeout");
  nonNegative(p.vertex_distance_m, "vertex distance");
  nonNegative(p.quality.friction, "friction coefficient mu");
  if (p.quality.torsional_friction_m)
    nonNegative(*p.quality.torsional_friction_m, "torsional friction");
  if (p.quality.cone_edges < 3) throw InvalidArgument("friction cones need at least 3 edges");
  if (p.robustness.samples < 1) throw InvalidArgument("robustness needs at least one sample");
  ranking::checkRobustRankingParams(p.ranking);
  if (p.physics) {
    if (p.physics->grasps < 1) throw InvalidArgument("physics judge: grasps must be at least 1");
    if (!(p.physics->mass_kg > 0) || !std::isfinite(p.physics->mass_kg))
      throw InvalidArgument("physics judge: mass_kg must be a finite number > 0");
  }
}

// The files a batch writes into its directory (and nothing else there).
void removeBatchFiles(const std::string& dir) {
  namespace fs = std::filesystem;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    const bool chart = name.rfind("robustness_", 0) == 0 && entry.path().extension() == ".png";
    if (chart || name == "runs.jsonl" || name == "results.jsonl" || name == "summary.md" ||
        name == "summary.csv" || name == "batch.json") {
      fs::remove(entry.path());
    }
  }
}

void prepareOutDir(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw IoError(dir, "cannot create the output directory: " + ec.message());
}

}  // namespace

BatchStats runBatch(const BatchParams& p) {
  checkBatchParams(p);
  std::vector<grasping::HandModel> hands;
  for (const auto& name : p.hands) hands.push_back(grasping::resolveHand(name));
  std::vector<ObjectIdentity> objects = internal::identifyObjects(p.objects);
  if (p.object_limit > 0 && objects.size() > p.object_limit) objects.resize(p.object_limit);
  prepareOutDir(p.out_dir);
  const DirectoryLock lock(p.out_dir);
  const nlohmann::json options = internal::resultOptions(p, hands);
  if (p.restart) {
    removeBatchFiles(p.out_dir);
  } else if (const auto recorded = internal::readBatchOptions(p.out_dir)) {
    const std::string changed = internal::describeDifferences(*recorded, options);
    if (!changed.empty()) {
      throw InvalidArgument(p.out_dir + ": its runs were made with other options (" + changed +
                            "); restart the batch (--restart) or use another output directory");
    }
  } else if (std::filesystem::exists(p.out_dir + "/runs.jsonl")) {
    log().warn(
        "{}: no batch.json (written by an older skelgrasp): the options of its runs "
        "cannot be checked; recording this run's options",
        p.out_dir);
  }
  internal::writeBatchOptions(p.out_dir, options);
  Stopwatch watch;
  internal::BatchStore store(p.out_dir);

  BatchStats stats;
  std::vector<ObjectIdentity> todo;
  std::vector<char> retried, changed;
  std::set<std::string> listed;
  for (std::size_t k = 0; k < objects.size(); ++k) {
    listed.insert(objects[k].id);
    if (static_cast<int>(k % p.shard_count) != p.shard_index) continue;
    ++stats.objects_total;
    ObjectIdentity& object = objects[k];
    object.hash = internal::contentHash(object.path);
    bool done = true, failed = false, stale = false;
    for (const auto& hand : hands) {
      for (const ranking::Planner planner : p.planners) {
        const auto run =
            store.records().runs.find(internal::runKey(object.id, hand.name(), planner));
        if (run == store.records().runs.end()) {
          done = false;
          continue;
        }
        failed = failed || run->second.status == RunStatus::kError;
        // Records of an older skelgrasp have no hash; an unreadable file keeps its old results.
        const std::string recorded = run->second.object_hash.value_or(object.hash);
        stale = stale || (!object.hash.empty() && recorded != object.hash);
      }
    }
    if (stale)
      log().warn("evaluate: {} changed since its runs were recorded; evaluated again", object.path);
    if (done && !stale && !(failed && p.retry_failed)) {
      ++stats.objects_skipped;
      continue;
    }
    todo.push_back(object);
    retried.push_back(done && failed && p.retry_failed && !stale);
    changed.push_back(stale);
  }
  std::size_t foreign = 0;
  for (const auto& [key, run] : store.records().runs) foreign += !listed.count(run.object);
  if (foreign > 0) {
    log().warn("{}: holds {} run(s) of objects not in this list; they stay in the summary",
               p.out_dir, foreign);
  }
  if (p.max_objects > 0 && todo.size() > p.max_objects) todo.resize(p.max_objects);
  for (std::size_t i = 0; i < todo.size(); ++i) {
    stats.objects_retried += retried[i];
    stats.objects_changed += changed[i];
  }
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
  store.compact();
  writeSummary(p.out_dir);
  return stats;
}

}  // namespace skelgrasp::evaluation
