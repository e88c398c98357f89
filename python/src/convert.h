#pragma once
// numpy <-> skelgrasp conversions shared by the binding files, and the wrapper types the module
// hands to Python (each keeps what its to_dict() needs: a mesh its load info, a grasp its hand).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/common/point_cloud.h"
#include "skelgrasp/common/pose.h"
#include "skelgrasp/evaluation/plan_record.h"
#include "skelgrasp/grasping/grasp.h"
#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/grasping/planning/planners.h"
#include "skelgrasp/perception/scan.h"
#include "skelgrasp/ranking/plan_grasps.h"
#include "skelgrasp/ranking/robust_ranking.h"
#include "skelgrasp/skeleton/extraction.h"

namespace skelgrasp::python {

namespace py = pybind11;

using Matrix = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IndexMatrix = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

// A mesh and where it came from (skeleton.json's "input" and grasps.json's "object").
struct Mesh {
  TriangleMesh mesh;
  MeshLoadInfo info;  // path "" for a mesh made from arrays
  std::string name;   // file name, or the name given to Mesh(...)
};

// A point cloud as the pipeline consumes it (a scan of one or more views).
struct Cloud {
  perception::Scan scan;
};

// The skeleton stage's result on `input` (skeleton.json through json()).
struct SkeletonOutput {
  skeleton::SkeletonResult result;
  Mesh input;

  nlohmann::json json() const;
};

using HandPtr = std::shared_ptr<grasping::HandModel>;

// A planned grasp with the hand it was planned for (joint names, to_dict()).
struct Grasp {
  grasping::Grasp grasp;
  HandPtr hand;
  // `run` only: ranking terms (NaN otherwise).
  double observed_contact_ratio = std::numeric_limits<double>::quiet_NaN();
  double rank_score = std::numeric_limits<double>::quiet_NaN();
};

// What plan() returns: the planner's result with the hand, the object's name and (skeleton
// planner) the skeleton, for to_dict(), render_plan() and score().
struct Plan {
  // The plan, its skeleton moved into `skeleton`: to_dict() writes the ranking's record and the
  // stages' times, as `skelgrasp plan` does (evaluation/plan_record.h).
  ranking::GraspPlan result;
  HandPtr hand;
  std::string object;
  std::optional<SkeletonOutput> skeleton;
};

// N x 3 float64 (any float or int dtype converts) -> points; throws InvalidArgument naming `what`
// for another shape or a non-finite entry.
std::vector<Eigen::Vector3d> toPoints(const py::object& array, const std::string& what);
// F x 3 integer indices, each in [0, vertex_count).
std::vector<Eigen::Vector3i> toFaces(const py::object& array, std::size_t vertex_count,
                                     const std::string& what);
std::vector<Rgb> toColours(const py::object& array, std::size_t count, const std::string& what);
// A 4 x 4 homogeneous rigid transform (rotation orthonormal within kPoseUnitTolerance, then made
// exact; last row 0 0 0 1), or the 7 numbers x y z qw qx qy qz.
Pose toPose(const py::object& array, const std::string& what);

Matrix fromPoints(const std::vector<Eigen::Vector3d>& points);
IndexMatrix fromFaces(const std::vector<Eigen::Vector3i>& faces);
Matrix fromPose(const Pose& pose);

// nlohmann::json -> Python objects (dict, list, float, int, str, bool, None).
py::object fromJson(const nlohmann::json& j);

// A whole number >= 0 from Python (an int, or anything with __index__ such as numpy's integers).
// Throws TypeError for another type, InvalidArgument naming `what` for a negative number or one
// beyond Count's range.
template <typename Count>
Count toCount(const py::handle& value, const std::string& what) {
  const auto index = py::reinterpret_steal<py::object>(PyNumber_Index(value.ptr()));
  if (!index) {
    PyErr_Clear();
    throw py::type_error(what + ": expected a whole number, got " +
                         py::str(py::type::handle_of(value).attr("__name__")).cast<std::string>());
  }
  const std::string text = py::str(index);
  if (PyObject_RichCompareBool(index.ptr(), py::int_(0).ptr(), Py_LT) == 1)
    throw InvalidArgument(what + ": " + text + " is negative, expected a whole number >= 0");
  try {
    return index.cast<Count>();
  } catch (const py::cast_error&) {
    throw InvalidArgument(what + ": " + text + " is too large");
  }
}

// The robust ranking of run() from its keyword arguments (as the CLI's
// --no-robustness, --robustness-samples, --robustness-variant, --robustness-top-k,
// --robustness-screen, --robustness-screen-samples, --robustness-screen-by,
// --robustness-confirm-samples, --robustness-mu,
// --no-robust-refine and --robust-refine-below-r; the budget's unset values are the hand's);
// `seed` also seeds the robustness samples. Throws InvalidArgument for samples or screen_samples <
// 1, confirm_samples < 0, refine_below_r outside [0, 1], an unknown variant or an unknown
// screen_by.
ranking::RobustRankingParams robustRankingParams(bool robustness, int samples,
                                                 const std::string& variant, std::size_t top_k,
                                                 std::optional<std::size_t> screen_k,
                                                 std::optional<int> screen_samples,
                                                 const std::optional<std::string>& screen_by,
                                                 std::optional<int> confirm_samples,
                                                 std::optional<double> mu, std::uint64_t seed,
                                                 bool refine, std::optional<double> refine_below_r);

// Contacts as a list of {point, normal, link, palm} dicts (Grasp.contacts, CloseResult.contacts).
py::list contactsList(const std::vector<grasping::Contact>& contacts);

// A soft-finger torsion length from Python: None, or finite and >= 0 (else InvalidArgument).
// A count of robustness samples in [min, ranking::kMaxRobustnessSamples], the command line's
// range: a billion samples would run for days.
void checkSamples(const char* name, int value, int min);
// timeout_s of plan and run: finite, in [0, ranking::kMaxPlanTimeoutS] (0 = none).
void checkTimeout(double timeout_s);
void checkTorsionalFriction(const std::optional<double>& torsional_friction);

// The quality keywords close() and score() share (--mu, --fc-test, --reference-compat,
// --torsional-friction; None leaves the contact model to the hand, withHandContactModel).
grasping::QualityParams qualityParams(double mu, const std::string& fc_test, bool reference_compat,
                                      std::optional<double> torsional_friction);

// {joint name: value} for the movable joints of `hand` in configuration `q`.
py::dict jointsDict(const grasping::HandModel& hand, const Eigen::VectorXd& q);

}  // namespace skelgrasp::python
