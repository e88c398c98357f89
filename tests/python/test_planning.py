"""Skeleton, plan, close and score on a generated capsule: the C++ tests' invariants."""
import numpy as np
import pytest

import skelgrasp
from skelgrasp import PlanOptions

from conftest import without_timing


def is_rigid(pose):
    rotation = pose[:3, :3]
    return (pose.shape == (4, 4) and np.allclose(rotation.T @ rotation, np.eye(3), atol=1e-9)
            and np.isclose(np.linalg.det(rotation), 1.0) and np.allclose(pose[3], [0, 0, 0, 1]))


def capsule_distance(points, radius=0.03, length=0.10):
    """Distance of points from the capsule's surface (axis z, centred)."""
    z = np.clip(points[:, 2], -length / 2, length / 2)
    axis = np.stack([np.zeros_like(z), np.zeros_like(z), z], axis=1)
    return np.abs(np.linalg.norm(points - axis, axis=1) - radius)


def test_capsule_skeleton_is_one_segment_between_two_endpoints(capsule):
    s = skelgrasp.skeleton(capsule)
    assert s.ok, s.status
    assert s.vertices.dtype == np.float64 and s.vertices.shape[1] == 3
    assert s.edges.shape[1] == 2 and s.edges.min() >= 0 and s.edges.max() < len(s.vertices)
    assert s.types.count("endpoint") == 2 and s.types.count("branch") == 0
    assert len(s.segments) == 1 and 0.05 < s.segments[0]["length"] < 0.16
    # On the axis, and a tree (|E| = |V| - 1 for one component).
    assert np.all(np.linalg.norm(s.vertices[:, :2], axis=1) < 0.004)
    assert len(s.edges) == len(s.vertices) - 1
    # Every input vertex is in exactly one vertex's surface points.
    mapped = np.sort(np.concatenate(s.surface_points))
    assert np.array_equal(mapped, np.arange(len(capsule.vertices)))
    document = s.to_dict()
    assert document["schema"] == "skelgrasp.skeleton/1"
    assert document["summary"]["vertices"] == len(s.vertices)
    assert document["segments"] == s.segments


def test_decimated_skeleton_keeps_the_segment_and_maps_every_vertex(capsule):
    full = skelgrasp.skeleton(capsule)
    budget = len(full.regularised_mesh.vertices) // 3
    s = skelgrasp.skeleton(capsule, max_vertices=budget)
    assert s.ok, s.status
    assert len(s.regularised_mesh.vertices) <= budget + 1
    assert s.to_dict()["regularisation"]["decimated_from_vertices"] == len(
        full.regularised_mesh.vertices)
    assert s.types.count("endpoint") == 2 and len(s.segments) == 1
    mapped = np.sort(np.concatenate(s.surface_points))
    assert np.array_equal(mapped, np.arange(len(capsule.vertices)))
    with pytest.raises(ValueError, match="max_vertices"):
        skelgrasp.skeleton(capsule, max_vertices=3)


def test_skeleton_defaults_come_from_the_library(capsule):
    # pybind11 signatures are in the docstring; the options' defaults in their fields' docs.
    assert "alpha_divisor: float = 50.0" in skelgrasp.skeleton.__doc__
    options = PlanOptions()
    assert options.seed == 1 and "(default 1)" in PlanOptions.seed.__doc__
    assert options.quality.friction == 0.35
    assert "(default 0.35)" in skelgrasp.QualityParams.friction.__doc__


def test_plan_invariants(capsule, sdh, capsule_plan):
    result = capsule_plan
    assert result.status[0] == "ok" and 0 < len(result.grasps) <= 4
    epsilons = [g.epsilon for g in result.grasps]
    # Robust ranking: all (<= top K) scored, ranked by r, ties by epsilon.
    keys = [(g.robustness["r"], g.epsilon) for g in result.grasps]
    assert keys == sorted(keys, reverse=True)
    for g in result.grasps:
        assert is_rigid(g.hand_pose) and is_rigid(g.gcp_pose)
        assert g.force_closure and g.epsilon > 0
        assert g.type in ("power", "precision")
        assert set(g.joints) == set(sdh.joints)
        points = np.array([c["point"] for c in g.contacts])
        normals = np.array([c["normal"] for c in g.contacts])
        assert len(points) >= 2 and np.all(capsule_distance(points) < 2e-3)
        assert np.allclose(np.linalg.norm(normals, axis=1), 1.0)
        assert g.to_dict()["hand_pose"]["position"] == pytest.approx(list(g.hand_pose[:3, 3]))
    document = result.to_dict()
    assert document["schema"] == "skelgrasp.grasps/3" and document["hand"] == "sdh"
    assert document["object"] == "capsule" and document["summary"] == result.summary
    assert [g["epsilon"] for g in document["grasps"]] == epsilons
    assert result.skeleton is not None and result.skeleton.ok
    # As `skelgrasp plan` writes them: the ranking's record and the stages' times.
    ranking, timing = document["ranking"], document["timing"]
    assert ranking["scored"] == sum(g.robustness is not None for g in result.grasps)
    parts = ranking["screening_s"] + ranking["scoring_s"] + ranking["refinement_s"]
    assert 0 < parts <= timing["ranking_s"]
    assert timing["planning_s"] == result.summary["planning_s"]
    assert timing["total_s"] == pytest.approx(timing["regularise_s"] + timing["skeleton_s"]
                                              + timing["planning_s"] + timing["ranking_s"])


def ranking_options(samples, top_k=10, **ranking):
    """PlanOptions scoring `top_k` grasps with `samples` executions each, `ranking` its other
    RobustRankingParams fields."""
    options = PlanOptions(ranking=skelgrasp.RobustRankingParams(top_k=top_k, **ranking))
    options.ranking.robustness.samples = samples
    return options


def test_plan_ranking_options(capsule, sdh):
    assert PlanOptions().ranking.robustness.samples == 50
    assert "(default 50)" in skelgrasp.RobustnessParams.samples.__doc__
    options = ranking_options(10, top_k=2, friction=0.5)
    options.ranking.robustness.variant = "reference"
    result = skelgrasp.plan(capsule, sdh, options, seed=1, max_grasps=4)
    scored = [g.robustness for g in result.grasps]
    assert all(r is not None for r in scored[:2]) and all(r is None for r in scored[2:])
    for r, entry in zip(scored[:2], result.to_dict()["grasps"]):
        assert r == entry["robustness"] and r["samples"] == 10 and r["variant"] == "reference"
        assert 0 <= r["ci95"][0] <= r["r"] <= r["ci95"][1] <= 1 and r["mu"] == 0.5
        # Refinement for robustness searched near both (the best 5 scored); a found pose replaced
        # the planner's only where it held as often in the check's own samples.
        check = r["refinement"].get("check")
        if check is None:
            assert not r["refinement"]["refined"]
        else:
            after = check["holds_after"]
            assert r["refinement"]["refined"] == (after is not None
                                                  and after >= check["holds_before"])
        assert r["refinement"]["search_samples"] >= 1
    options = ranking_options(10, top_k=2)
    options.ranking.refinement.enabled = False
    unrefined = skelgrasp.plan(capsule, sdh, options, seed=1, max_grasps=4)
    assert all("refinement" not in g.robustness for g in unrefined.grasps[:2])
    plain = skelgrasp.plan(capsule, sdh, PlanOptions(ranking=skelgrasp.RobustRankingParams(
        enabled=False)), seed=1, max_grasps=4)
    epsilons = [g.epsilon for g in plain.grasps]
    assert epsilons == sorted(epsilons, reverse=True)
    assert all(g.robustness is None and "robustness" not in g.to_dict() for g in plain.grasps)
    assert plain.to_dict()["ranking"] is None
    with pytest.raises(ValueError, match="^ranking.robustness.samples: 0 is outside"):
        skelgrasp.plan(capsule, sdh, ranking_options(0))


def test_plan_ranks_with_the_hands_budget_unless_told_otherwise(capsule):
    # The Shadow hand's description sets its own ranking budget (docs/hands.md, "Ranking budget");
    # a field set overrides its part of it, None leaves it to the hand.
    shadow = skelgrasp.hand("shadow")
    own = skelgrasp.plan(capsule, shadow, ranking_options(4), seed=1, max_grasps=4)
    assert own.to_dict()["ranking"]["budget"] == {
        "screen_grasps": 40, "screen_samples": 8, "screen_by": "epsilon",
        "confirm_samples": 0, "refine_below_r": 0.5}
    options = ranking_options(4, screen_k=60, screen_samples=10, screen_by="preshapes",
                              confirm_samples=10)
    options.ranking.refinement.search_below_r = 0.7
    given = skelgrasp.plan(capsule, shadow, options, seed=1, max_grasps=4)
    assert given.to_dict()["ranking"]["budget"] == {
        "screen_grasps": 60, "screen_samples": 10, "screen_by": "preshapes",
        "confirm_samples": 10, "refine_below_r": 0.7}
    for field, bad in (("screen_samples", 0), ("confirm_samples", -1)):
        with pytest.raises(ValueError, match=f"^ranking.{field}: {bad} is outside"):
            skelgrasp.plan(capsule, shadow, ranking_options(4, **{field: bad}))
    options = ranking_options(4)
    options.ranking.refinement.search_below_r = 1.5
    with pytest.raises(ValueError, match="^ranking.refinement.search_below_r: 1.5 is not"):
        skelgrasp.plan(capsule, shadow, options)
    with pytest.raises(ValueError, match="^RobustRankingParams.screen_by: unknown"):
        options.ranking.screen_by = "random"


def test_plan_is_deterministic_for_a_seed(capsule, sdh, capsule_plan):
    again = skelgrasp.plan(capsule, sdh, seed=1, max_grasps=4)
    assert without_timing(again.to_dict()) == without_timing(capsule_plan.to_dict())


def test_surface_planner(capsule, sdh):
    options = PlanOptions(planner="surface", seed=2)
    options.surface_planner.max_hypotheses = 40
    result = skelgrasp.plan(capsule, sdh, options)
    document = result.to_dict()
    assert document["planner"] == "surface" and result.skeleton is None
    assert document["timing"]["regularise_s"] is None and document["timing"]["skeleton_s"] is None
    assert result.summary["hypotheses"] <= 40
    assert all(g.strategy == "surface" for g in result.grasps)


def test_surface_candidates_join_the_skeleton_planners_pool(capsule):
    assert PlanOptions().skeleton_planner.surface_candidates == 50
    # ARMAR-III's power grasp closes on the capsule from most surface normals (the SDH's seldom).
    armar3 = skelgrasp.hand("armar3")
    hypotheses = 30
    options = unranked()
    options.skeleton_planner.surface_candidates = hypotheses
    result = skelgrasp.plan(capsule, armar3, options, seed=1)
    options.skeleton_planner.surface_candidates = 0
    without = skelgrasp.plan(capsule, armar3, options, seed=1)
    assert result.summary["hypotheses"] == without.summary["hypotheses"] + hypotheses
    surface = [g for g in result.grasps if g.strategy == "surface"]
    assert surface and len(result.grasps) == len(without.grasps) + len(surface)


def unranked():
    """PlanOptions without the robust ranking: the planner's grasps in epsilon order."""
    return PlanOptions(ranking=skelgrasp.RobustRankingParams(enabled=False))


def test_alternative_preshapes_is_an_option_of_plan(capsule, sdh, capsule_plan):
    # The SDH's alternatives ("claw" and "lateral_power", power preshapes, "precision_tripod" and
    # "lateral_precision") are closed wherever the main preshape of their type is;
    # "narrow_tripod" only on small objects (70 mm in the SDH's description), and the capsule is
    # 160 mm long.
    assert PlanOptions().skeleton_planner.alternative_preshapes
    with_alternatives = skelgrasp.plan(capsule, sdh, unranked(), seed=1)
    options = unranked()
    options.skeleton_planner.alternative_preshapes = False
    plain = skelgrasp.plan(capsule, sdh, options, seed=1)
    options = unranked()
    options.quality.reference_compat = True
    reference = skelgrasp.plan(capsule, sdh, options, seed=1)
    grasps = with_alternatives.to_dict()["grasps"]
    lateral_power = [g for g in grasps if g["preshape"] == "lateral_power"]
    lateral_precision = [g for g in grasps if g["preshape"] == "lateral_precision"]
    claw = [g for g in grasps if g["preshape"] == "claw"]
    tripod = [g for g in grasps if g["preshape"] == "precision_tripod"]
    assert lateral_power and all(g["type"] == "power" for g in lateral_power)
    assert claw and all(g["type"] == "power" for g in claw)
    assert tripod and all(g["type"] == "precision" for g in tripod)
    assert lateral_precision and all(g["type"] == "precision" for g in lateral_precision)
    assert sdh.preshape_length_limits == {"narrow_tripod": 0.07}
    assert skelgrasp.hand("armar3").preshape_length_limits == {}
    assert not [g for g in grasps if g["preshape"] == "narrow_tripod"]
    alternatives = lateral_power + lateral_precision + claw + tripod
    assert len(with_alternatives.grasps) == len(plain.grasps) + len(alternatives)
    for result in (plain, reference):
        assert {g["preshape"] for g in result.to_dict()["grasps"]} <= {"power", "precision"}


def test_wrench_volume_is_computed_on_request_only(capsule, sdh):
    assert not PlanOptions().quality.compute_volume
    without = skelgrasp.plan(capsule, sdh, unranked(), seed=1, max_grasps=5)
    options = unranked()
    options.quality.compute_volume = True
    with_volume = skelgrasp.plan(capsule, sdh, options, seed=1, max_grasps=5)
    assert len(without.grasps) == len(with_volume.grasps) > 0
    for a, b in zip(without.grasps, with_volume.grasps):
        assert a.volume is None and b.volume > 0
        # Epsilon from subset hulls agrees with the whole hull's (both joggled by Qhull).
        assert abs(a.epsilon - b.epsilon) < 1e-7
    assert all(g["volume"] is None for g in without.to_dict()["grasps"])


def test_soft_finger_contacts_are_an_option_of_plan_and_a_keyword_of_close_and_score(capsule,
                                                                                    sdh):
    assert PlanOptions().quality.torsional_friction_m is None
    options = ranking_options(6)
    options.quality.torsional_friction_m = 0.0023
    soft = skelgrasp.plan(capsule, sdh, options, seed=5, max_grasps=3)
    scored = [g for g in soft.grasps if g.robustness is not None]
    assert scored and all(g.robustness["torsional_friction_m"] == 0.0023 for g in scored)
    # score with the same contact model gives plan's r back; point contacts never hold more
    # (the soft wrenches' hull holds the point ones').
    again = skelgrasp.score(capsule, sdh, soft, robustness_samples=6, seed=5,
                            torsional_friction=0.0023)
    point = skelgrasp.score(capsule, sdh, soft, robustness_samples=6, seed=5)
    for g, s, p in zip(soft.grasps, again, point):
        if g.robustness is not None:
            assert s["robustness"] == g.robustness["r"]
        assert s["robustness"] >= p["robustness"]
        assert s["epsilon"] >= p["epsilon"] * (1 - 1e-7) - 1e-12
        assert s["force_closure"] or not p["force_closure"]
    best = soft.grasps[0]
    closed = skelgrasp.close(capsule, sdh, best.to_dict()["preshape"], best.gcp_pose,
                             torsional_friction=0.0023)
    assert closed.epsilon == pytest.approx(best.epsilon, rel=1e-6)
    options.quality.torsional_friction_m = -0.001
    with pytest.raises(ValueError, match="^quality.torsional_friction_m: -0.001 is not"):
        skelgrasp.plan(capsule, sdh, options)


def test_contact_patch_is_an_option_of_plan_and_a_keyword_of_close_and_score(capsule, sdh):
    assert PlanOptions().closing.contact_patch == "corners"
    options = ranking_options(6)
    options.closing.contact_patch = "centre"
    centre = skelgrasp.plan(capsule, sdh, options, seed=5, max_grasps=3)
    scored = [g for g in centre.grasps if g.robustness is not None]
    assert scored and all(g.robustness["contact_patch"] == "centre" for g in scored)
    for g in centre.grasps:  # one contact per link
        links = [c["link"] for c in g.contacts]
        assert len(links) == len(set(links))
    # score with the same contact model gives plan's r back.
    again = skelgrasp.score(capsule, sdh, centre, robustness_samples=6, seed=5,
                            contact_patch="centre")
    for g, s in zip(centre.grasps, again):
        if g.robustness is not None:
            assert s["robustness"] == g.robustness["r"]
    corners = skelgrasp.plan(capsule, sdh, ranking_options(6), seed=5, max_grasps=3)
    assert all(g.robustness["contact_patch"] == "corners"
               for g in corners.grasps if g.robustness is not None)
    best = centre.grasps[0]
    closed = skelgrasp.close(capsule, sdh, best.to_dict()["preshape"], best.gcp_pose,
                             contact_patch="centre")
    assert closed.epsilon == pytest.approx(best.epsilon, rel=1e-6)
    # reference_compat judges as the reference code: one contact per link, whatever is asked.
    compat = skelgrasp.close(capsule, sdh, best.to_dict()["preshape"], best.gcp_pose,
                             reference_compat=True, contact_patch="corners")
    links = [c["link"] for c in compat.contacts]
    assert len(links) == len(set(links))
    with pytest.raises(ValueError, match="^ClosingParams.contact_patch: unknown contact patch"):
        options.closing.contact_patch = "edges"


def test_close_at_a_planned_grasp_reproduces_its_contacts(capsule, sdh, capsule_plan):
    best = capsule_plan.grasps[0]
    closed = skelgrasp.close(capsule, sdh, best.to_dict()["preshape"], best.gcp_pose)
    assert closed.closed and closed.status == "closed"
    assert np.allclose(closed.hand_pose, best.hand_pose, atol=1e-9)
    assert closed.force_closure == best.force_closure
    assert closed.epsilon == pytest.approx(best.epsilon, rel=1e-6)
    assert closed.joints == pytest.approx(best.joints)
    document = closed.to_dict()
    assert document["status"] == "closed" and document["hand"] == "sdh"


def test_close_away_from_the_object_finds_too_few_contacts(capsule, sdh):
    # The grasp centre point half a metre beside the capsule: the fingers close on nothing.
    gcp = np.eye(4)
    gcp[:3, 3] = [0.5, 0.0, 0.0]
    closed = skelgrasp.close(capsule, sdh, "power", gcp)
    assert not closed.closed and closed.status == "too_few_contacts"
    assert closed.contacts == [] and not closed.force_closure and closed.epsilon == 0
    assert closed.to_dict()["status"] == "too_few_contacts"


def test_score_recomputes_quality_and_robustness(capsule, sdh, capsule_plan):
    scores = skelgrasp.score(capsule, sdh, capsule_plan, robustness_samples=4, seed=3)
    assert len(scores) == len(capsule_plan.grasps)
    for s, g in zip(scores, capsule_plan.grasps):
        assert s["force_closure"] == g.force_closure
        assert s["epsilon"] == pytest.approx(g.epsilon, rel=1e-9)
        assert s["volume"] is None  # the whole hull only on request
        assert 0.0 <= s["robustness"] <= 1.0 and s["robustness_samples"] == 4
        low, high = s["robustness_interval"]
        assert low <= s["robustness"] <= high
        # Every failed sample has one cause; a start in collision that held after the guarded
        # approach (the default, settled variant) is no failure.
        failed = (s["robustness_collisions"] - s["robustness_guarded_holds"]
                  + s["robustness_closing_failures"] + s["robustness_no_force_closure"]
                  + s["robustness_too_weak"])
        assert failed == 4 - round(s["robustness"] * 4)
        assert 0 <= s["robustness_settled_holds"] <= round(s["robustness"] * 4)
    single = skelgrasp.score(capsule, sdh, capsule_plan.grasps[0], robustness_samples=0)
    assert single[0]["robustness"] is None
    # Higher friction never loses force closure for the same contacts.
    assert all(s["force_closure"] for s in skelgrasp.score(capsule, sdh, capsule_plan.grasps,
                                                           mu=0.8, robustness_samples=0))


def test_score_reproduces_the_r_plan_ranked_by(capsule, sdh):
    planned = skelgrasp.plan(capsule, sdh, ranking_options(6), seed=5, max_grasps=3)
    scores = skelgrasp.score(capsule, sdh, planned, robustness_samples=6, seed=5)
    scored = [(s, g) for s, g in zip(scores, planned.grasps) if g.robustness is not None]
    assert scored
    for s, g in scored:
        assert s["robustness"] == g.robustness["r"]
    # Force closure alone: the default (settled) runs the guarded variant's samples and only adds
    # holds by letting the object move; the guarded one runs the paper's and only rescues starts
    # in collision. The load check only removes holds.
    unchecked = skelgrasp.score(capsule, sdh, planned, robustness_samples=6, seed=5,
                                load_check=False)
    guarded = skelgrasp.score(capsule, sdh, planned, robustness_samples=6, seed=5,
                              robustness_variant="guarded", load_check=False)
    paper = skelgrasp.score(capsule, sdh, planned, robustness_samples=6, seed=5,
                            robustness_variant="paper")
    assert all(u["robustness"] >= gs["robustness"] >= ps["robustness"]
               for u, gs, ps in zip(unchecked, guarded, paper))
    assert all(u["robustness"] >= s["robustness"] for u, s in zip(unchecked, scores))
    with pytest.raises(ValueError, match="guarded"):
        skelgrasp.score(capsule, sdh, planned, robustness_variant="guardd")


def test_score_grasps_closes_again_at_each_mu(capsule, sdh, capsule_plan):
    doc = skelgrasp.score_grasps(capsule, sdh, capsule_plan.to_dict(), mu=[0.35, 0.5],
                                 robustness_samples=4, seed=3)
    assert doc["schema"] == "skelgrasp.score/1"
    assert len(doc["grasps"]) == len(capsule_plan.grasps)
    for s in doc["grasps"]:
        assert [c["mu"] for c in s["closure"]] == [0.35, 0.5]
        if s["closure"][0]["force_closure"]:
            assert s["closure"][1]["force_closure"]
        for c in s["closure"]:
            r = c["robustness"]
            assert r["ci95"][0] <= r["r"] <= r["ci95"][1]
    # Soft fingers hold wherever point contacts do, sample by sample, in the paper variant: the
    # same closings judged with a larger wrench cone. (Not per sample in the settled variant,
    # whose settling path itself depends on the contact model.)
    point = skelgrasp.score_grasps(capsule, sdh, capsule_plan.to_dict(), mu=[0.35],
                                   robustness_samples=4, seed=3, robustness_variant="paper")
    soft = skelgrasp.score_grasps(capsule, sdh, capsule_plan.to_dict(), mu=[0.35],
                                  robustness_samples=4, seed=3, robustness_variant="paper",
                                  torsional_friction=0.0023)
    assert soft["parameters"]["torsional_friction_m"] == 0.0023
    assert point["parameters"]["torsional_friction_m"] == 0.0  # the SDH's own: point contacts
    for s, p in zip(soft["grasps"], point["grasps"]):
        assert s["closure"][0]["robustness"]["r"] >= p["closure"][0]["robustness"]["r"]
    with pytest.raises(ValueError, match="schema"):
        skelgrasp.score_grasps(capsule, sdh, {"schema": "other/1", "grasps": []})


def test_other_hand_grasps_are_refused(capsule, capsule_plan):
    with pytest.raises(ValueError, match="planned for hand 'sdh'"):
        skelgrasp.score(capsule, skelgrasp.hand("armar3"), capsule_plan, robustness_samples=0)


def test_render(tmp_path, capsule, capsule_plan):
    skelgrasp.render_plan(str(tmp_path / "plan.png"), capsule_plan, capsule)
    skelgrasp.render_grasp(str(tmp_path / "grasp.png"), capsule_plan.grasps[0], capsule)
    for name in ("plan.png", "grasp.png"):
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
