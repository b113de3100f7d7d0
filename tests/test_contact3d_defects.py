"""Two 3D scenes that used to fail from inside the solver: a symmetric half model without a
contact point (the closest-point search stalled 0.18 m from the touching point, and the contact
region then found no surface), and a contact smaller than the grid resolves (a zero semi-axis
reached the samples' chords: numpy warnings, then a bare "not converged")."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from ibfem.geometry.solids import solid_from_dict
from ibfem.solver.contact.touching3d import closest_points_3d

SCENES = Path(__file__).resolve().parent / "scenes"


def _half_ball(radius: float, angle: float) -> object:
    """A ball of radius R resting on z = 0 (centre (0, 0, R)), its lower half revolved through angle."""
    return solid_from_dict({"type": "revolution", "axis_origin": [0, 0, radius], "axis": [0, 0, 1], "angle_deg": angle,
                            "profile": {"type": "profile", "edges": [
                                {"type": "line", "start": [0, 0], "end": [radius, 0], "name": "flat"},
                                {"type": "arc", "center": [0, 0], "radius": radius, "start_angle": 0,
                                 "end_angle": -90, "name": "dome"},
                                {"type": "line", "start": [0, -radius], "end": [0, 0], "name": "axis"}]}})


@pytest.mark.parametrize("angle, start", [(360.0, (0.3, -0.2, 0.05)), (180.0, (0.02, 0.45, 0.3))])
def test_closest_points_of_a_ball_on_a_block(angle, start):
    """A ball touching a block's top face z = 0 at the origin: the search ends there from a start
    0.3-0.5 m away (half model: on its symmetry plane y = 0), to a millionth of the element size."""
    ball = _half_ball(0.95, angle)
    lower = -1.4 if angle == 360.0 else 0.0
    block = solid_from_dict({"type": "box", "min": [-1.4, lower, -0.9], "max": [1.4, 1.4, 0.0]})
    point = closest_points_3d(ball, block, np.array(start), 0.19)
    np.testing.assert_allclose(point, 0.0, atol=1e-6 * 0.19)


def _run(scene: Path, out: Path):
    r = subprocess.run([sys.executable, "-m", "ibfem", "run", str(scene), "--out", str(out), "--quiet", "--no-estimate"],
                       capture_output=True, text=True)
    return r, json.loads((out / "summary.json").read_text()) if (out / "summary.json").exists() else None


def test_half_model_without_a_point_converges_at_the_touching_point(tmp_path):
    r, summary = _run(SCENES / "half_model_no_point.toml", tmp_path)
    assert r.returncode == 0, r.stderr
    assert "Warning" not in r.stderr
    c = summary["contacts"][0]
    np.testing.assert_allclose(c["point"], 0.0, atol=1e-9)  # the ball's lowest point, on the symmetry plane
    assert c["model_share"] == pytest.approx(0.5, abs=1e-6)
    assert not c["checks"]["penetration_found"] and not c["checks"]["tension_at_region_edges"]
    assert c["semi_axes"][0] == pytest.approx(c["semi_axes"][1], rel=1e-9)  # a ball on a flat: a circle


def test_contact_below_the_grid_resolution_says_so(tmp_path):
    """Hertz's radius about 0.022 m against a finest cell of 0.062 m: exit 1, the history kept, a
    message naming the overlap and what to refine, and no numpy warning."""
    r, summary = _run(SCENES / "contact_below_resolution.toml", tmp_path)
    assert r.returncode == 1, r.stderr
    assert "Warning" not in r.stderr and "not converged" in r.stderr
    assert summary["iterations"]["contacts"][0]  # the history
    (message,) = summary["iterations"]["messages"]
    assert "smaller than the grid resolves" in message and "refinement levels" in message
