"""Meshes and clouds from numpy arrays; every bad array raises ValueError naming the problem."""
import numpy as np
import pytest

import skelgrasp

from conftest import capsule_arrays


def test_mesh_round_trips_its_arrays():
    vertices, faces = capsule_arrays()
    mesh = skelgrasp.Mesh(vertices, faces)
    assert mesh.vertices.dtype == np.float64 and mesh.vertices.shape == vertices.shape
    assert np.array_equal(mesh.vertices, vertices)
    assert np.issubdtype(mesh.faces.dtype, np.integer) and np.array_equal(mesh.faces, faces)
    # Closed and outward: the volume is close to the capsule's (polygonised, so a bit less).
    exact = np.pi * 0.03**2 * 0.10 + 4 / 3 * np.pi * 0.03**3
    assert 0.9 * exact < mesh.volume < exact
    assert np.allclose(mesh.bounds, [[-0.03, -0.03, -0.08], [0.03, 0.03, 0.08]], atol=1e-9)


def test_mesh_accepts_lists_and_int32_faces():
    vertices, faces = capsule_arrays()
    mesh = skelgrasp.Mesh(vertices.tolist(), faces.astype(np.int32))
    assert np.array_equal(mesh.faces, faces)


@pytest.mark.parametrize("vertices, faces, message", [
    (np.zeros((4, 2)), [[0, 1, 2]], "vertices: expected an N x 3 array, got shape (4 x 2)"),
    (np.zeros(3), [[0, 1, 2]], "vertices: expected an N x 3 array, got shape (3)"),
    (np.eye(3), [[0, 1, 2, 0]], "faces: expected an N x 3 array, got shape (1 x 4)"),
    (np.eye(3), [[0, 1, 3]], "faces: row 0 has vertex index 3 outside [0, 3)"),
    (np.eye(3), [[0, -1, 2]], "faces: row 0 has vertex index -1 outside [0, 3)"),
    (np.eye(3), [[0.0, 1.0, 2.0]], "faces: indices must be integers, got dtype float64"),
    ([[0, 0, 0], [1, 0, np.nan], [0, 1, 0]], [[0, 1, 2]], "vertices: row 1 is not finite (nan)"),
    ([[0, 0, 0], [1, 0, np.inf], [0, 1, 0]], [[0, 1, 2]], "vertices: row 1 is not finite (inf)"),
    (np.zeros((0, 3)), np.zeros((0, 3), dtype=int), "vertices: the mesh has no vertices"),
    (np.eye(3), np.zeros((0, 3), dtype=int), "faces: the mesh has no faces"),
    ("abc", [[0, 1, 2]], "vertices: not a numeric array"),
    (None, [[0, 1, 2]], "vertices: got None, expected an N x 3 array"),
])
def test_bad_mesh_arrays_raise_value_error(vertices, faces, message):
    with pytest.raises(ValueError) as error:
        skelgrasp.Mesh(vertices, faces)
    assert str(error.value) == message


def test_point_cloud_arrays():
    points = np.random.default_rng(1).normal(size=(50, 3))
    normals = np.tile([0.0, 0.0, 2.0], (50, 1))
    colors = np.full((50, 3), 200, dtype=np.uint8)
    cloud = skelgrasp.PointCloud(points, normals=normals, colors=colors)
    assert len(cloud) == 50 and np.array_equal(cloud.points, points)
    assert np.allclose(cloud.normals, [0, 0, 1])  # made unit
    assert cloud.colors.dtype == np.uint8 and np.all(cloud.colors == 200)
    assert skelgrasp.PointCloud(points).normals is None


@pytest.mark.parametrize("kwargs, message", [
    ({"points": np.zeros((5, 4))}, "points: expected an N x 3 array, got shape (5 x 4)"),
    ({"points": np.zeros((0, 3))}, "points: the cloud has no points"),
    ({"points": np.zeros((5, 3)), "normals": np.ones((4, 3))},
     "normals: 4 rows for 5 points (one normal per point)"),
    ({"points": np.zeros((2, 3)), "normals": np.zeros((2, 3))}, "normals: a normal has length 0"),
    ({"points": np.zeros((2, 3)), "colors": [[0, 0, 0], [0, 0, 300]]},
     "colors: row 1 has 300 outside [0, 255]"),
])
def test_bad_cloud_arrays_raise_value_error(kwargs, message):
    with pytest.raises(ValueError) as error:
        skelgrasp.PointCloud(**kwargs)
    assert str(error.value) == message
