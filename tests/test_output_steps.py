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
