"""A ball in a conical seat touches along the seat's circle: the relative curvature along the
circle is exactly zero (the ball's 1/R equals the cone's hoop curvature sin 45 / r there), which the
contact frame's finite differences read as -0.22 against 100 1/m. That was refused as "conforming
surfaces (the gap closes or opens the wrong way)"; it is a line contact whose line curves, refused
as such with the line's radius."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.contact.ellipse import CURVATURE_NOISE, LINE_CONTACT_RATIO, is_line_contact
from ibfem.solver.contact.ellipse_geometry import ContactFrame3D
from ibfem.solver.io.scene import load_scene

SCENE = Path(__file__).parent / "scenes" / "ball_in_cone_seat.toml"


def _frame(k0: float, k1: float) -> ContactFrame3D:
    return ContactFrame3D(point=np.zeros(3), normal=np.array([0.0, 0.0, 1.0]), axes=np.eye(3)[:2],
                          curvatures=np.array([k0, k1]))


@pytest.mark.parametrize("k0, line", [(-0.22, True), (0.5 * LINE_CONTACT_RATIO * 100, True),
                                      (-2 * CURVATURE_NOISE * 100, False), (0.01 * 100, False)])
def test_a_slightly_negative_smaller_curvature_is_a_line_contact(k0, line):
    """Conforming by more than the estimate's error stays refused; a positive ratio keeps its
    point-contact threshold."""
    assert is_line_contact(_frame(k0, 100.0)) is line


def test_the_ball_in_a_conical_seat_is_refused_as_a_curved_line_naming_its_radius():
    from ibfem.solver.solving import solve

    scene = load_scene(tomllib.loads(SCENE.read_text()), label=SCENE.name, base_dir=SCENE.parent)
    with pytest.raises(ValueError) as err:
        solve(scene.problem)
    text = str(err.value)
    assert "conforming" not in text and "curves in the tangent plane" in text
    # the seat's circle, of radius r = R sin 45 = 7.07 mm in space, curves in the tangent plane (at
    # 45 degrees to it) by cos 45 / r: a radius of R = 10 mm
    radius = float(text.split("(radius ")[1].split(" m")[0])
    assert radius == pytest.approx(0.01 * math.sin(math.pi / 4) / math.cos(math.pi / 4), rel=0.05)
