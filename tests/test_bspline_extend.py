"""Extending a clamped B-spline past its domain (geometry.bspline_extend): a polynomial written as
a B-spline with several spans extends into the same polynomial; a NURBS quarter circle extends
along the same circle; the spline is unchanged on its own domain."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import BSpline, make_interp_spline

from ibfem.geometry import primitive_from_dict
from ibfem.geometry.bspline_extend import extend_clamped, extend_surface_dict


def _cubic(x):
    return np.stack([1 + 2 * x - 3 * x**2 + 0.5 * x**3, x**2, x], axis=-1)


def test_a_polynomial_extends_into_the_same_polynomial():
    x = np.linspace(0.0, 1.0, 9)
    spline = make_interp_spline(x, _cubic(x), k=3)  # a cubic is reproduced exactly, 6 spans
    t, c = extend_clamped(spline.t, 3, spline.c, -0.3, 1.4)
    assert t[0] == -0.3 and t[-1] == 1.4 and np.array_equal(t[4:-4], spline.t[4:-4])
    xx = np.linspace(-0.3, 1.4, 200)
    assert np.abs(BSpline(t, c, 3)(xx) - _cubic(xx)).max() < 1e-13


def test_a_rational_quarter_circle_extends_along_the_circle():
    w = np.array([1.0, np.sqrt(0.5), 1.0])
    H = np.column_stack([np.array([[1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]) * w[:, None], w])
    t, H2 = extend_clamped([0, 0, 0, 1, 1, 1.0], 2, H, -0.2, 1.3)
    y = BSpline(t, H2, 2)(np.linspace(-0.2, 1.3, 61))
    assert np.abs(np.linalg.norm(y[:, :2] / y[:, 2:], axis=1) - 1.0).max() < 1e-14
    assert H2[:, 2].min() > 0


def test_an_extended_surface_keeps_its_points_on_the_old_domain():
    rng = np.random.default_rng(3)
    d = {"type": "bspline_surface", "degree_u": 3, "degree_v": 2, "knots_u": [0, 0, 0, 0, 0.4, 1, 1, 1, 1],
         "knots_v": [0, 0, 0, 0.5, 1, 1, 1], "control_points": rng.normal(size=(5, 4, 3)).tolist(),
         "weights": rng.uniform(0.8, 1.25, size=(5, 4)).tolist()}
    old, new = primitive_from_dict(d), primitive_from_dict(extend_surface_dict(d, (-0.02, 1.03), (0.0, 1.05)))
    assert new.domain == ((-0.02, 1.03), (0.0, 1.05))
    uv = rng.uniform(0.0, 1.0, size=(300, 2))
    assert np.abs(new.evaluate(uv) - old.evaluate(uv)).max() < 1e-12


def test_an_unclamped_knot_vector_is_refused():
    with pytest.raises(ValueError, match="not clamped"):
        extend_clamped([0, 1, 2, 3, 4, 5], 2, np.zeros((3, 2)), -1.0, 6.0)
