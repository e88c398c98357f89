"""simulate(): the physics judge from Python, against the command line's `simulate`."""
import json

import pytest

import skelgrasp
from conftest import run_cli, write_ply, capsule_arrays


def test_simulate_reports_every_grasp_and_agrees_with_the_cli(tmp_path, capsule, sdh,
                                                              capsule_plan):
    doc = skelgrasp.simulate(capsule, sdh, capsule_plan, mu=[0.35, 0.5], samples=2, seed=3)
    assert doc["schema"] == "skelgrasp.simulation/1"
    assert doc["hand"] == "sdh"
    assert len(doc["grasps"]) == len(capsule_plan.grasps)
    for g in doc["grasps"]:
        assert [at["mu"] for at in g["physics"]] == [0.35, 0.5]
        for at in g["physics"]:
            nominal = at["nominal"]
            if nominal["holds"]:
                assert nominal["failed_phase"] is None
                assert len(nominal["disturbances"]) == 6
            r = at["robustness"]
            assert r["samples"] == 2
            assert r["holds"] + r["start_failures"] + r["closing_failures"] \
                + r["disturbance_failures"] == 2
    # The command line on the same grasps file executes the same grasps with the same outcomes.
    grasps = tmp_path / "grasps.json"
    grasps.write_text(json.dumps(capsule_plan.to_dict()))
    vertices, faces = capsule_arrays()
    mesh = tmp_path / "capsule.ply"
    write_ply(mesh, vertices, faces)
    out = tmp_path / "simulation.json"
    code, _, err = run_cli("simulate", grasps, mesh, "--mu", "0.35,0.5", "--samples", "2",
                           "--seed", "3", "--out", out)
    assert code == 0, err
    cli = json.loads(out.read_text())
    for ours, theirs in zip(doc["grasps"], cli["grasps"]):
        for a, b in zip(ours["physics"], theirs["physics"]):
            assert a["nominal"]["holds"] == b["nominal"]["holds"]
            assert a["nominal"]["disturbances"] == b["nominal"]["disturbances"]
            assert a["robustness"] == b["robustness"]


def test_simulate_refuses_bad_arguments(capsule, sdh, capsule_plan):
    with pytest.raises(ValueError, match="mass"):
        skelgrasp.simulate(capsule, sdh, capsule_plan, mass=0)
    with pytest.raises(ValueError, match="fingertip_force"):
        skelgrasp.simulate(capsule, sdh, capsule_plan, fingertip_force=float("nan"))
    with pytest.raises(ValueError, match="samples"):
        skelgrasp.simulate(capsule, sdh, capsule_plan, samples=-1)
