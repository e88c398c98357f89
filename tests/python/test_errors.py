"""Every error path raises the right exception with the message the CLI prints, and nothing
crashes the interpreter."""
import json

import numpy as np
import pytest

import skelgrasp

from conftest import cli_error, run_cli, write_ply


def test_missing_mesh_is_file_not_found_with_the_cli_message(tmp_path, sdh):
    path = str(tmp_path / "missing.ply")
    with pytest.raises(FileNotFoundError) as error:
        skelgrasp.load_mesh(path)
    assert str(error.value) == f"{path}: no such file"
    code, _, stderr = run_cli("plan", path, "--hand", "sdh", "--out", tmp_path / "g.json")
    assert code == 2 and cli_error(stderr) == str(error.value)


def test_malformed_mesh_is_os_error_with_the_cli_message(tmp_path):
    path = tmp_path / "broken.ply"
    path.write_text("ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n")
    with pytest.raises(OSError) as error:
        skelgrasp.load_mesh(str(path))
    assert not isinstance(error.value, FileNotFoundError)
    assert str(error.value).startswith(f"{path}: ")
    code, _, stderr = run_cli("plan", path, "--hand", "sdh", "--out", tmp_path / "g.json")
    assert code == 2 and cli_error(stderr) == str(error.value)


def test_nan_vertex_in_a_file_is_os_error(tmp_path):
    path = tmp_path / "nan.ply"
    write_ply(path, [[0, 0, 0], [1, 0, float("nan")], [0, 1, 0]], [[0, 1, 2]])
    with pytest.raises(OSError) as error:
        skelgrasp.load_mesh(str(path))
    code, _, stderr = run_cli("plan", path, "--hand", "sdh", "--out", tmp_path / "g.json")
    assert code == 2 and cli_error(stderr) == str(error.value)


def test_unknown_units_is_value_error():
    with pytest.raises(ValueError):
        skelgrasp.load_mesh("whatever.ply", units="inch")


def test_missing_cloud_is_file_not_found(tmp_path):
    path = str(tmp_path / "missing.pcd")
    with pytest.raises(FileNotFoundError) as error:
        skelgrasp.load_cloud(path)
    code, _, stderr = run_cli("run", path, "--out", tmp_path / "out")
    assert code == 2 and cli_error(stderr) == str(error.value)


def test_unknown_hand_is_value_error_with_the_cli_message(tmp_path):
    with pytest.raises(ValueError) as error:
        skelgrasp.hand("robotiq")
    assert "unknown hand 'robotiq'" in str(error.value) and "sdh" in str(error.value)
    code, _, stderr = run_cli("hands")  # the list the message names
    assert code == 0
    code, _, stderr = run_cli("plan", tmp_path / "x.ply", "--hand", "robotiq", "--out",
                              tmp_path / "g.json")
    assert code == 2 and cli_error(stderr) == str(error.value)


def test_missing_hand_files(tmp_path):
    with pytest.raises(FileNotFoundError):
        skelgrasp.load_hand(str(tmp_path / "hand.urdf"), str(tmp_path / "hand.grasp.json"))


def test_bad_planner_preshape_and_pose(capsule, sdh):
    with pytest.raises(ValueError, match="^PlanOptions.planner: unknown planner 'magic'"):
        skelgrasp.PlanOptions(planner="magic")
    with pytest.raises(ValueError, match="fist"):
        skelgrasp.close(capsule, sdh, "fist", np.eye(4))
    with pytest.raises(ValueError, match="gcp_pose: expected a 4 x 4 matrix"):
        skelgrasp.close(capsule, sdh, "power", np.eye(3))
    skewed = np.eye(4)
    skewed[0, 1] = 0.5
    with pytest.raises(ValueError, match="gcp_pose: "):
        skelgrasp.close(capsule, sdh, "power", skewed)
    with pytest.raises(ValueError, match="gcp_pose: "):
        skelgrasp.close(capsule, sdh, "power", np.full((4, 4), np.nan))
    with pytest.raises(ValueError, match="^QualityParams.fc_test: unknown force-closure test"):
        skelgrasp.QualityParams(fc_test="guess")
    with pytest.raises(ValueError):
        skelgrasp.score(capsule, sdh, "not grasps")
    with pytest.raises(TypeError):
        skelgrasp.plan("mesh.ply", sdh)
    with pytest.raises(TypeError):  # the planner is an option, not an argument
        skelgrasp.plan(capsule, sdh, "surface")


def test_flat_mesh_the_skeleton_cannot_process_is_value_error(sdh):
    # Two triangles: no volume to wrap into a skeleton worth planning on, or a planner result
    # without grasps; either way no crash.
    vertices = np.array([[0, 0, 0], [0.1, 0, 0], [0, 0.1, 0], [0.1, 0.1, 0]], dtype=float)
    mesh = skelgrasp.Mesh(vertices, [[0, 1, 2], [1, 3, 2]])
    try:
        result = skelgrasp.plan(mesh, sdh, max_grasps=1, timeout_s=5)
    except ValueError as error:
        assert str(error).startswith("mesh: ")
    else:
        assert result.status[0] in ("ok", "no_result")


def test_bad_log_level():
    with pytest.raises(ValueError):
        skelgrasp.set_log_level("loud")
    skelgrasp.set_log_level("warn")


def test_mesh_without_area_is_value_error_not_a_crash(sdh):
    # Ten faces that repeat one vertex, and one face on a line: the alpha wrap used to kill the
    # interpreter (SIGSEGV); the skeleton stage refuses them first.
    rng = np.random.default_rng(7)
    vertices = rng.uniform(-0.05, 0.05, size=(10, 3))
    for faces in (np.zeros((10, 3), dtype=np.int64), [[0, 1, 2]]):
        mesh = skelgrasp.Mesh(vertices if len(faces) == 10 else
                              np.array([[0, 0, 0], [0.05, 0, 0], [0.1, 0, 0]], dtype=float), faces)
        with pytest.raises(ValueError, match="degenerate mesh: no face has a positive area"):
            skelgrasp.plan(mesh, sdh, max_grasps=1, timeout_s=5)


def test_plan_timeout_and_samples_take_the_cli_ranges(capsule, sdh):
    for timeout in (float("nan"), -5.0, float("inf"), 1e7):
        with pytest.raises(ValueError, match="^timeout_s: "):
            skelgrasp.plan(capsule, sdh, timeout_s=timeout)
    options = skelgrasp.PlanOptions(timeout_s=20)
    options.ranking.robustness.samples = 10**9
    with pytest.raises(ValueError, match="^ranking.robustness.samples: 1000000000 is outside"):
        skelgrasp.plan(capsule, sdh, options)
    options = skelgrasp.PlanOptions(ranking=skelgrasp.RobustRankingParams(screen_samples=10**9))
    with pytest.raises(ValueError, match="^ranking.screen_samples: "):
        skelgrasp.plan(capsule, sdh, options)
    with pytest.raises(ValueError, match="robustness_samples: "):
        skelgrasp.score(capsule, sdh, [], robustness_samples=10**9)


def test_surface_planner_refuses_a_mesh_without_area(sdh):
    mesh = skelgrasp.Mesh(np.array([[0, 0, 0], [0.05, 0, 0], [0.1, 0, 0]], dtype=float),
                          [[0, 1, 2]])
    with pytest.raises(ValueError, match="degenerate mesh"):
        skelgrasp.plan(mesh, sdh, skelgrasp.PlanOptions(planner="surface"), max_grasps=1,
                       timeout_s=5)


def test_score_grasps_names_what_is_wrong_in_a_dict_or_a_file(tmp_path, capsule, sdh):
    grasp = {"id": 0, "hand_pose": {"position": [float("nan"), 0, 0],
                                    "quaternion_wxyz": [1, 0, 0, 0]}}
    document = {"schema": "skelgrasp.grasps/3", "hand": "sdh", "grasps": [grasp]}
    # NaN in a dict was nlohmann's raw parse error as RuntimeError.
    with pytest.raises(ValueError, match="grasps: a number is not finite"):
        skelgrasp.score_grasps(capsule, sdh, document)
    grasp["hand_pose"]["position"] = [0, 0, 1001]
    with pytest.raises(ValueError, match="limit of 100 m"):
        skelgrasp.score_grasps(capsule, sdh, document)
    path = tmp_path / "far.json"
    path.write_text(json.dumps(document))
    with pytest.raises(OSError, match=f"^{path}: grasp 0: "):
        skelgrasp.score_grasps(capsule, sdh, str(path))


def test_score_grasps_and_simulate_refuse_more_work_than_a_command_may_run(capsule, sdh):
    grasps = [{"id": i, "hand_pose": {"position": [0, 0, 0.2], "quaternion_wxyz": [1, 0, 0, 0]}}
              for i in range(101)]
    document = {"schema": "skelgrasp.grasps/3", "hand": "sdh", "grasps": grasps}
    # 101 x (1 + 100000) closings, 11 x (1 + 10000) executions: refused before any of them.
    with pytest.raises(ValueError, match="more than the limit of 10000000 per command"):
        skelgrasp.score_grasps(capsule, sdh, document, robustness_samples=100000)
    with pytest.raises(ValueError, match="more than the limit of 100000 per command"):
        skelgrasp.simulate(capsule, sdh, document, samples=10000, max_grasps=11)
