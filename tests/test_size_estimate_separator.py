"""The size estimate's work space of a large body's own separators (solver.model.estimate,
FAR_WORK_FACTOR): the plane nested dissection cuts first, and the update-matrix stack and largest
front of the symbolic multifrontal factorisation of a plate against the rule."""

from __future__ import annotations

import importlib.util
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.model import estimate

ROOT = Path(__file__).resolve().parent.parent


def test_separator_cuts_across_the_longest_side():
    # a plate of 108 x 108 x 20 cells is cut across one of its long sides: 109 x 21 nodes, 3 dofs each
    assert estimate._background_separator_dofs(np.array([108.0, 108.0, 20.0]), 1.0) == pytest.approx(3 * 109 * 21)
    assert estimate._background_separator_dofs(np.array([20.0, 108.0, 50.0]), 1.0) == pytest.approx(3 * 21 * 51)
    # a body filling an eighth of its box fills a quarter of its section
    assert estimate._background_separator_dofs(np.array([10.0, 10.0, 10.0]), 0.125) == pytest.approx(3 * 121 / 4)
    assert estimate._background_separator_dofs(np.array([10.0, 10.0]), 1.0) == 0.0
    assert estimate._background_separator_dofs(np.array([np.inf, 1.0, 1.0]), 1.0) == 0.0


def _plate_scene(element_size: float) -> dict:
    data = tomllib.loads((ROOT / "benchmarks" / "scenes" / "ball_on_plate_million.toml").read_text())
    for body in data["bodies"]:
        body["element_size"] = element_size
    data["solver"] = {"load_steps": 1}
    return data


@pytest.mark.slow
def test_plate_work_space_against_the_symbolic_factorisation():
    """A plate of 2.7 x 2.7 x 0.5 m at 50 mm cells (115k dofs): the stack and largest front of its
    symbolic factorisation, in the order the run factors in, within 30 % of the rule's."""
    spec = importlib.util.spec_from_file_location("factor_profile_3d", ROOT / "benchmarks" / "factor_profile_3d.py")
    profile = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("factor_profile_3d", profile)
    spec.loader.exec_module(profile)
    from ibfem.solver.io.scene import scene_from_dict

    problem = scene_from_dict(_plate_scene(0.05), label="plate").problem
    f = max((f for _, f in profile.body_factors(problem)), key=lambda f: f.n)  # the plate
    measured = f.stack_bytes + f.front_bytes
    plate = next(b for b in problem.bodies if b.name == "plate")
    lo, hi = (np.asarray(v, dtype=float) for v in plate.profile.bounds)
    rule = 8.0 * estimate.FAR_WORK_FACTOR * estimate._background_separator_dofs((hi - lo) / 0.05, 1.0) ** 2
    assert rule == pytest.approx(measured, rel=0.3)
