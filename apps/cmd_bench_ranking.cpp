// skelgrasp bench ranking INPUT...: the robust ranking with an exact shortcut off (the old path)
// and on (the new), in one process on the same planned grasps, per object and hand: time of each
// path, their ratio, and whether they return the same scored grasps with the same r. The
// shortcuts (--compare): `pruning`, screening a candidate only until it cannot enter the scored
// top_k (in pre-score order); `best-first`, screening best-first against pruning in pre-score
// order; `closure-shortcut`, settling's closure test skipped while the squeeze is unbalanced
// (grasping/quality/settling.h); `cell-skipping`, the exact box gap skipping empty cells of the
// triangle grid (DistanceFieldParams::skip_empty_cells); `jump-order`, the fast closing's jump
// attempts stopping at the first link that allows no step
// (ClosingParams::jump_stops_at_blocking_link); `refusals`, the fast closing's later passes not
// testing again a refused step while the fingers it was tested against stand where they stood
// (ClosingParams::skip_repeated_refusals); `gap-hints`, the fast closing's exact box gaps starting
// from the face the box was closest to in its last query (ClosingParams::gap_hints); `box-tests`,
// the hand's box shapes tested for intersection with the object on its distance field rather than
// by FCL (DistanceFieldParams:: box_intersection_tests). Two comparisons are not of an exact
// shortcut but of a choice: `screen-by`, screening the best by epsilon (old) or each preshape's
// best in turn (new, RobustRankingParams::screen_candidates); its paths return different grasps,
// and the mean r of each path's scored grasps says which is worth more. Both paths run each hand's
// own ranking budget (the Shadow hand's is smaller), except that screen-by sets each path's
// screening choice whatever the hand's description says. `confirm` is a choice too: the screening's
// contenders without (old) or with (new) the default confirmation samples
// (RobustRankingParams::confirm_samples), whatever the hand's budget says.
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <filesystem>
#include <iostream>
#include <map>
#include <optional>

#include "cli.h"
#include "mesh_list.h"
#include "option_checks.h"
#include "output_paths.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/ranking/plan_grasps.h"
#include "skelgrasp/ranking/robust_ranking.h"
#include "skelgrasp/skeleton/extraction.h"

namespace skelgrasp::cli {
namespace {

// Exit code when the two paths return different scored grasps: a failed check, not bad input.
constexpr int kExitPathsDiffer = 1;

struct BenchRankingArgs {
  std::vector<std::string> inputs;
  std::string hands = "armar3,sdh,shadow";
  std::size_t limit = 0;
  int repeat = 1;
  std::string compare = "pruning";
  std::string json_out;
};

// The exact shortcut a run compares off (old path) and on (new path).
enum class Shortcut {
  kPruning,
  kBestFirst,
  kClosureShortcut,
  kCellSkipping,
  kJumpOrder,
  kRefusals,
  kGapHints,
  kBoxTests,
  kScreenBy,  // not exact: the two paths may score different grasps
  kConfirm    // not exact either
};

// --compare's names: the option admits these (CLI::IsMember on the keys) and the run looks its
// shortcut up here.
const std::map<std::string, Shortcut>& shortcutsByName() {
  static const std::map<std::string, Shortcut> names = {
      {"pruning", Shortcut::kPruning},
      {"best-first", Shortcut::kBestFirst},
      {"closure-shortcut", Shortcut::kClosureShortcut},
      {"cell-skipping", Shortcut::kCellSkipping},
      {"jump-order", Shortcut::kJumpOrder},
      {"refusals", Shortcut::kRefusals},
      {"gap-hints", Shortcut::kGapHints},
      {"box-tests", Shortcut::kBoxTests},
      {"screen-by", Shortcut::kScreenBy},
      {"confirm", Shortcut::kConfirm}};
  return names;
}

struct PathRun {
  ranking::RobustRankingResult result;
  double seconds = 0;
};

// `object` is the one of the path (cell-skipping, box-tests: built with or without the shortcut).
PathRun rankOnce(const grasping::HandModel& hand, const grasping::GraspObject& object,
                 const std::vector<grasping::Grasp>& grasps,
                 const grasping::SkeletonPlannerParams& planner, Shortcut shortcut, bool new_path) {
  // The other shortcuts stay at their defaults, so each comparison is against today's ranking.
  ranking::RobustRankingParams params;
  grasping::HypothesisParams hypothesis = planner.hypothesis;
  switch (shortcut) {
    case Shortcut::kPruning:
      params.screening_pruning =
          new_path ? ranking::ScreeningPruning::kInOrder : ranking::ScreeningPruning::kNone;
      break;
    case Shortcut::kBestFirst:
      params.screening_pruning =
          new_path ? ranking::ScreeningPruning::kBestFirst : ranking::ScreeningPruning::kInOrder;
      break;
    case Shortcut::kClosureShortcut:
      params.robustness.settling.skip_closure_test_when_unbalanced = new_path;
      break;
    case Shortcut::kCellSkipping:  // the caller passes the path's object
    case Shortcut::kBoxTests:
      break;
    case Shortcut::kJumpOrder:
      hypothesis.closing.jump_stops_at_blocking_link = new_path;
      break;
    case Shortcut::kRefusals:
      hypothesis.closing.skip_repeated_refusals = new_path;
      break;
    case Shortcut::kGapHints:
      hypothesis.closing.gap_hints = new_path;
      break;
    case Shortcut::kScreenBy:
      params.screen_candidates = new_path ? ranking::ScreenCandidates::kPreshapesInTurn
                                          : ranking::ScreenCandidates::kByPreScore;
      break;
    case Shortcut::kConfirm:
      params.confirm_samples = new_path ? ranking::kDefaultConfirmSamples : 0;
      break;
  }
  PathRun run;
  const Stopwatch watch;
  run.result = ranking::rankByRobustness(hand, object, grasps, hypothesis, params);
  run.seconds = watch.seconds();
  return run;
}

// The mean r of the scored grasps (they come first); 0 when none was scored.
double meanScoredR(const ranking::RobustRankingResult& result) {
  double sum = 0;
  for (std::size_t i = 0; i < result.scored; ++i) sum += result.grasps[i].robustness->r;
  return result.scored > 0 ? sum / static_cast<double>(result.scored) : 0.0;
}

// The scored grasps (they come first) agree in order, pose and r.
bool sameScoredGrasps(const ranking::RobustRankingResult& a,
                      const ranking::RobustRankingResult& b) {
  if (a.scored != b.scored) return false;
  for (std::size_t i = 0; i < a.scored; ++i) {
    if (a.order[i] != b.order[i] || a.grasps[i].robustness->r != b.grasps[i].robustness->r ||
        !a.grasps[i].hand_pose.isApprox(b.grasps[i].hand_pose, 0.0))
      return false;
  }
  return true;
}

int runBenchRanking(const BenchRankingArgs& args) {
  checkOutputFileOption(args.json_out);
  setLogLevel(spdlog::level::warn);
  auto files = collectMeshFiles(args.inputs);
  if (args.limit > 0 && files.size() > args.limit) files.resize(args.limit);
  if (files.empty()) return fail("bench ranking: no mesh files in the given inputs");
  std::vector<grasping::HandModel> hands;
  for (const auto& name : splitList(args.hands)) hands.push_back(grasping::resolveHand(name));
  // One core, as the plan-time goal is stated.
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 1);
  const grasping::SkeletonPlannerParams planner;
  const Shortcut shortcut = shortcutsByName().at(args.compare);
  std::cout << fmt::format("comparing {}: old path ({}) against new path ({})\n", args.compare,
                           shortcut == Shortcut::kScreenBy ? "epsilon" : "off",
                           shortcut == Shortcut::kScreenBy ? "preshapes" : "on");
  const bool exact = shortcut != Shortcut::kScreenBy && shortcut != Shortcut::kConfirm;
  std::cout << fmt::format("{:<32} {:<8} {:>6} {:>8} {:>7} {:>7} {:>7} {:>6} {:>6} {:>6}\n",
                           "object", "hand", "cands", "pruned", "old_s", "new_s", "ratio", "same",
                           "old_r", "new_r");
  std::map<std::string, std::pair<double, double>> totals;  // per hand: old, new seconds
  std::map<std::string, std::vector<double>> ratios;
  std::map<std::string, std::pair<std::vector<double>, std::vector<double>>> mean_rs;  // old, new
  bool all_same = true;
  nlohmann::json rows = nlohmann::json::array();
  ProgressReporter progress("bench ranking", files.size(), 10.0);
  for (std::size_t f = 0; f < files.size(); ++f) {
    const std::string name = std::filesystem::path(files[f]).stem().string();
    try {
      const TriangleMesh mesh = loadMesh(files[f]);
      const auto skel = skeleton::extractSkeleton(mesh);
      if (!skel.status.ok()) throw Error(skel.status.message);
      const grasping::GraspObject object(mesh);
      // The old path's object for cell-skipping and box-tests, its field built before any
      // timing (the new one's is built by the planning below).
      std::optional<grasping::GraspObject> old_object;
      if (shortcut == Shortcut::kCellSkipping || shortcut == Shortcut::kBoxTests) {
        grasping::DistanceFieldParams old_params;
        if (shortcut == Shortcut::kCellSkipping) old_params.skip_empty_cells = false;
        if (shortcut == Shortcut::kBoxTests) old_params.box_intersection_tests = false;
        old_object.emplace(mesh, old_params);
        old_object->distanceField();
      }
      for (const auto& hand : hands) {
        // The planned grasps, ranked below once per path.
        ranking::PlanOptions options;
        options.skeleton_planner = planner;
        options.ranking.enabled = false;
        ranking::PlanInputs inputs;
        inputs.skeleton = &skel;
        const auto plan = ranking::planGrasps(object, hand, options, inputs);
        double old_s = 0, new_s = 0;
        PathRun old_run, new_run;
        // Alternating which path goes first, so neither always runs on a warmer cache.
        for (int rep = 0; rep < args.repeat; ++rep) {
          for (int k = 0; k < 2; ++k) {
            const bool new_path = (k == 1) != (rep % 2 == 1);
            const bool old_object_path = old_object && !new_path;
            PathRun run = rankOnce(hand, old_object_path ? *old_object : object, plan.grasps,
                                   planner, shortcut, new_path);
            (new_path ? new_s : old_s) += run.seconds;
            (new_path ? new_run : old_run) = std::move(run);
          }
        }
        const bool same = sameScoredGrasps(old_run.result, new_run.result);
        all_same = all_same && same;
        const double ratio = new_s > 0 ? old_s / new_s : 0;
        totals[hand.name()].first += old_s / args.repeat;
        totals[hand.name()].second += new_s / args.repeat;
        ratios[hand.name()].push_back(ratio);
        // Every path screens as many candidates, fully or cut short (the same ones, but for
        // screen-by).
        const std::size_t candidates = old_run.result.screened + old_run.result.screen_pruned;
        const double old_r = meanScoredR(old_run.result), new_r = meanScoredR(new_run.result);
        mean_rs[hand.name()].first.push_back(old_r);
        mean_rs[hand.name()].second.push_back(new_r);
        std::cout << fmt::format(
            "{:<32} {:<8} {:>6} {:>8} {:>7.2f} {:>7.2f} {:>6.2f}x {:>6} {:>6.3f} {:>6.3f}\n",
            name.substr(0, 32), hand.name(), candidates, new_run.result.screen_pruned,
            old_s / args.repeat, new_s / args.repeat, ratio, same ? "yes" : "NO", old_r, new_r);
        rows.push_back({{"object", name},
                        {"hand", hand.name()},
                        {"candidates", candidates},
                        {"pruned", new_run.result.screen_pruned},
                        {"old_s", old_s / args.repeat},
                        {"new_s", new_s / args.repeat},
                        {"same_scored_grasps", same},
                        {"old_mean_r", old_r},
                        {"new_mean_r", new_r}});
      }
    } catch (const std::exception& e) {
      spdlog::error("bench ranking: {}: {}", files[f], e.what());
    }
    progress.step(f + 1);
  }
  for (const auto& [hand, t] : totals) {
    std::cout << fmt::format(
        "{:<8} ranking time old {:.1f} s, new {:.1f} s over the objects: {:.2f}x (median per "
        "object {:.2f}x)\n",
        hand, t.first, t.second, t.second > 0 ? t.first / t.second : 0.0, median(ratios[hand]));
    std::cout << fmt::format(
        "{:<8} mean r of the scored grasps, median over the objects: old {:.3f}, new {:.3f}\n",
        hand, median(mean_rs[hand].first), median(mean_rs[hand].second));
  }
  if (!args.json_out.empty()) writeJsonFile(args.json_out, {{"rows", rows}});
  // A choice, not a shortcut: the paths may differ, and the r above says how.
  if (!exact) return kExitOk;
  std::cout << (all_same ? "every object: the same scored grasps with the same r\n"
                         : "SOME OBJECTS DIFFER in their scored grasps\n");
  return all_same ? kExitOk : kExitPathsDiffer;
}

}  // namespace

void registerBenchRankingCommand(CLI::App& app, Action& action) {
  CLI::App* bench = app.get_subcommand("bench");  // created by registerBenchCommand
  auto* cmd = bench->add_subcommand(
      "ranking",
      "Robust ranking without and with an exact shortcut (or another screening choice), one "
      "process, same grasps (one core)");
  auto args = std::make_shared<BenchRankingArgs>();
  cmd->add_option("inputs", args->inputs, "Mesh files or directories")->required();
  cmd->add_option("--hands", args->hands, "Comma-separated built-in hands")->capture_default_str();
  cmd->add_option("--limit", args->limit, "Only the first N meshes (0 = all)")
      ->capture_default_str();
  cmd->add_option("--repeat", args->repeat, "Runs of each path per object and hand (mean)")
      ->transform(countIn(1, kMaxRepeat))
      ->capture_default_str();
  cmd->add_option("--compare", args->compare,
                  "pruning (screening stops where it cannot choose), best-first (screening "
                  "best-first against pruning in pre-score order), closure-shortcut (settling "
                  "skips the closure test while the squeeze is unbalanced), cell-skipping (the "
                  "exact box gap skips empty cells), jump-order (the fast closing's jump "
                  "attempts stop at the first link that allows no step), refusals (later passes "
                  "do not test again a refused step while the fingers it was tested against "
                  "stand where they stood), gap-hints (exact box gaps start from the face the "
                  "box was closest to in its last query) or box-tests (box shapes tested for "
                  "intersection on the object's distance field, not by FCL); or, not exact, the "
                  "two paths' r "
                  "compared: screen-by (screening the best by epsilon against each preshape's "
                  "best in turn) or "
                  "confirm (the screening's contenders without and with confirmation samples)")
      ->check(CLI::IsMember(shortcutsByName()))
      ->capture_default_str();
  cmd->add_option("--json", args->json_out, "Also write the rows as JSON");
  cmd->callback([=, &action] { action = [=] { return runBenchRanking(*args); }; });
}

}  // namespace skelgrasp::cli
