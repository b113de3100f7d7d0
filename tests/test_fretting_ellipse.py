"""A frictional contact with memory (a load path) on an elliptical region: crossed cylinders,
R 1 m along x on R 0.5 m along y, the normal displacement held while the tangential one rises and
falls. The shape b / a stays Hertz's under a path (the points' memory lives on the region's
parametrisation), so the final check must not fail the run for a shape it did not iterate."""

import math
import tomllib
from pathlib import Path

import pytest

from ibfem.solver.io.scene import scene_from_dict
from ibfem.solver.reference.theory import hertz_elliptic_contact
from ibfem.solver.solving import solve

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "examples" / "solid" / "crossed_cylinders.toml"


def crossed_cylinders_fretting() -> dict:
    data = tomllib.loads(SCENE.read_text(encoding="utf-8"))
    data["output"] = {"vtk": False, "plots": False}
    for body in data["bodies"]:
        body["refinement"] = {"levels": 4, "around": "contact", "radius": 0.1}
    data["solver"] = {"steps_per_unit": 2}
    data["paths"] = [{"name": "hold", "points": [[0.0, 0.0], [1.0, 1.0], [2.0, 1.0]]},
                     {"name": "fret", "cycle": {"amplitude": 1.0, "cycles": 0.5, "points_per_cycle": 4, "start": 1.0}}]
    loaded = data["boundary_conditions"][0]
    loaded["value"], loaded["path"] = [1.0e-4, 0.0, -0.0015], ["fret", "hold", "hold"]
    data["contacts"][0].update(type="frictional", friction=0.3)
    return data


def test_an_elliptical_contact_under_a_path_converges_with_hertzs_shape():
    solution = solve(scene_from_dict(crossed_cylinders_fretting(), label="crossed.toml", base_dir=SCENE.parent).problem)
    assert solution.converged, solution.iterations["messages"]
    (c,) = solution.contacts
    a, b = c["semi_axes"]
    e_star = 2.0e11 / (2.0 * (1.0 - 0.3 ** 2))
    a_h, b_h, _ = hertz_elliptic_contact(c["normal_force"], (1.0, 2.0), e_star)
    assert b / a == pytest.approx(b_h / a_h, rel=1e-6)  # the shape kept at Hertz's for the curvatures
    assert math.isclose(a, a_h, rel_tol=0.1)  # the size searched (1.5 cells across b: coarse)
    assert [s["t"] for s in solution.steps] == pytest.approx([0.5, 1.0, 1.25, 1.5, 2.0])  # the cycle's corners too
