// The options objects of plan(): PlanOptions and the library's Params structs it holds, each field
// an attribute (plan_options.h). Enumerations are strings checked on assignment, counts refuse
// negative numbers on assignment, validate() checks the rest.
#include <pybind11/stl.h>

#include <fmt/format.h>

#include <algorithm>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "convert.h"
#include "plan_options.h"
#include "skelgrasp/ranking/limits.h"

namespace skelgrasp::python {
namespace {

// A bound options struct T: its fields in the order they are added, for the keyword constructor
// and __repr__; copy.copy and copy.deepcopy give independent copies.
template <typename T>
class OptionsClass {
 public:
  OptionsClass(py::module_& m, const char* name, const char* doc)
      : class_(m, name, doc), name_(name) {}

  template <typename Value>
  OptionsClass& field(const char* field, Value T::*member, const std::string& doc) {
    class_.def_readwrite(field, member, doc.c_str());
    fields_.emplace_back(field);
    return *this;
  }

  template <typename Get, typename Set>
  OptionsClass& property(const char* field, Get get, Set set, const std::string& doc) {
    class_.def_property(field, get, set, doc.c_str());
    fields_.emplace_back(field);
    return *this;
  }

  // A count >= 0 held as `Count` (std::size_t, std::uint64_t) at `access(object)`.
  template <typename Access>
  OptionsClass& count(const char* field, Access access, const std::string& doc) {
    const std::string what = name_ + "." + field;
    using Count = std::decay_t<decltype(access(std::declval<T&>()))>;
    return property(
        field, [access](T& t) { return access(t); },
        [access, what](T& t, const py::object& value) { access(t) = toCount<Count>(value, what); },
        doc);
  }

  // The same for a count that may be None (std::optional<Count>).
  template <typename Access>
  OptionsClass& optionalCount(const char* field, Access access, const std::string& doc) {
    const std::string what = name_ + "." + field;
    using Count = typename std::decay_t<decltype(access(std::declval<T&>()))>::value_type;
    return property(
        field, [access](T& t) { return access(t); },
        [access, what](T& t, const py::object& value) {
          if (value.is_none())
            access(t).reset();
          else
            access(t) = toCount<Count>(value, what);
        },
        doc);
  }

  // An enumeration at `access(object)` as its name (`Text`: a string, or one that may be None);
  // `parse` throws InvalidArgument for another name.
  template <typename Text = std::string, typename Access, typename Parse, typename Name>
  OptionsClass& choice(const char* field, Access access, Parse parse, Name name,
                       const std::string& doc) {
    const std::string what = name_ + "." + field;
    return property(
        field, [access, name](T& t) { return name(access(t)); },
        [access, parse, what](T& t, const Text& text) {
          try {
            access(t) = parse(text);
          } catch (const InvalidArgument& e) {
            throw InvalidArgument(what + ": " + e.what());
          }
        },
        doc);
  }

  // Adds the constructor T(**fields) starting from `make()`, __repr__ (`multiline`: one field per
  // line), the copies and validate().
  void finish(
      std::function<void(const T&)> validate, const std::string& validate_doc,
      bool multiline = false, std::function<T()> make = [] { return T{}; }) {
    const std::string name = name_;
    const std::vector<std::string> fields = fields_;
    class_.def(py::init([name, fields, make](const py::kwargs& kwargs) {
                 py::object self = py::cast(make());
                 for (const auto& [key, value] : kwargs) {
                   const std::string field = py::str(key);
                   if (std::find(fields.begin(), fields.end(), field) == fields.end())
                     throw py::type_error(name + "(): no field '" + field + "'");
                   self.attr(key) = value;
                 }
                 return self.cast<T>();
               }),
               ("Every field its default; keywords set fields by name: " + name + "(" +
                fields.front() + "=...).")
                   .c_str());
    class_.def("__repr__", [name, fields, multiline](const py::object& self) {
      std::string out = name + (multiline ? "(\n    " : "(");
      for (std::size_t i = 0; i < fields.size(); ++i) {
        if (i > 0) out += multiline ? ",\n    " : ", ";
        out += fields[i] + "=" + py::repr(self.attr(fields[i].c_str())).cast<std::string>();
      }
      return out + (multiline ? ",\n)" : ")");
    });
    class_.def("__copy__", [](const T& t) { return T(t); });
    class_.def(
        "__deepcopy__", [](const T& t, const py::dict&) { return T(t); }, py::arg("memo"));
    class_.def(
        "validate", [validate](const T& t) { validate(t); }, validate_doc.c_str());
  }

 private:
  py::class_<T> class_;
  std::string name_;
  std::vector<std::string> fields_;
};

const char* const kValidateDoc =
    "Raises ValueError naming the field ('<field>: <problem>', one line) for a value plan() "
    "would refuse: not finite, negative, out of its range.";

void bindQuality(py::module_& m) {
  const grasping::QualityParams defaults;
  OptionsClass<grasping::QualityParams>(m, "QualityParams", R"doc(
How a grasp's contacts are judged (``PlanOptions.quality``): friction, contact model, force-closure
test (docs/hands.md).)doc")
      .field("friction", &grasping::QualityParams::friction,
             fmt::format("Coulomb friction coefficient mu, in [0, {}] (default {}).",
                         ranking::kMaxFriction, defaults.friction))
      .field("torsional_friction_m", &grasping::QualityParams::torsional_friction_m,
             "Soft-finger contacts: torsional friction length in metres, about 2/3 mu times the "
             "pad's contact radius; 0: point contacts; None (default): the hand's own model "
             "(point contacts for the built-in hands).")
      .choice(
          "fc_test", [](grasping::QualityParams & q) -> auto& { return q.fc_test; },
          grasping::parseForceClosureTest,
          [](grasping::ForceClosureTest t) { return grasping::toString(t); },
          fmt::format("Force-closure test: 'lp' (linear program) or 'hull' (6D convex hull) "
                      "(default '{}').",
                      grasping::toString(defaults.fc_test)))
      .field("compute_volume", &grasping::QualityParams::compute_volume,
             "Also each grasp's wrench space volume (the whole 6D hull, slower; else "
             "Grasp.volume is None) (default False).")
      .field("reference_compat", &grasping::QualityParams::reference_compat,
             "Judge as the reference code (cones 45 degrees off the normal, epsilon from the hull "
             "centre; one contact per link; 'power' and 'precision' preshapes only) "
             "(default False).")
      .finish([](const grasping::QualityParams& q) { validateQuality(q, ""); }, kValidateDoc);
}

void bindClosing(py::module_& m) {
  const grasping::ClosingParams defaults;
  OptionsClass<grasping::ClosingParams>(m, "ClosingParams", R"doc(
How the fingers close on the object (``PlanOptions.closing``; docs/hands.md).)doc")
      .choice(
          "method", [](grasping::ClosingParams & c) -> auto& { return c.method; },
          grasping::parseClosingMethod,
          [](grasping::ClosingMethod method) { return grasping::toString(method); },
          fmt::format("'fast' (jumps over provably free steps) or 'stepwise' (0.02 rad steps) "
                      "(default '{}').",
                      grasping::toString(defaults.method)))
      .choice(
          "contact_patch", [](grasping::ClosingParams & c) -> auto& { return c.contact_patch; },
          grasping::parseContactPatch,
          [](grasping::ContactPatch patch) { return grasping::toString(patch); },
          fmt::format("Where a link touching over an area pushes: 'corners' (its patch's "
                      "corners) or 'centre' (its centre only, the reference's model; implied by "
                      "QualityParams.reference_compat) (default '{}').",
                      grasping::toString(defaults.contact_patch)))
      .finish([](const grasping::ClosingParams&) {}, kValidateDoc);
}

void bindSkeleton(py::module_& m) {
  using skeleton::SkeletonParams;
  const SkeletonParams defaults;
  OptionsClass<SkeletonParams>(m, "SkeletonParams", R"doc(
The skeleton stage (``PlanOptions.skeleton``): regularisation to a closed manifold, contraction,
cleanup; the keywords of :func:`skeleton` (docs/skeleton.md).)doc")
      .choice(
          "regularisation", [](SkeletonParams & s) -> auto& { return s.regularisation.method; },
          geometry::parseRegularisationMethod,
          [](geometry::RegularisationMethod method) { return geometry::toString(method); },
          fmt::format("'auto' (a clean closed manifold as it is, any other mesh wrapped), "
                      "'alpha_wrap' or 'none' (default '{}').",
                      geometry::toString(defaults.regularisation.method)))
      .property(
          "alpha_divisor", [](const SkeletonParams& s) { return s.regularisation.alpha_divisor; },
          [](SkeletonParams& s, double v) { s.regularisation.alpha_divisor = v; },
          fmt::format("Alpha = bounding box diagonal / this, > 0 (default {}).",
                      defaults.regularisation.alpha_divisor))
      .property(
          "offset_divisor", [](const SkeletonParams& s) { return s.regularisation.offset_divisor; },
          [](SkeletonParams& s, double v) { s.regularisation.offset_divisor = v; },
          fmt::format("Wrap offset = bounding box diagonal / this, > 0 (default {}).",
                      defaults.regularisation.offset_divisor))
      .property(
          "remesh_target_edge_m",
          [](const SkeletonParams& s) { return s.regularisation.remesh_target_edge_m; },
          [](SkeletonParams& s, double v) { s.regularisation.remesh_target_edge_m = v; },
          "Isotropic remeshing after wrapping to this edge length in metres; 0 (default): off.")
      .optionalCount(
          "max_vertices", [](SkeletonParams & s) -> auto& { return s.regularisation.max_vertices; },
          fmt::format("Simplify a larger closed mesh to about this many vertices before the "
                      "contraction, at least 4; None: never (default {}).",
                      defaults.regularisation.max_vertices.value_or(0)))
      .field("spur_radius_factor", &SkeletonParams::spur_radius_factor,
             fmt::format("Prune terminal branches shorter than this times the local radius; 0: "
                         "off (default {}).",
                         defaults.spur_radius_factor))
      .property(
          "curvature_stencil_m",
          [](const SkeletonParams& s) { return s.graph.curvature_stencil_m; },
          [](SkeletonParams& s, double v) { s.graph.curvature_stencil_m = v; },
          fmt::format("Arc length in metres over which the skeleton's curvature is "
                      "differentiated (default {}).",
                      defaults.graph.curvature_stencil_m))
      .finish([](const SkeletonParams& s) { validateSkeleton(s, ""); }, kValidateDoc);
}

void bindPlanners(py::module_& m) {
  using grasping::SkeletonPlannerParams;
  const SkeletonPlannerParams defaults;
  OptionsClass<SkeletonPlannerParams>(m, "SkeletonPlannerParams", R"doc(
The skeleton planner (``PlanOptions.skeleton_planner``; paper Alg. 1, docs/planning.md). Its time
and grasp limits, seed and hypothesis settings are PlanOptions'.)doc")
      .field("vertex_distance_m", &SkeletonPlannerParams::vertex_distance_m,
             "Visit skeleton vertices at least this far apart, in metres; 0 (default): every "
             "vertex.")
      .field("round_ratio", &SkeletonPlannerParams::round_ratio,
             fmt::format("lambda1/lambda2 below this is a round section; None (default): the "
                         "hand's ({} for the built-in hands).",
                         grasping::PlannerThresholds{}.round_ratio))
      .field("fallback", &SkeletonPlannerParams::fallback,
             "Fallback strategies for objects whose skeleton gives few grasps; False: the "
             "skeleton strategies only, as the paper (default True).")
      .field("centre_candidates", &SkeletonPlannerParams::centre_candidates,
             "Also try power and precision grasps about the object's centre on every object, the "
             "robust grasps the ranking chooses from (default True).")
      .count(
          "surface_candidates",
          [](SkeletonPlannerParams & p) -> auto& { return p.surface_candidates; },
          fmt::format("Surface-normal hypotheses added to the pool the ranking chooses from; 0: "
                      "none (default {}).",
                      defaults.surface_candidates))
      .field("alternative_preshapes", &SkeletonPlannerParams::alternative_preshapes,
             "Also close every pose with the hand's alternative preshapes of its grasp type (the "
             "SDH's tripods and lateral grips; docs/hands.md); False or "
             "QualityParams.reference_compat: 'power' and 'precision' only (default True).")
      .field("precision_retreat_m", &SkeletonPlannerParams::precision_retreat_m,
             "Back precision grasps' open hand off this much further than the first "
             "collision-free pose, in metres; 0 (default): as the paper.")
      .property(
          "refine", [](const SkeletonPlannerParams& p) { return p.refinement.enabled; },
          [](SkeletonPlannerParams& p, bool v) { p.refinement.enabled = v; },
          "Local refinement of every closed hypothesis (8-12x slower planning) (default False).")
      .property(
          "refine_evaluations",
          [](const SkeletonPlannerParams& p) { return p.refinement.max_evaluations; },
          [](SkeletonPlannerParams& p, int v) { p.refinement.max_evaluations = v; },
          fmt::format("Poses local refinement tries around each closed hypothesis, >= 0 "
                      "(default {}).",
                      defaults.refinement.max_evaluations))
      .finish([](const SkeletonPlannerParams& p) { validateSkeletonPlanner(p, ""); }, kValidateDoc);

  using grasping::SurfacePlannerParams;
  OptionsClass<SurfacePlannerParams>(m, "SurfacePlannerParams", R"doc(
The surface-normal baseline planner (``PlanOptions.surface_planner``, planner 'surface'). Its time
and grasp limits, seed and hypothesis settings are PlanOptions'.)doc")
      .count(
          "max_hypotheses", [](SurfacePlannerParams & p) -> auto& { return p.max_hypotheses; },
          fmt::format("Hypotheses sampled; 0: until PlanOptions.timeout_s (default {}).",
                      SurfacePlannerParams{}.max_hypotheses))
      .finish([](const SurfacePlannerParams&) {}, kValidateDoc);
}

void bindRanking(py::module_& m) {
  using ranking::RobustnessParams;
  const ranking::RobustRankingParams defaults;
  OptionsClass<RobustnessParams>(m, "RobustnessParams", R"doc(
How a grasp's robustness r is measured (``PlanOptions.ranking.robustness``; docs/ranking.md). Its
samples are seeded by PlanOptions.seed.)doc")
      .field("samples", &RobustnessParams::samples,
             fmt::format("Perturbed executions per scored grasp, in [1, {}] (default {}).",
                         ranking::kMaxRobustnessSamples, defaults.robustness.samples))
      .choice(
          "variant", [](RobustnessParams & p) -> auto& { return p.variant; },
          ranking::parseRobustnessVariant,
          [](ranking::RobustnessVariant v) { return ranking::toString(v); },
          fmt::format("'paper' (hand moved, 10 mm / 5 deg), 'guarded' (a start in collision "
                      "backs off along the approach), 'settled' (guarded, the object free to "
                      "settle) or 'reference' (object moved, 5 mm / 2.5 deg) (default '{}').",
                      ranking::toString(defaults.robustness.variant)))
      .property(
          "load_check", [](const RobustnessParams& p) { return p.load.has_value(); },
          [](RobustnessParams& p, bool wanted) {
            p.load = wanted ? std::optional(ranking::defaultLoadCheck()) : std::nullopt;
          },
          "A sample holds only when its grip also carries the object's weight; the 'paper' and "
          "'reference' variants never check it (default True).")
      // The ranking's robustness (50 samples, the load check), not RobustnessParams{}'s.
      .finish([](const RobustnessParams& p) { validateRobustness(p, ""); }, kValidateDoc, false,
              ranking::defaultRankingRobustness);

  using ranking::RobustRefinementParams;
  OptionsClass<RobustRefinementParams>(m, "RobustRefinementParams", R"doc(
Refinement for robustness (``PlanOptions.ranking.refinement``): the most robust scored grasps'
neighbourhoods searched for more robust poses (docs/ranking.md).)doc")
      .field("enabled", &RobustRefinementParams::enabled,
             "False: the planner's poses are returned (default True).")
      .count(
          "max_grasps", [](RobustRefinementParams & p) -> auto& { return p.max_grasps; },
          fmt::format("Scored grasps searched, the most robust first; 0: all (default {}).",
                      defaults.refinement.max_grasps))
      .field("search_below_r", &RobustRefinementParams::search_below_r,
             fmt::format("Only grasps whose r is below this, in [0, 1], are searched; None "
                         "(default): the hand's ranking budget, else {}.",
                         ranking::kDefaultSearchBelowR))
      .field("max_evaluations", &RobustRefinementParams::max_evaluations,
             fmt::format("Poses tried near each searched grasp, >= 0 (default {}).",
                         defaults.refinement.max_evaluations))
      .field("samples", &RobustRefinementParams::samples,
             fmt::format("Perturbed executions per pose tried, >= 1 (default {}).",
                         defaults.refinement.samples))
      .field("max_standoff_m", &RobustRefinementParams::max_standoff_m,
             fmt::format("Farthest the search backs a grasp off or moves it closer, in metres "
                         "(default {}).",
                         defaults.refinement.max_standoff_m))
      .field("mean_shift_steps", &RobustRefinementParams::mean_shift_steps,
             fmt::format("Steps moving the best pose towards where its executions held, >= 0 "
                         "(default {}).",
                         defaults.refinement.mean_shift_steps))
      .finish([](const RobustRefinementParams& p) { validateRobustRefinement(p, ""); },
              kValidateDoc);

  using ranking::RobustRankingParams;
  OptionsClass<RobustRankingParams>(m, "RobustRankingParams", R"doc(
The robust ranking (``PlanOptions.ranking``; docs/ranking.md): screen_k grasps get a cheap r from
screen_samples executions, the best 2 x top_k of them confirm_samples more, the best top_k a
robustness r from robustness.samples, and those lead, ranked by r. None: the hand's ranking
budget (docs/hands.md), else the library's default.)doc")
      .field("enabled", &RobustRankingParams::enabled,
             "False: the grasps keep the planner's epsilon order and get no r (default True).")
      .count(
          "top_k", [](RobustRankingParams & p) -> auto& { return p.top_k; },
          fmt::format("Grasps scored for robustness; 0: all (default {}).", defaults.top_k))
      .optionalCount(
          "screen_k", [](RobustRankingParams & p) -> auto& { return p.screen_k; },
          fmt::format("Grasps screened; 0: all; None (default): the hand's, else {}.",
                      ranking::kDefaultScreenK))
      .field("screen_samples", &RobustRankingParams::screen_samples,
             fmt::format("Executions per screened grasp, >= 1; None (default): the hand's, "
                         "else {}.",
                         ranking::kDefaultScreenSamples))
      .choice<std::optional<std::string>>(
          "screen_by", [](RobustRankingParams & p) -> auto& { return p.screen_candidates; },
          [](const std::optional<std::string>& text) -> std::optional<ranking::ScreenCandidates> {
            if (!text) return std::nullopt;
            return ranking::parseScreenCandidates(*text);
          },
          [](const std::optional<ranking::ScreenCandidates>& candidates)
              -> std::optional<std::string> {
            if (!candidates) return std::nullopt;
            return std::string(ranking::toString(*candidates));
          },
          fmt::format("Which grasps are screened: 'preshapes' (each preshape's best by epsilon "
                      "in turn), 'travel' (each preshape's by least finger travel in turn) or "
                      "'epsilon' (the best over all); None (default): the hand's, else '{}'.",
                      ranking::toString(ranking::kDefaultScreenCandidates)))
      .field("confirm_samples", &RobustRankingParams::confirm_samples,
             fmt::format("More executions for the best 2 x top_k screened grasps, >= 0; None "
                         "(default): the hand's, else {}.",
                         ranking::kDefaultConfirmSamples))
      .field("friction", &RobustRankingParams::friction,
             "Friction coefficient of r; None (default): PlanOptions.quality.friction.")
      .field("robustness", &RobustRankingParams::robustness, "RobustnessParams: how r is measured.")
      .field("refinement", &RobustRankingParams::refinement,
             "RobustRefinementParams: the search for more robust poses.")
      .finish([](const RobustRankingParams& p) { validateRobustRanking(p, ""); }, kValidateDoc);
}

void bindPlanOptions(py::module_& m) {
  const PlanOptions defaults;
  OptionsClass<PlanOptions>(m, "PlanOptions", R"doc(
Everything :func:`plan` can be told (``skelgrasp plan``'s options; docs/python.md). Every default
is the library's; the time limit is the library's 0 (none), not the command line's 30 s::

    options = skelgrasp.PlanOptions(seed=2, timeout_s=30)
    options.ranking.robustness.samples = 100
    options.quality.friction = 0.5
    skelgrasp.plan(mesh, hand, options))doc")
      .choice(
          "planner", [](PlanOptions & o) -> auto& { return o.planner; }, ranking::parsePlanner,
          [](ranking::Planner p) { return ranking::toString(p); },
          "'skeleton' (default; paper Alg. 1) or 'surface' (the surface-normal baseline).")
      .count(
          "seed", [](PlanOptions & o) -> auto& { return o.seed; },
          fmt::format("Seeds the planner and the robustness samples; a plan is deterministic for "
                      "it (default {}).",
                      defaults.seed))
      .field("timeout_s", &PlanOptions::timeout_s,
             "Planning time limit in seconds; 0 (default): none.")
      .count(
          "max_grasps", [](PlanOptions & o) -> auto& { return o.max_grasps; },
          "Stop planning after this many grasps; 0 (default): no limit.")
      .field("min_epsilon", &PlanOptions::min_epsilon,
             "Reject grasps with a lower epsilon, >= 0 (default 0).")
      .field("quality", &PlanOptions::quality, "QualityParams: friction and contact model.")
      .field("closing", &PlanOptions::closing, "ClosingParams: how the fingers close.")
      .field("skeleton", &PlanOptions::skeleton, "SkeletonParams: the skeleton stage.")
      .field("skeleton_planner", &PlanOptions::skeleton_planner,
             "SkeletonPlannerParams: the skeleton planner's strategies.")
      .field("surface_planner", &PlanOptions::surface_planner,
             "SurfacePlannerParams: the surface planner's hypotheses.")
      .field("ranking", &PlanOptions::ranking, "RobustRankingParams: the robust ranking.")
      .finish([](const PlanOptions& o) { o.validate(); },
              std::string(kValidateDoc) + " plan() calls it.", true);
}

}  // namespace

void bindOptions(py::module_& m) {
  bindQuality(m);
  bindClosing(m);
  bindSkeleton(m);
  bindPlanners(m);
  bindRanking(m);
  bindPlanOptions(m);
}

}  // namespace skelgrasp::python
