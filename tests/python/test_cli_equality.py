"""The Python module and the CLI give the same results for the same input and seed."""
import json

import numpy as np

import skelgrasp

from conftest import capsule_arrays, run_cli, without_timing, write_ply, ycb_mesh_path


def plan_cli(tmp_path, mesh_path, hand, *options):
    """`skelgrasp plan` without a time limit, as Python plans; its grasps.json without timings."""
    out = tmp_path / "grasps.json"
    code, _, stderr = run_cli("plan", mesh_path, "--hand", hand, "--timeout", 0, "--out", out,
                              "-q", *options)
    assert code == 0, stderr
    return without_timing(json.loads(out.read_text()))


def plan_both(tmp_path, mesh_path, hand, seed, max_grasps):
    cli = plan_cli(tmp_path, mesh_path, hand, "--seed", seed, "--max-grasps", max_grasps)
    python = skelgrasp.plan(skelgrasp.load_mesh(str(mesh_path)), skelgrasp.hand(hand), seed=seed,
                            max_grasps=max_grasps).to_dict()
    return cli, without_timing(python)


def test_plan_on_a_generated_capsule_equals_the_cli(tmp_path):
    path = tmp_path / "capsule.ply"
    write_ply(path, *capsule_arrays())
    cli, python = plan_both(tmp_path, path, "sdh", 7, 3)
    assert cli["grasps"], "the capsule should have grasps"
    assert python == cli


def test_nested_options_change_what_their_cli_options_change(tmp_path):
    path = tmp_path / "capsule.ply"
    write_ply(path, *capsule_arrays())
    options = skelgrasp.PlanOptions(seed=7, max_grasps=3)
    options.quality.friction = 0.5
    options.ranking.robustness.samples = 10
    options.ranking.robustness.variant = "paper"
    options.skeleton_planner.surface_candidates = 0
    python = skelgrasp.plan(skelgrasp.load_mesh(str(path)), skelgrasp.hand("sdh"), options)
    cli = plan_cli(tmp_path, path, "sdh", "--seed", 7, "--max-grasps", 3, "--mu", 0.5,
                   "--robustness-samples", 10, "--robustness-variant", "paper",
                   "--surface-candidates", 0)
    assert without_timing(python.to_dict()) == cli
    scored = [g.robustness for g in python.grasps if g.robustness is not None]
    assert scored and all((r["samples"], r["variant"], r["mu"]) == (10, "paper", 0.5)
                          for r in scored)
    default, _ = plan_both(tmp_path, path, "sdh", 7, 3)
    assert default != cli


def test_plan_on_a_ycb_mesh_equals_the_cli(tmp_path):
    cli, python = plan_both(tmp_path, ycb_mesh_path(), "armar3", 2, 2)
    assert python == cli


def test_close_equals_the_cli(tmp_path):
    path = tmp_path / "capsule.ply"
    write_ply(path, *capsule_arrays())
    mesh = skelgrasp.load_mesh(str(path))
    gcp = np.eye(4)
    gcp[:3, :3] = [[0, 0, -1], [0, 1, 0], [1, 0, 0]]  # approach along -x
    gcp[:3, 3] = [0.03, 0.0, 0.0]
    python = skelgrasp.close(mesh, skelgrasp.hand("sdh"), "power", gcp).to_dict()
    pose = " ".join(repr(float(x)) for x in gcp.flatten())
    code, stdout, stderr = run_cli("close", path, "--hand", "sdh", "--preshape", "power",
                                   "--pose", pose, "--json", "-q")
    assert code == 0, stderr
    assert python == json.loads(stdout)
