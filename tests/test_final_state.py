"""A final state that fails the contact conditions is never reported as converged:
bodies that still interpenetrate anywhere outside the contact region found make the run
not converged, with a message, whatever the region search concluded.

Reproducer: the ellipse example on a coarse grid with its boundary tessellated (the thesis's
non-projected variant): the region search settles on an empty region (a = 0, N = 0) while the
bodies overlap; variants: frictionless contact, a larger load."""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.io.scene import scene_from_dict
from ibfem.solver.solving import solve

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def coarse_tessellated_ellipse(kind: str = "tied", uy: float = -1.0e-4) -> dict:
    data = tomllib.loads((EXAMPLES / "ellipse_on_block.toml").read_text())
    data["solver"].update(exact_geometry=False, chord_tolerance=1e-3)
    for body in data["bodies"]:
        body["element_size"] = 0.05
        body["refinement"] = [{"levels": 3, "around": "contact", "radius": 0.03}]
    data["boundary_conditions"][0]["value"] = [0.0, uy]
    data["contacts"][0]["type"] = kind
    data["output"] = {"vtk": False, "plots": False}
    return data


@pytest.mark.parametrize("kind, uy", [("tied", -1.0e-4), ("frictionless", -1.0e-4), ("tied", -3.0e-4)])
def test_interpenetrating_final_state_is_not_converged(kind, uy):
    sol = solve(scene_from_dict(coarse_tessellated_ellipse(kind, uy), label="scene.toml").problem)
    c = sol.contacts[0]
    checks = c["checks"]
    # the independent evidence: the bodies overlap at the sample points outside the region
    assert checks["min_gap"] < 0.0 and checks["penetration_points"] > 0
    assert checks["penetration"] is True
    assert not sol.converged
    assert any("interpenetrate" in m or "penetration True" in m for m in sol.iterations["messages"])


def test_a_consistent_final_state_has_no_penetration_and_converges():
    """The check does not fire on a good solution: the same scene on its fine exact grid."""
    data = tomllib.loads((EXAMPLES / "ellipse_on_block.toml").read_text())
    data["output"] = {"vtk": False, "plots": False}
    data["solver"]["load_steps"] = 1
    sol = solve(scene_from_dict(data, label="scene.toml").problem)
    checks = sol.contacts[0]["checks"]
    assert sol.converged, sol.iterations["messages"]
    assert checks["penetration_points"] == 0 and checks["min_gap"] >= 0.0
    assert np.isfinite(sol.contacts[0]["normal_force"]) and sol.contacts[0]["normal_force"] > 0
