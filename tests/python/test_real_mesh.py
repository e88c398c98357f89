"""Skeleton and plan on a real YCB mesh (skipped without ../shared/data)."""
import numpy as np

import skelgrasp

from conftest import ycb_mesh_path


def test_banana_with_the_sdh():
    mesh = skelgrasp.load_mesh(ycb_mesh_path("011_banana"))
    assert mesh.name == "011_banana.ply" and mesh.vertices.shape[1] == 3
    s = skelgrasp.skeleton(mesh)
    assert s.ok, s.status
    # A banana is one curved arm: no loop, at least two endpoints.
    assert len(s.edges) == len(s.vertices) - 1 and s.types.count("endpoint") >= 2
    mapped = np.sort(np.concatenate(s.surface_points))
    assert np.array_equal(mapped, np.arange(len(mesh.vertices)))
    result = skelgrasp.plan(mesh, skelgrasp.hand("sdh"), seed=1, max_grasps=3)
    assert result.grasps, result.summary["rejections"]
    lo, hi = mesh.bounds
    for g in result.grasps:
        assert g.force_closure
        for c in g.contacts:
            assert np.all(c["point"] >= lo - 1e-3) and np.all(c["point"] <= hi + 1e-3)
