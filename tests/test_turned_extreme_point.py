"""A body whose lowest point lies on its grid's border: the half ellipse of
examples/ellipse_on_block.toml and its block turned together by 25 degrees about the contact
point put the ellipse's extreme point in y on the box the grid starts at, and the boundary piece
there, outside the grid by round-off, was refused ("lies in no grid cell"). Checked against the
unturned run: a turned pair is the same contact (half-width within 0.1 %, the force within 0.1 %)."""

import math
import tomllib
from pathlib import Path

import pytest

from ibfem.solver.io.scene import scene_from_dict
from ibfem.solver.solving import solve

SCENE = Path(__file__).resolve().parents[1] / "examples" / "ellipse_on_block.toml"


def _turned(theta_deg: float) -> dict:
    data = tomllib.loads(SCENE.read_text(encoding="utf-8"))
    data["output"] = {"vtk": False, "plots": False}
    data["solver"]["load_steps"] = 1
    for body in data["bodies"]:
        body["shape"].update(rotate_deg=theta_deg, pivot=[0.0, 0.0])
    t = math.radians(theta_deg)
    data["boundary_conditions"][0]["value"] = [1.0e-4 * math.sin(t), -1.0e-4 * math.cos(t)]
    return data


def test_a_turn_that_puts_the_extreme_point_on_the_grids_border():
    runs = [solve(scene_from_dict(_turned(theta), label=f"turned {theta}").problem) for theta in (0.0, 25.0)]
    assert all(r.converged for r in runs)
    (flat,), (turned,) = (r.contacts for r in runs)
    assert turned["half_width"] == pytest.approx(flat["half_width"], rel=1e-3)
    assert turned["normal_force"] == pytest.approx(flat["normal_force"], rel=1e-3)
