"""The size estimate of a 3D scene (``ibfem run --check``, solver.model.estimate) against the
grids then built: cells and dofs within 30 %, upright and turned by 37 degrees about (1, 2, 3)
(a turned part's bounding box is about twice its volume: the estimate follows the part, as the
octree does, not its box)."""

import tomllib
from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.fem.bodies import discretise
from ibfem.solver.io.scene import load_scene
from ibfem.solver.model.estimate import estimate_size
from ibfem.solver.model.resolve import resolve_problem

FULL = Path(__file__).resolve().parent.parent / "examples" / "solid" / "full"


@pytest.mark.parametrize("name", ["ball_on_block", "ball_on_block_turned"])
def test_estimate_against_the_built_octrees(name):
    data = tomllib.loads((FULL / f"{name}.toml").read_text())
    for body in data["bodies"]:
        body["element_size"] = 0.125
        body["refinement"][0]["levels"] = 2
    problem = load_scene(data, label=f"{name}.toml", base_dir=FULL).problem
    size = estimate_size(problem)
    bodies = discretise(resolve_problem(problem), problem.options)
    cells = sum(len(b.grid.level) for b in bodies)
    dofs = sum(b.n_dofs for b in bodies)
    assert size.cells == pytest.approx(cells, rel=0.3)
    assert size.dofs == pytest.approx(dofs, rel=0.3)
    # every octree cell holds material or lies within its half diagonal of the part
    for b in bodies:
        phi = b.boundary.signed_distance(b.grid.center)
        assert np.all(phi > -0.5 * np.sqrt(3.0) * b.grid.size * (1 + 1e-6))
