"""reconstruct and run on a real table scan (skipped without ../shared/data)."""
import math
import os

import numpy as np
import pytest

import skelgrasp

from conftest import shared_data_dir


def mug_scan():
    path = os.path.join(shared_data_dir(), "scans", "pcd", "gpd_table_mug.pcd")
    if not shared_data_dir() or not os.path.exists(path):
        pytest.skip(f"real data absent: {path}")
    return skelgrasp.load_cloud(path)


def test_reconstruct_and_run_on_the_mug_scan():
    cloud = mug_scan()
    assert cloud.points.shape[1] == 3 and len(cloud) > 1000
    rec = skelgrasp.reconstruct(cloud)
    assert len(rec.objects) == 1 and rec.to_dict()["schema"] == "skelgrasp.reconstruction/1"
    mesh, observed = rec.objects[0], rec.observed[0]
    assert mesh.volume > 0 and len(observed) == len(mesh.vertices)
    assert set(np.unique(observed)) <= {0, 1}
    # The same object when asked for the one nearest to its centre.
    centre = mesh.bounds.mean(axis=0)
    near = skelgrasp.reconstruct(cloud, objects=centre)
    assert np.allclose(near.objects[0].bounds, mesh.bounds)
    # The mug stands well inside the table: the hull margin does not change it, and is reported.
    tight = skelgrasp.reconstruct(cloud, plane_hull_margin_m=0.0)
    assert tight.to_dict()["scene"]["plane_hull_margin_m"] == 0.0
    assert np.allclose(tight.objects[0].bounds, mesh.bounds)
    with pytest.raises(ValueError, match="hull margin"):
        skelgrasp.reconstruct(cloud, plane_hull_margin_m=-0.01)

    run = skelgrasp.run(cloud, skelgrasp.hand("armar3"), max_grasps=2)
    document = run.to_dict()
    assert document["schema"] == "skelgrasp.run/4" and len(document["grasps"]) == len(run)
    assert run.status[0] in ("ok", "no_result") and len(run.observed) == len(run.mesh.vertices)
    for g in run.grasps:
        assert g.force_closure and math.isfinite(g.rank_score)
        assert 0.0 <= g.observed_contact_ratio <= 1.0


def test_run_every_object_of_the_scan_in_one_run():
    cloud = mug_scan()
    hand = skelgrasp.hand("armar3")
    scene = skelgrasp.run(cloud, hand, objects="all", max_grasps=2, robustness=False)
    assert isinstance(scene, skelgrasp.SceneRunResult) and len(scene) >= 1
    document = scene.to_dict()
    assert document["schema"] == "skelgrasp.run/4"
    assert [o["id"] for o in document["objects"]] == [o.id for o in scene.objects]
    listed = 0
    for o in scene.objects:
        grasps = scene.grasps(o.id)
        listed += len(grasps)
        assert (o.reason == "") == (len(grasps) > 0)
        assert o.points > 0 and len(o.centroid) == 3
        for g in grasps:
            assert g.force_closure
    assert listed == len(document["grasps"])
    assert scene.status[0] == ("ok" if listed else "no_result")
    with pytest.raises(ValueError, match="the scene has"):
        scene.grasps(len(scene))
    # index:0 is the largest object, the first of the scene run.
    first = skelgrasp.run(cloud, hand, objects="index:0", max_grasps=2, robustness=False)
    assert len(first.mesh.vertices) == len(scene.objects[0].mesh.vertices)


def test_scan_errors():
    with pytest.raises(ValueError, match="objects: "):
        skelgrasp.reconstruct(skelgrasp.PointCloud(np.zeros((10, 3))), objects=[1, 2])
    # A flat patch has no object above its plane: the CLI's error, as ValueError.
    grid = np.stack(np.meshgrid(np.linspace(0, 0.3, 40), np.linspace(0, 0.3, 40)), -1)
    plane = np.concatenate([grid.reshape(-1, 2), np.full((1600, 1), 1.0)], axis=1)
    with pytest.raises(ValueError, match="^plane: "):
        skelgrasp.reconstruct(skelgrasp.PointCloud(plane, name="plane"))
