"""The 2D fretting example's energy per cycle on shifted grids: against the example's own grid and
against the Mindlin-Deresiewicz closed form (solver.reference.fretting, K. L. Johnson, Contact
Mechanics, 1985, sections 7.3 and 7.4; the line contact's W(Q*) for each run's computed amplitude
and normal force).

The grids moved by 0.4 of the finest cell along the contact and along its normal, and by (0.1,
0.4) and (-0.3, 0.4) coarsest cells (docs/load-paths.md, "The contact's edges in finer cells
(2D)"): the energy from the friction work within 2 % of the closed form and of the aligned
grid's; from the loop (its branches read by monotone cubics) within 2 % of both: measured -0.08
to -1.60 % of the closed form and within 1.5 % of the aligned grid on eight grids."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

from ibfem.solver.io.output import write_scene_results
from ibfem.solver.io.scene import scene_from_dict
from ibfem.solver.reports.validate_fretting import EXAMPLE, compare
from ibfem.solver.solving import solve

OFFSETS = ([0.025, 0.0], [0.0, 0.025], [0.1, 0.4], [-0.3, 0.4])


def _cycles(tmp_path, offset) -> list[dict]:
    """The example (two cycles) on the grid moved by ``offset`` (coarsest cells; None: its own):
    its complete cycle against the closed form."""
    data = tomllib.loads(EXAMPLE.read_text(encoding="utf-8"))
    data["output"] = {"vtk": False, "plots": False}
    data["paths"][1]["cycle"]["cycles"] = 1.5
    data["paths"][0]["points"][-1][0] = 2.5
    if offset is not None:
        data["solver"]["grid_offset"] = offset
    sc = scene_from_dict(data, label="fretting_grid.toml", base_dir=EXAMPLE.parent)
    solution = solve(sc.problem)
    assert solution.converged, solution.iterations["messages"]
    summary = write_scene_results(tmp_path, sc, solution)
    result = compare(summary, dict(np.load(tmp_path / "profiles_0.npz")), 1.0, 2.0e11, 0.3)
    assert max(abs(r["c_error_over_a"]) for r in result["steps"]) < 0.01
    return result["cycles"]


@pytest.mark.slow
def test_shifted_grids_keep_the_energy_per_cycle(tmp_path):
    (base,) = _cycles(tmp_path, None)
    assert abs(base["friction_error"]) < 0.02 and abs(base["loop_error"]) < 0.02, base
    for offset in OFFSETS:
        out = tmp_path / f"shift_{offset[0]}_{offset[1]}"
        out.mkdir()
        (c,) = _cycles(out, offset)
        assert abs(c["friction_error"]) < 0.02, (offset, c)
        assert c["energy_friction"] == pytest.approx(base["energy_friction"], rel=0.02), offset
        assert c["energy_loop"] == pytest.approx(base["energy_loop"], rel=0.02), offset
        assert abs(c["loop_error"]) < 0.02, (offset, c)
