"""plan()'s options objects: their fields round-trip, validate() names the field it refuses, the
keyword shortcuts override the fields, and no options plan what the default options plan."""
import copy
import math

import pytest

import skelgrasp
from skelgrasp import PlanOptions

from conftest import without_timing

# A value other than the default for every field of every options class (PlanOptions: its own
# fields; the groups it holds are classes of their own here).
NON_DEFAULT = {
    "PlanOptions": {"planner": "surface", "seed": 7, "timeout_s": 12.5, "max_grasps": 3,
                    "min_epsilon": 0.01},
    "QualityParams": {"friction": 0.6, "torsional_friction_m": 0.002, "fc_test": "hull",
                      "compute_volume": True, "reference_compat": True},
    "ClosingParams": {"method": "stepwise", "contact_patch": "centre"},
    "SkeletonParams": {"regularisation": "alpha_wrap", "alpha_divisor": 40.0,
                       "offset_divisor": 300.0, "remesh_target_edge_m": 0.002,
                       "max_vertices": None, "spur_radius_factor": 1.5,
                       "curvature_stencil_m": 0.01},
    "SkeletonPlannerParams": {"vertex_distance_m": 0.01, "round_ratio": 1.5, "fallback": False,
                              "centre_candidates": False, "surface_candidates": 0,
                              "alternative_preshapes": False, "precision_retreat_m": 0.008,
                              "refine": True, "refine_evaluations": 3},
    "SurfacePlannerParams": {"max_hypotheses": 40},
    "RobustnessParams": {"samples": 10, "variant": "paper", "load_check": False},
    "RobustRefinementParams": {"enabled": False, "max_grasps": 2, "search_below_r": 0.9,
                               "max_evaluations": 2, "samples": 6, "max_standoff_m": 0.01,
                               "mean_shift_steps": 0},
    "RobustRankingParams": {"enabled": False, "top_k": 3, "screen_k": 20, "screen_samples": 5,
                            "screen_by": "travel", "confirm_samples": 0, "friction": 0.5},
}
# The fields that hold another options object.
NESTED = {
    "PlanOptions": {"quality": "QualityParams", "closing": "ClosingParams",
                    "skeleton": "SkeletonParams", "skeleton_planner": "SkeletonPlannerParams",
                    "surface_planner": "SurfacePlannerParams", "ranking": "RobustRankingParams"},
    "RobustRankingParams": {"robustness": "RobustnessParams",
                            "refinement": "RobustRefinementParams"},
}


def fields_of(cls):
    return {name for name, value in vars(cls).items() if isinstance(value, property)}


@pytest.mark.parametrize("name", sorted(NON_DEFAULT))
def test_every_field_round_trips(name):
    cls = getattr(skelgrasp, name)
    changes = NON_DEFAULT[name]
    assert fields_of(cls) == set(changes) | set(NESTED.get(name, {})), "a field without a test"
    assert all(getattr(cls(), field) != value for field, value in changes.items())
    assigned = cls()
    for field, value in changes.items():
        setattr(assigned, field, value)
    for options in (cls(**changes), assigned):
        for field, value in changes.items():
            assert getattr(options, field) == value
            assert f"{field}={value!r}" in repr(options)
        assert repr(options).startswith(name + "(")
        options.validate()
        assert not hasattr(options, "__dict__")  # a mistyped field is an error, not a new one
        with pytest.raises(AttributeError):
            options.no_such_field = 1
    with pytest.raises(TypeError, match=f"{name}\\(\\): no field 'no_such_field'"):
        cls(no_such_field=1)
    for field, group in NESTED.get(name, {}).items():
        assert type(getattr(cls(), field)).__name__ == group


def test_nested_groups_are_edited_in_place_and_copied_on_assignment():
    options = PlanOptions()
    options.ranking.robustness.samples = 7  # through the attribute: the options' own group
    assert options.ranking.robustness.samples == 7
    robustness = skelgrasp.RobustnessParams(samples=9)
    options.ranking.robustness = robustness  # assigned: a copy
    robustness.samples = 11
    assert options.ranking.robustness.samples == 9
    copied = copy.deepcopy(options)
    copied.ranking.robustness.samples = 3
    copied.quality.friction = 0.8
    assert options.ranking.robustness.samples == 9 and options.quality.friction == 0.35
    assert copy.copy(options).ranking.robustness.samples == 9
    assert "ranking=RobustRankingParams(" in repr(options) and "samples=9" in repr(options)


def test_defaults_are_the_librarys():
    options = PlanOptions()
    assert (options.planner, options.seed, options.timeout_s, options.max_grasps) == (
        "skeleton", 1, 0.0, 0)
    assert options.quality.friction == 0.35 and options.quality.torsional_friction_m is None
    assert options.ranking.enabled and options.ranking.top_k == 10
    assert options.ranking.screen_k is None and options.ranking.screen_by is None
    assert options.ranking.robustness.variant == "settled" and options.ranking.robustness.load_check
    assert options.surface_planner.max_hypotheses == 500
    assert "(default 500)" in skelgrasp.SurfacePlannerParams.max_hypotheses.__doc__


NAN, INF = math.nan, math.inf
# (field path below PlanOptions, value, how the problem validate() reports begins).
REFUSED = [
    ("timeout_s", NAN, "nan is not a finite number of seconds in [0, 1000000]"),
    ("timeout_s", -1.0, "-1 is not a finite number of seconds"),
    ("min_epsilon", -0.1, "-0.1 is not a finite number >= 0"),
    ("quality.friction", 11.0, "11 is not a finite number in [0, 10]"),
    ("quality.friction", NAN, "nan is not a finite number in [0, 10]"),
    ("quality.torsional_friction_m", -0.001, "-0.001 is not a finite number >= 0"),
    ("skeleton.alpha_divisor", 0.0, "0 is not a finite number > 0"),
    ("skeleton.offset_divisor", INF, "inf is not a finite number > 0"),
    ("skeleton.remesh_target_edge_m", -0.001, "-0.001 is not a finite number >= 0"),
    ("skeleton.max_vertices", 3, "3 is below the 4 vertices of a closed mesh"),
    ("skeleton.spur_radius_factor", NAN, "nan is not a finite number >= 0"),
    ("skeleton.curvature_stencil_m", -1.0, "-1 is not a finite number >= 0"),
    ("skeleton_planner.vertex_distance_m", -0.01, "-0.01 is not a finite number >= 0"),
    ("skeleton_planner.round_ratio", INF, "inf is not a finite number >= 0"),
    ("skeleton_planner.precision_retreat_m", NAN, "nan is not a finite number >= 0"),
    ("skeleton_planner.refine_evaluations", -1, "-1 is negative"),
    ("ranking.screen_samples", 0, "0 is outside [1, 1000000]"),
    ("ranking.confirm_samples", -1, "-1 is outside [0, 1000000]"),
    ("ranking.friction", 10.5, "10.5 is not a finite number in [0, 10]"),
    ("ranking.robustness.samples", 0, "0 is outside [1, 1000000]"),
    ("ranking.robustness.samples", 10**6 + 1, "1000001 is outside [1, 1000000]"),
    ("ranking.refinement.search_below_r", 1.5, "1.5 is not a finite number in [0, 1]"),
    ("ranking.refinement.max_evaluations", -1, "-1 is outside [0, 1000000]"),
    ("ranking.refinement.samples", 0, "0 is outside [1, 1000000]"),
    ("ranking.refinement.max_standoff_m", NAN, "nan is not a finite number >= 0"),
    ("ranking.refinement.mean_shift_steps", -1, "-1 is outside [0, 1000000]"),
]


def with_value(path, value):
    """PlanOptions with the field at `path` set to `value`, and the group holding it."""
    options = PlanOptions()
    *groups, field = path.split(".")
    group = options
    for name in groups:
        group = getattr(group, name)
    setattr(group, field, value)
    return options, group


@pytest.mark.parametrize("path, value, problem", REFUSED, ids=[r[0] for r in REFUSED])
def test_validate_names_the_field_it_refuses(capsule, sdh, path, value, problem):
    options, group = with_value(path, value)
    with pytest.raises(ValueError) as error:
        options.validate()
    message = str(error.value)
    assert message.startswith(f"{path}: {problem}") and "\n" not in message
    # The group alone names the field within it; plan() refuses before any work.
    if group is not options:
        with pytest.raises(ValueError) as error:
            group.validate()
        assert str(error.value) == message[message.rindex(".", 0, len(path)) + 1:]
    with pytest.raises(ValueError, match=f"^{path}: "):
        skelgrasp.plan(capsule, sdh, options)


def test_assignment_refuses_unknown_names_and_negative_counts():
    options = PlanOptions()
    with pytest.raises(ValueError, match="^PlanOptions.max_grasps: -1 is negative"):
        options.max_grasps = -1
    with pytest.raises(ValueError, match="^RobustRankingParams.screen_k: -5 is negative"):
        options.ranking.screen_k = -5
    with pytest.raises(TypeError, match="^PlanOptions.seed: expected a whole number, got float"):
        options.seed = 1.5
    with pytest.raises(ValueError, match="^RobustnessParams.variant: unknown robustness variant"):
        options.ranking.robustness.variant = "gentle"
    with pytest.raises(ValueError, match="^SkeletonParams.regularisation: unknown"):
        options.skeleton.regularisation = "smooth"
    with pytest.raises(ValueError, match="^ClosingParams.method: unknown closing method"):
        options.closing.method = "slow"
    assert options.max_grasps == 0 and options.ranking.screen_k is None  # unchanged
    options.ranking.screen_k = 0  # 0: all
    assert options.ranking.screen_k == 0


def test_the_surface_planner_needs_hypotheses_or_a_time_limit():
    options = PlanOptions(planner="surface")
    options.surface_planner.max_hypotheses = 0
    with pytest.raises(ValueError, match=r"^surface_planner.max_hypotheses: 0 \(until the time "):
        options.validate()
    options.timeout_s = 5
    options.validate()


def test_plan_without_options_is_plan_with_the_default_options(capsule, sdh):
    implicit = skelgrasp.plan(capsule, sdh)
    explicit = skelgrasp.plan(capsule, sdh, PlanOptions())
    assert implicit.grasps and implicit.status[0] == "ok"
    assert without_timing(implicit.to_dict()) == without_timing(explicit.to_dict())


def test_shortcuts_override_the_options_fields(capsule, sdh):
    options = PlanOptions(seed=3, max_grasps=2, timeout_s=NAN)
    options.ranking.robustness.samples = 4
    shortcut = skelgrasp.plan(capsule, sdh, options, seed=1, max_grasps=4, timeout_s=0, mu=0.5)
    explicit = copy.deepcopy(options)
    explicit.seed, explicit.max_grasps, explicit.timeout_s = 1, 4, 0
    explicit.quality.friction = 0.5
    planned = without_timing(shortcut.to_dict())
    assert planned == without_timing(skelgrasp.plan(capsule, sdh, explicit).to_dict())
    assert all(g.robustness["mu"] == 0.5 for g in shortcut.grasps if g.robustness)
    # The caller's options are left as they were, and the shortcuts did change the plan.
    assert (options.seed, options.max_grasps, options.quality.friction) == (3, 2, 0.35)
    options.timeout_s = 0
    assert without_timing(skelgrasp.plan(capsule, sdh, options).to_dict()) != planned
