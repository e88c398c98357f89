"""Shared fixtures of the Python module's tests (run by ctest: tests/CMakeLists.txt)."""
import os
import subprocess

import numpy as np
import pytest

import skelgrasp

# The timing members differ between any two runs; everything else of a plan is deterministic.
TIMING_KEYS = ("planning_s", "ms_per_valid_grasp")


def shared_data_dir():
    return os.environ.get("SKELGRASP_SHARED_DATA_DIR", "")


def cli_path():
    path = os.environ.get("SKELGRASP_CLI", "")
    if not path or not os.path.exists(path):
        pytest.skip("SKELGRASP_CLI does not name the built skelgrasp executable")
    return path


def run_cli(*args):
    """Runs the skelgrasp executable; returns (exit code, stdout, stderr)."""
    done = subprocess.run([cli_path(), *map(str, args)], capture_output=True, text=True,
                          check=False)
    return done.returncode, done.stdout, done.stderr


def cli_error(stderr):
    """The problem of the CLI's one error line, after "skelgrasp: error: "."""
    lines = [line for line in stderr.splitlines() if line.startswith("skelgrasp: error: ")]
    assert len(lines) == 1, stderr
    return lines[0][len("skelgrasp: error: "):]


def capsule_arrays(radius=0.03, length=0.10, segments=24, rings=8):
    """A closed, outward-oriented capsule along z (numpy only): cylinder plus two hemispheres."""
    # Profile from the bottom pole to the top pole as (r, z).
    profile = []
    for i in range(rings + 1):
        a = -np.pi / 2 + (np.pi / 2) * i / rings
        profile.append((radius * np.cos(a), -length / 2 + radius * np.sin(a)))
    for i in range(rings + 1):
        a = (np.pi / 2) * i / rings
        profile.append((radius * np.cos(a), length / 2 + radius * np.sin(a)))
    vertices = [(0.0, 0.0, profile[0][1])]
    ring_rows = profile[1:-1]
    for r, z in ring_rows:
        for s in range(segments):
            t = 2 * np.pi * s / segments
            vertices.append((r * np.cos(t), r * np.sin(t), z))
    vertices.append((0.0, 0.0, profile[-1][1]))
    top = len(vertices) - 1
    faces = []

    def ring(k, s):
        return 1 + k * segments + s % segments

    for s in range(segments):
        faces.append((0, ring(0, s + 1), ring(0, s)))
    for k in range(len(ring_rows) - 1):
        for s in range(segments):
            a, b = ring(k, s), ring(k, s + 1)
            c, d = ring(k + 1, s), ring(k + 1, s + 1)
            faces.append((a, b, d))
            faces.append((a, d, c))
    last = len(ring_rows) - 1
    for s in range(segments):
        faces.append((top, ring(last, s), ring(last, s + 1)))
    return np.array(vertices, dtype=np.float64), np.array(faces, dtype=np.int64)


def write_ply(path, vertices, faces):
    with open(path, "w", encoding="ascii") as out:
        out.write("ply\nformat ascii 1.0\n")
        out.write(f"element vertex {len(vertices)}\nproperty double x\nproperty double y\n"
                  "property double z\n")
        out.write(f"element face {len(faces)}\nproperty list uchar int vertex_indices\n")
        out.write("end_header\n")
        for v in vertices:
            out.write(f"{v[0]!r} {v[1]!r} {v[2]!r}\n")
        for f in faces:
            out.write(f"3 {f[0]} {f[1]} {f[2]}\n")


@pytest.fixture(scope="session")
def capsule():
    vertices, faces = capsule_arrays()
    return skelgrasp.Mesh(vertices, faces, name="capsule")


@pytest.fixture(scope="session")
def sdh():
    return skelgrasp.hand("sdh")


@pytest.fixture(scope="session")
def capsule_plan(capsule, sdh):
    return skelgrasp.plan(capsule, sdh, seed=1, max_grasps=4)


def ycb_mesh_path(name="011_banana"):
    data = shared_data_dir()
    path = os.path.join(data, "objects", "ycb", name + ".ply")
    if not data or not os.path.exists(path):
        pytest.skip(f"real data absent: {path} (tests use ../shared/data when it is present)")
    return path


RANKING_TIMING_KEYS = ("screening_s", "scoring_s", "refinement_s")


def without_timing(document):
    """A copy of a plan document without its timing members (the summary's, the ranking record's
    and the whole "timing" object)."""
    summary = dict(document["summary"])
    for key in TIMING_KEYS:
        summary.pop(key, None)
    out = {**document, "summary": summary}
    out.pop("timing", None)
    if out.get("ranking"):
        out["ranking"] = {k: v for k, v in out["ranking"].items() if k not in RANKING_TIMING_KEYS}
    return out
