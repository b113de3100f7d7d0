"""The axisymmetric flat punch with a conical chamfer (solver/reference/chamfered_punch_3d.py): its
closed form against the cone (b = 0), equilibrium, an adaptive quadrature of the same integral and
Boussinesq's influence coefficients on the same gap (solver/reference/halfspace.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from ibfem.solver.reference.chamfered_punch_3d import (chamfered_punch_3d_approach, chamfered_punch_3d_load,
                                                       chamfered_punch_3d_pressure, chamfered_punch_3d_radius)


def test_without_a_flat_it_is_the_cone():
    """b = 0: P = pi E* k a^2 / 2, d = pi k a / 2, p = (E* k / 2) arccosh(a / r) (Johnson eq. 5.25
    with cot alpha = k)."""
    a, k, e_star = 0.03, 0.05, 1.2e11
    assert chamfered_punch_3d_load(a, 0.0, k, e_star) == pytest.approx(math.pi * e_star * k * a * a / 2, rel=1e-12)
    assert chamfered_punch_3d_approach(a, 0.0, k) == pytest.approx(math.pi * k * a / 2, rel=1e-12)
    r = np.linspace(0.05, 0.95, 10) * a
    np.testing.assert_allclose(chamfered_punch_3d_pressure(r, a, 0.0, k, e_star), 0.5 * e_star * k * np.arccosh(a / r),
                               rtol=1e-6)


def test_pressure_balances_the_load_and_matches_an_adaptive_quadrature():
    a, b, k, e_star = 0.05, 0.04, 0.08, 1.6e11
    load = chamfered_punch_3d_load(a, b, k, e_star)
    assert chamfered_punch_3d_radius(load, b, k, e_star) == pytest.approx(a, rel=1e-10)

    def adaptive(ri):
        kernel = lambda t: (math.acos(b / t) + b / math.sqrt(t * t - b * b)) / math.sqrt(t * t - ri * ri)
        lo = max(ri, b)
        return e_star * k / math.pi * quad(kernel, lo, a, limit=400, points=[0.5 * (lo + a)])[0]

    for ri in (0.0, 0.02, 0.035, 0.042, 0.048):
        assert chamfered_punch_3d_pressure(np.array([ri]), a, b, k, e_star)[0] == pytest.approx(adaptive(ri), rel=1e-5)
    # 2 pi int p r dr = P: Gauss-Legendre clustered at both ends of each piece (p is infinite at b)
    v, w = np.polynomial.legendre.leggauss(400)
    total = 0.0
    for lo, hi in ((0.0, b), (b, a)):
        r = lo + 0.5 * (hi - lo) * (1.0 - np.cos(0.5 * math.pi * (v + 1.0)))
        jac = 0.25 * (hi - lo) * math.pi * np.sin(0.5 * math.pi * (v + 1.0))
        total += 2 * math.pi * float(np.sum(w * jac * r * chamfered_punch_3d_pressure(r, a, b, k, e_star)))
    assert total == pytest.approx(load, rel=1e-3)


def test_closed_form_against_the_half_space_influence_coefficients():
    """The same gap k max(r - b, 0) on Boussinesq's influence coefficients (0.5 mm squares, the
    quarter): the contact radius within a square and the pressure's means over rings within 3 %
    of the closed form's peak of the rings, away from the edge's logarithmic peak."""
    from ibfem.solver.reference.halfspace import halfspace_contact

    b, k, e_star = 0.01, 0.08, 1.6e11
    a = 0.0125
    load = chamfered_punch_3d_load(a, b, k, e_star)
    dx = 0.0005
    x = np.arange(dx / 2, 0.016, dx)
    ref = halfspace_contact(lambda X, Y: k * np.clip(np.hypot(X, Y) - b, 0.0, None), x, x, e_star, force=load / 4,
                            symmetric=True)
    X, Y = np.meshgrid(x, x, indexing="ij")
    r = np.hypot(X, Y)
    edge = r[ref.pressure > 0].max()
    assert edge == pytest.approx(a, abs=1.5 * dx)
    rings = np.arange(0.0, a, 0.001)
    closed = chamfered_punch_3d_pressure(r.ravel(), a, b, k, e_star).reshape(r.shape)
    means = []
    for lo in rings:
        m = (r >= lo) & (r < lo + 0.001) & (np.abs(r - b) > 0.001)
        if m.any():
            means.append((ref.pressure[m].mean(), closed[m].mean()))
    means = np.array(means)
    assert np.abs(means[:, 0] - means[:, 1]).max() < 0.03 * means[:, 1].max()
