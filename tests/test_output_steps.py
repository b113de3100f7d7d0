"""The load-step series' stresses: each step's VTU holds that step's recovered stress (the steps
are recovered side by side in batches). A linear elastic plate under a traction whose factor
follows a path has each step's stress equal to the path's factor times the stress of the unit
load, so every step's file is the final step's scaled by the ratio of their factors."""

import numpy as np
import pytest

from test_load_paths import _scene


def test_each_step_file_holds_its_own_stress(tmp_path):
    pv = pytest.importorskip("pyvista")
    from ibfem.solver.io import output
    from ibfem.solver.solving import solve

    sc = _scene([{"name": "ramp", "points": [[0, 0], [1, 1], [2, 0.5]]}], "ramp", {"steps_per_unit": 2})
    output._BATCH_VALUES, batch = 1.0, output._BATCH_VALUES  # one step per batch, then all together
    try:
        output.write_scene_results(tmp_path / "one", sc, solve(sc.problem))
    finally:
        output._BATCH_VALUES = batch
    output.write_scene_results(tmp_path / "all", sc, solve(sc.problem))
    factors = [0.5, 1.0, 0.75, 0.5]  # the path at t = 0.5, 1, 1.5, 2
    final = pv.read(tmp_path / "all" / "plate.vtu")
    for where, key in (("point_data", "stress"), ("cell_data", "cell_stress")):  # recovered and raw
        want = np.asarray(getattr(final, where)[key])
        top = np.abs(want).max()
        assert top > 1e5
        for run in ("one", "all"):
            for k, factor in enumerate(factors, start=1):
                step = pv.read(tmp_path / run / "steps" / f"step_{k:04d}" / "plate.vtu")
                got = np.asarray(getattr(step, where)[key])
                assert np.allclose(got, want * factor / factors[-1], rtol=1e-8, atol=1e-8 * top)


def test_two_bodies_keep_their_batches():
    """Bodies asked for in turn, step after step, each recover a batch of steps once (a stand-in
    solution whose stresses are the field itself: one centroid, one node)."""
    from ibfem.solver.io import output

    calls = []

    class Stand:
        def centroid_stress(self, body, fields=None):
            return np.zeros((1, 3)) if fields is None else np.repeat(np.asarray(fields)[:1], 3, axis=0).T.reshape(1, -1)

        def nodal_stress(self, body, values=None):
            calls.append(body) if values is not None else None
            return np.zeros((1, 3)) if values is None else values + (body == "b")

    fields = [np.full(4, float(k)) for k in range(10)]
    output._BATCH_VALUES, batch = 24.0, output._BATCH_VALUES  # 4 steps a batch
    try:
        stresses = output._StepStresses(Stand(), [{"field": u} for u in fields])
        for k, u in enumerate(fields):
            for body in ("a", "b"):
                centroid, nodal = stresses.get(body, u)
                assert np.all(centroid == k) and np.all(nodal == k + (body == "b"))
    finally:
        output._BATCH_VALUES = batch
    assert calls == ["a", "b"] * 3  # steps 0-3, 4-7, 8-9
