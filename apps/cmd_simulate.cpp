// skelgrasp simulate GRASPS.json MESH --hand H: execute given grasps in the physics judge (Bullet):
// the hand welded at each grasp's pose closes on a free object, which must then stay put under its
// weight along +-x, +-y, +-z; with --samples, the same under r's pose error (sim_r).
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli.h"
#include "grasps_hand.h"
#include "option_checks.h"
#include "output_paths.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/evaluation/score.h"
#include "skelgrasp/evaluation/simulate.h"

namespace skelgrasp::cli {
namespace {

constexpr double kMaxDensityKgM3 = 1e5;
constexpr double kMaxForceN = 1e4;
// The judge's own bounds (physics/execution.h).
constexpr double kMaxTimeStepS = 0.01;
constexpr std::uint64_t kMaxSolverIterations = 1000;

struct SimulateArgs {
  std::string grasps;
  std::string mesh;
  std::string hand;
  std::string description;
  std::vector<double> mu = evaluation::SimulateParams{}.frictions;
  double mass_kg = physics::PhysicalObjectParams{}.mass_kg;
  std::optional<double> density;
  std::optional<double> force_n;
  std::optional<double> fingertip_force_n;
  int samples = evaluation::SimulateParams{}.samples;
  std::uint64_t seed = ranking::RobustnessParams{}.seed;
  std::optional<std::uint64_t> object;
  std::optional<std::uint64_t> max_grasps;
  double time_step_s = physics::JudgeParams{}.time_step_s;
  int solver_iterations = physics::JudgeParams{}.solver_iterations;
  std::string out = "simulation.json";
  std::string units = "auto";
};

int runSimulate(const SimulateArgs& a) {
  checkOutputFileOption(a.out);
  if (a.mu.size() > evaluation::kMaxScoreFrictions) {
    throw InvalidArgument(
        fmt::format("--mu: {} values, at most {}", a.mu.size(), evaluation::kMaxScoreFrictions));
  }
  const nlohmann::json file = readJsonFile(a.grasps);
  const auto hand = handOfGraspsFile(file, a.grasps, a.hand, a.description);
  std::vector<grasping::GraspPlacement> placements;
  try {
    std::optional<long long> object;
    if (a.object) object = static_cast<long long>(*a.object);
    placements = grasping::readGraspPlacements(file, hand, object);
  } catch (const InvalidArgument& e) {
    throw IoError(a.grasps, e.what());
  }
  if (a.max_grasps && placements.size() > *a.max_grasps) placements.resize(*a.max_grasps);
  evaluation::SimulateParams params;
  params.frictions = a.mu;
  params.samples = a.samples;
  params.robustness.seed = a.seed;
  params.judge.disturbance_force_n = a.force_n;
  params.judge.fingertip_force_n = a.fingertip_force_n;
  params.judge.time_step_s = a.time_step_s;
  params.judge.solver_iterations = a.solver_iterations;
  // Refused before the mesh is read: the file's grasps times the executions asked for.
  try {
    evaluation::checkSimulationWork(placements.size(), params);
  } catch (const InvalidArgument& e) {
    throw IoError(a.grasps, e.what());
  }
  MeshLoadOptions load;
  load.units = parseLengthUnit(a.units);
  const TriangleMesh mesh = loadMesh(a.mesh, load);
  physics::PhysicalObjectParams object_params;
  object_params.mass_kg = a.mass_kg;
  object_params.density_kg_m3 = a.density;
  const physics::PhysicalObject physical(mesh, object_params);
  const grasping::GraspObject object(mesh);
  const auto result = evaluation::simulateGrasps(hand, object, physical, placements, params);
  OutputTransaction outputs;
  writeJsonFile(
      outputs.stage(a.out),
      evaluation::simulationToJson(result, params, hand, physical,
                                   std::filesystem::path(a.mesh).filename().string(), a.grasps));
  outputs.commit();
  std::cout << evaluation::simulationSummaryLine(result, params) << " -> " << a.out << std::endl;
  return kExitOk;
}

}  // namespace

void registerSimulateCommand(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand(
      "simulate",
      "Execute grasps in the physics judge (Bullet): close on a free object, then pull it "
      "along +-x, +-y, +-z; --samples adds sim_r under r's pose error");
  auto a = std::make_shared<SimulateArgs>();
  cmd->add_option("GRASPS", a->grasps,
                  "grasps.json (schema skelgrasp.grasps/N of plan or skelgrasp.run/N of run)")
      ->required();
  cmd->add_option("MESH", a->mesh, "The object's mesh, in the grasps' frame (.ply .obj .off .stl)")
      ->required();
  cmd->add_option("--hand", a->hand,
                  "Built-in hand or a .urdf file (default: the built-in hand GRASPS names)");
  cmd->add_option("--grasp-description", a->description,
                  "Grasp description JSON for a .urdf hand (docs/hands.md)");
  std::string shown_default;
  for (double mu : a->mu)
    shown_default += fmt::format("{}{}", shown_default.empty() ? "" : ",", mu);
  cmd->add_option(
         "--mu", a->mu,
         "Friction coefficients, comma-separated, e.g. 0.35,0.5 (default " + shown_default + ")")
      ->delimiter(',')
      ->check(finiteIn(0, kMaxFriction));
  cmd->add_option("--mass", a->mass_kg, "Object mass (kg)")
      ->check(positiveFinite(physics::kMaxObjectMassKg))
      ->capture_default_str();
  cmd->add_option("--density", a->density,
                  "Object density (kg/m^3) instead of --mass: mass = density x enclosed volume")
      ->check(positiveFinite(kMaxDensityKgM3));
  cmd->add_option("--force", a->force_n,
                  "Disturbance force (N; default: the object's weight, mass x 9.81)")
      ->check(positiveFinite(kMaxForceN));
  cmd->add_option("--fingertip-force", a->fingertip_force_n,
                  "Finger strength at the fingertip (N) that sets the joint torque limits "
                  "(default: the hand's, docs/physics.md)")
      ->check(positiveFinite(kMaxForceN));
  cmd->add_option(
         "--samples", a->samples,
         "Perturbed executions per grasp and mu for sim_r (r's pose error; 0: nominal only)")
      ->transform(countIn(0, evaluation::kMaxSimulationSamples))
      ->capture_default_str();
  cmd->add_option("--seed", a->seed, "Pose error seed (plan's default reproduces r's samples)")
      ->transform(countIn(0, UINT64_MAX))
      ->capture_default_str();
  cmd->add_option("--object", a->object,
                  "Run files with several objects: simulate the grasps of this object id")
      ->transform(countIn(0, kMaxCount));
  cmd->add_option("--max-grasps", a->max_grasps, "Simulate only the first N grasps of the file")
      ->transform(countIn(1, kMaxCount));
  cmd->add_option("--time-step", a->time_step_s, "Engine integration step (s)")
      ->check(positiveFinite(kMaxTimeStepS))
      ->capture_default_str();
  cmd->add_option("--solver-iterations", a->solver_iterations,
                  "Constraint solver iterations per step")
      ->transform(countIn(1, kMaxSolverIterations))
      ->capture_default_str();
  cmd->add_option("--out", a->out, "Output JSON (schema skelgrasp.simulation/1)")
      ->capture_default_str();
  cmd->add_option("--units", a->units, "Mesh units: auto, m or mm")->capture_default_str();
  cmd->callback([a, &action] { action = [a] { return runSimulate(*a); }; });
}

}  // namespace skelgrasp::cli
