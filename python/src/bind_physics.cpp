// simulate(): the physics judge on grasps (`skelgrasp simulate`, docs/physics.md).
#include <fmt/format.h>
#include <pybind11/stl.h>

#include <cmath>

#include "bindings.h"
#include "convert.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/evaluation/simulate.h"
#include "skelgrasp/grasping/io/grasps_file.h"
#include "skelgrasp/grasping/simulation/grasp_object.h"
#include "skelgrasp/physics/physical_object.h"

namespace skelgrasp::python {
namespace {

// A grasps.json given as a path, as the parsed document (a dict) or as a plan result (its
// to_dict()).
nlohmann::json graspsDocument(const py::object& grasps, std::string& source) {
  if (py::isinstance<py::str>(grasps)) {
    source = grasps.cast<std::string>();
    return readJsonFile(source);
  }
  py::object document = grasps;
  if (py::hasattr(grasps, "to_dict")) document = grasps.attr("to_dict")();
  const std::string text = py::module_::import("json").attr("dumps")(document).cast<std::string>();
  return nlohmann::json::parse(text);
}

py::object simulate(const Mesh& mesh, const HandPtr& hand, const py::object& grasps,
                    const std::vector<double>& mu, int samples, std::uint64_t seed, double mass,
                    std::optional<double> fingertip_force, std::optional<double> force,
                    const std::optional<long long>& object, std::optional<std::size_t> max_grasps) {
  if (!(mass > 0) || !(mass <= physics::kMaxObjectMassKg))
    throw InvalidArgument(fmt::format("mass: must be in (0, {:g}] kg", physics::kMaxObjectMassKg));
  if (fingertip_force && !(*fingertip_force > 0 && std::isfinite(*fingertip_force)))
    throw InvalidArgument("fingertip_force: must be a finite number > 0 (N)");
  if (force && !(*force > 0 && std::isfinite(*force)))
    throw InvalidArgument("force: must be a finite number > 0 (N)");
  std::string source = "grasps";
  const nlohmann::json file = graspsDocument(grasps, source);
  auto placements = grasping::readGraspPlacements(file, *hand, object);
  if (max_grasps && placements.size() > *max_grasps) placements.resize(*max_grasps);
  evaluation::SimulateParams params;
  params.frictions = mu;
  params.samples = samples;
  params.robustness.seed = seed;
  params.judge.fingertip_force_n = fingertip_force;
  params.judge.disturbance_force_n = force;
  evaluation::checkSimulationWork(placements.size(), params);  // before the object is prepared
  physics::PhysicalObjectParams object_params;
  object_params.mass_kg = mass;
  nlohmann::json out;
  {
    py::gil_scoped_release release;
    const physics::PhysicalObject physical(mesh.mesh, object_params);
    const grasping::GraspObject target(mesh.mesh);
    const auto result = evaluation::simulateGrasps(*hand, target, physical, placements, params);
    out = evaluation::simulationToJson(result, params, *hand, physical, mesh.name, source);
  }
  return fromJson(out);
}

}  // namespace

void bindPhysics(py::module_& m) {
  const evaluation::SimulateParams defaults;
  m.def("simulate", &simulate, py::arg("mesh"), py::arg("hand"), py::arg("grasps"), py::kw_only(),
        py::arg("mu") = defaults.frictions, py::arg("samples") = defaults.samples,
        py::arg("seed") = defaults.robustness.seed,
        py::arg("mass") = physics::PhysicalObjectParams{}.mass_kg,
        py::arg("fingertip_force") = py::none(), py::arg("force") = py::none(),
        py::arg("object") = py::none(), py::arg("max_grasps") = py::none(),
        R"doc(
``skelgrasp simulate``: executes grasps in the physics judge (Bullet; docs/physics.md). ``grasps``
is a plan result, a grasps.json path or its parsed dict. Each grasp's hand is welded at its pose
in its preshape, the fingers close with torque-limited servos on a free object of ``mass`` kg,
then the object is pulled along +-x, +-y, +-z by its weight (or ``force`` N); it holds when it
moves < 2 cm and turns < 15 degrees in all six. ``mu``: friction coefficients, each judged in turn;
``samples`` > 0 adds sim_r, the share of executions under r's seeded pose error (10 mm / 5
degrees) that hold; ``fingertip_force`` (N) overrides the hand's strength. Returns the
skelgrasp.simulation/1 document.)doc");
}

}  // namespace skelgrasp::python
