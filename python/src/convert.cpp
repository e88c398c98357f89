#include "convert.h"

#include <fmt/format.h>

#include <cmath>

#include "skelgrasp/common/error.h"
#include "skelgrasp/ranking/limits.h"
#include "skelgrasp/skeleton/output.h"

namespace skelgrasp::python {
namespace {

// Any numeric array-like as a C-contiguous float64 / int64 array (copies only when needed).
Matrix asDoubles(const py::object& object, const std::string& what) {
  if (object.is_none()) throw InvalidArgument(what + ": got None, expected an N x 3 array");
  Matrix a = Matrix::ensure(object);  // null (error cleared) when not convertible
  if (!a) throw InvalidArgument(what + ": not a numeric array");
  return a;
}

void checkShape(const py::array& a, py::ssize_t columns, const std::string& what) {
  if (a.ndim() != 2 || a.shape(1) != columns) {
    std::string shape;
    for (py::ssize_t d = 0; d < a.ndim(); ++d)
      shape += (d ? " x " : "") + std::to_string(a.shape(d));
    throw InvalidArgument(fmt::format("{}: expected an N x {} array, got shape ({})", what, columns,
                                      a.ndim() ? shape : "scalar"));
  }
}

}  // namespace

std::vector<Eigen::Vector3d> toPoints(const py::object& object, const std::string& what) {
  const Matrix a = asDoubles(object, what);
  checkShape(a, 3, what);
  const auto view = a.unchecked<2>();
  std::vector<Eigen::Vector3d> points(static_cast<std::size_t>(a.shape(0)));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(view(i, c)))
        throw InvalidArgument(fmt::format("{}: row {} is not finite ({})", what, i, view(i, c)));
      points[static_cast<std::size_t>(i)][c] = view(i, c);
    }
  }
  return points;
}

std::vector<Eigen::Vector3i> toFaces(const py::object& object, std::size_t vertex_count,
                                     const std::string& what) {
  if (object.is_none()) throw InvalidArgument(what + ": got None, expected an F x 3 array");
  const py::array raw = py::array::ensure(object);
  if (!raw) throw InvalidArgument(what + ": not an integer array");
  // Floats would silently truncate: indices must be integers.
  if (raw.size() > 0 && raw.dtype().kind() != 'i' && raw.dtype().kind() != 'u')
    throw InvalidArgument(what + ": indices must be integers, got dtype " +
                          std::string(py::str(raw.dtype())));
  const IndexMatrix a = IndexMatrix::ensure(raw);
  checkShape(a, 3, what);
  const auto view = a.unchecked<2>();
  std::vector<Eigen::Vector3i> faces(static_cast<std::size_t>(a.shape(0)));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    for (int c = 0; c < 3; ++c) {
      const std::int64_t index = view(i, c);
      if (index < 0 || static_cast<std::uint64_t>(index) >= vertex_count)
        throw InvalidArgument(fmt::format("{}: row {} has vertex index {} outside [0, {})", what, i,
                                          index, vertex_count));
      faces[static_cast<std::size_t>(i)][c] = static_cast<int>(index);
    }
  }
  return faces;
}

std::vector<Rgb> toColours(const py::object& object, std::size_t count, const std::string& what) {
  const py::array raw = py::array::ensure(object);
  if (!raw) throw InvalidArgument(what + ": not a numeric array");
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(raw);
  checkShape(a, 3, what);
  if (static_cast<std::size_t>(a.shape(0)) != count)
    throw InvalidArgument(
        fmt::format("{}: {} rows for {} points (one colour per point)", what, a.shape(0), count));
  const auto view = a.unchecked<2>();
  std::vector<Rgb> colours(count);
  for (std::size_t i = 0; i < count; ++i) {
    for (int c = 0; c < 3; ++c) {
      const double v = view(static_cast<py::ssize_t>(i), c);
      if (!(v >= 0 && v <= 255))
        throw InvalidArgument(fmt::format("{}: row {} has {} outside [0, 255]", what, i, v));
      colours[i][static_cast<std::size_t>(c)] = static_cast<std::uint8_t>(std::lround(v));
    }
  }
  return colours;
}

Pose toPose(const py::object& object, const std::string& what) {
  const Matrix a = asDoubles(object, what);
  // parsePose does every check the CLI's --pose does (finite, distance, unit rotation, last row).
  std::string text;
  const bool matrix = a.ndim() == 2 && a.shape(0) == 4 && a.shape(1) == 4;
  const bool seven = a.ndim() == 1 && a.shape(0) == 7;
  if (!matrix && !seven)
    throw InvalidArgument(what + ": expected a 4 x 4 matrix or 7 numbers x y z qw qx qy qz");
  const double* data = a.data();
  for (py::ssize_t i = 0; i < a.size(); ++i) text += fmt::format("{:.17g} ", data[i]);
  try {
    return parsePose(text);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(what + ": " + e.what());
  }
}

Matrix fromPoints(const std::vector<Eigen::Vector3d>& points) {
  Matrix out({static_cast<py::ssize_t>(points.size()), py::ssize_t{3}});
  auto view = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int c = 0; c < 3; ++c) view(static_cast<py::ssize_t>(i), c) = points[i][c];
  return out;
}

IndexMatrix fromFaces(const std::vector<Eigen::Vector3i>& faces) {
  IndexMatrix out({static_cast<py::ssize_t>(faces.size()), py::ssize_t{3}});
  auto view = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (int c = 0; c < 3; ++c) view(static_cast<py::ssize_t>(i), c) = faces[i][c];
  return out;
}

Matrix fromPose(const Pose& pose) {
  Matrix out({py::ssize_t{4}, py::ssize_t{4}});
  auto view = out.mutable_unchecked<2>();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) view(r, c) = pose.matrix()(r, c);
  return out;
}

py::object fromJson(const nlohmann::json& j) {
  // The writers' documents are small (a plan's grasps.json is tens of kilobytes): going through
  // Python's json module keeps every number and null exactly as the files have them.
  // A handle, never released: a static py::object would be decref'd after the interpreter ended.
  static const py::handle loads = py::object(py::module_::import("json").attr("loads")).release();
  return loads(j.dump());
}

nlohmann::json SkeletonOutput::json() const {
  return skeleton::skeletonToJson(result, input.mesh, input.info);
}

py::dict jointsDict(const grasping::HandModel& hand, const Eigen::VectorXd& q) {
  py::dict joints;
  for (std::size_t j = 0; j < hand.joints().size(); ++j) {
    if (hand.joints()[j].movable() && static_cast<Eigen::Index>(j) < q.size())
      joints[py::str(hand.joints()[j].name)] = q[static_cast<Eigen::Index>(j)];
  }
  return joints;
}

ranking::RobustRankingParams robustRankingParams(
    bool robustness, int samples, const std::string& variant, std::size_t top_k,
    std::optional<std::size_t> screen_k, std::optional<int> screen_samples,
    const std::optional<std::string>& screen_by, std::optional<int> confirm_samples,
    std::optional<double> mu, std::uint64_t seed, bool refine,
    std::optional<double> refine_below_r) {
  checkSamples("robustness_samples", samples, 1);
  if (screen_samples) checkSamples("robustness_screen_samples", *screen_samples, 1);
  if (confirm_samples) checkSamples("robustness_confirm_samples", *confirm_samples, 0);
  if (refine_below_r && !(*refine_below_r >= 0 && *refine_below_r <= 1))
    throw InvalidArgument("robust_refine_below_r: must be in [0, 1]");
  if (mu && !(std::isfinite(*mu) && *mu >= 0))
    throw InvalidArgument("robustness_mu: must be finite and >= 0");
  ranking::RobustRankingParams p;
  p.enabled = robustness;
  p.robustness.samples = samples;
  p.robustness.variant = ranking::parseRobustnessVariant(variant);
  p.robustness.seed = seed;
  ranking::setLoadCheck(p.robustness, true);
  p.top_k = top_k;
  p.screen_k = screen_k;
  p.screen_samples = screen_samples;
  if (screen_by) p.screen_candidates = ranking::parseScreenCandidates(*screen_by);
  p.confirm_samples = confirm_samples;
  p.refinement.search_below_r = refine_below_r;
  p.friction = mu;
  p.refinement.enabled = refine;
  return p;
}

py::list contactsList(const std::vector<grasping::Contact>& contacts) {
  py::list out;
  for (const auto& c : contacts) {
    py::dict d;
    d["point"] = fromPoints({c.point}).attr("reshape")(3);
    d["normal"] = fromPoints({c.normal}).attr("reshape")(3);
    d["link"] = c.link;
    d["palm"] = c.palm;
    out.append(d);
  }
  return out;
}

grasping::QualityParams qualityParams(double mu, const std::string& fc_test, bool reference_compat,
                                      std::optional<double> torsional_friction) {
  checkTorsionalFriction(torsional_friction);
  grasping::QualityParams q;
  q.friction = mu;
  q.fc_test = grasping::parseForceClosureTest(fc_test);
  q.reference_compat = reference_compat;
  q.torsional_friction_m = torsional_friction;
  return q;
}

void checkSamples(const char* name, int value, int min) {
  if (value < min || static_cast<std::uint64_t>(value) > ranking::kMaxRobustnessSamples)
    throw InvalidArgument(fmt::format("{}: {} is outside [{}, {}]", name, value, min,
                                      ranking::kMaxRobustnessSamples));
}

void checkTimeout(double timeout_s) {
  if (!(std::isfinite(timeout_s) && timeout_s >= 0 && timeout_s <= ranking::kMaxPlanTimeoutS))
    throw InvalidArgument(fmt::format("timeout_s: {} is not a finite number of seconds in [0, {}]",
                                      timeout_s, ranking::kMaxPlanTimeoutS));
}

void checkTorsionalFriction(const std::optional<double>& torsional_friction) {
  if (torsional_friction && !(*torsional_friction >= 0 && std::isfinite(*torsional_friction)))
    throw InvalidArgument("torsional_friction: must be None or a finite length >= 0 (metres)");
}

}  // namespace skelgrasp::python
