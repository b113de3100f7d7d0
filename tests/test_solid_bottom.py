"""The exact gap of a solid to a flat (solver.reference.crowned_roller.solid_bottom), the gap the
half-space references of the rollers are computed from, against a sphere's closed form."""

from __future__ import annotations

import numpy as np

from ibfem.geometry.solids import solid_from_dict
from ibfem.solver.reference.crowned_roller import solid_bottom


def test_sphere_bottom_is_its_closed_form():
    sphere = solid_from_dict({"type": "sphere", "center": [0.0, 0.0, 0.5], "radius": 0.5})
    X, Y = np.meshgrid(np.linspace(-0.05, 0.05, 7), np.linspace(0.0, 0.05, 5))
    height = solid_bottom(sphere, X, Y)
    exact = 0.5 - np.sqrt(0.25 - X**2 - np.maximum(Y, 1e-7) ** 2)
    assert height.shape == X.shape
    np.testing.assert_allclose(height, exact, rtol=0, atol=1e-12)
