"""The Python module and the CLI give the same results for the same input and seed."""
import json

import numpy as np

import skelgrasp

from conftest import capsule_arrays, run_cli, without_timing, write_ply, ycb_mesh_path


def plan_both(tmp_path, mesh_path, hand, seed, max_grasps):
    out = tmp_path / "grasps.json"
    code, _, stderr = run_cli("plan", mesh_path, "--hand", hand, "--seed", seed, "--timeout", 0,
                              "--max-grasps", max_grasps, "--out", out, "-q")
    assert code == 0, stderr
    cli = json.loads(out.read_text())
    python = skelgrasp.plan(skelgrasp.load_mesh(str(mesh_path)), skelgrasp.hand(hand), seed=seed,
                            max_grasps=max_grasps).to_dict()
    return without_timing(cli), without_timing(python)


def test_plan_on_a_generated_capsule_equals_the_cli(tmp_path):
    path = tmp_path / "capsule.ply"
    write_ply(path, *capsule_arrays())
    cli, python = plan_both(tmp_path, path, "sdh", 7, 3)
    assert cli["grasps"], "the capsule should have grasps"
    assert python == cli


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
