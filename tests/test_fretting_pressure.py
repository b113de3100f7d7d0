"""The pressure Coulomb's law uses on a 3D contact with friction history
(solver.contact.friction_history_pressure): the point pressures' edge-consistent fit
p_fit = sqrt(1 - X^2 - Y^2) P(X, Y), P quadratic, with the same moments up to the second order.
Checked against Hertz's pressure p0 sqrt(1 - r^2 / a^2) (K. L. Johnson, Contact Mechanics, 1985,
section 4.2), which the family holds exactly, and against the moment conditions it is built on."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from ibfem.solver.contact.friction_history_pressure import low_rank, pressure_fit

A, B = 0.04, 0.025  # semi-axes


def _disc_quadrature(n_r: int = 60, n_t: int = 96, half: bool = False):
    """Gauss-Legendre in r times the trapezoid rule in theta on the ellipse (a, b) (its upper half
    with ``half``): points (q, 2) and weights (q,)."""
    x, w = np.polynomial.legendre.leggauss(n_r)
    r, wr = 0.5 * (x + 1.0), 0.5 * w
    span = np.pi if half else 2.0 * np.pi
    t = (np.arange(n_t) + 0.5) * span / n_t
    rr, tt = np.meshgrid(r, t, indexing="ij")
    pts = np.column_stack([A * (rr * np.cos(tt)).ravel(), B * (rr * np.sin(tt)).ravel()])
    weights = (A * B * rr * wr[:, None] * span / n_t).ravel()
    return pts, weights


def _fit(pts, weights, p):
    """The fit of point pressures p given as p = I x + 0 (x = p)."""
    q = len(p)
    return pressure_fit(pts, (A, B), weights, sp.identity(q, format="csr"), np.zeros(q))


@pytest.mark.parametrize("half", [False, True])
def test_hertz_pressure_is_kept(half):
    pts, w = _disc_quadrature(half=half)
    rho2 = (pts[:, 0] / A) ** 2 + (pts[:, 1] / B) ** 2
    p = 3.0e9 * np.sqrt(np.clip(1.0 - rho2, 0.0, None))
    np.testing.assert_allclose(_fit(pts, w, p).pressure(p), p, rtol=0, atol=1e-9 * p.max())


def test_moments_up_to_the_second_order_are_those_of_the_point_pressures():
    pts, w = _disc_quadrature()
    rng = np.random.default_rng(3)
    p = rng.uniform(-1.0, 3.0, len(w)) * 1e9
    fitted = _fit(pts, w, p).pressure(p)
    X, Y = pts[:, 0] / A, pts[:, 1] / B
    for m in (np.ones_like(X), X, Y, X * X, X * Y, Y * Y):
        assert float(w @ (fitted * m)) == pytest.approx(float(w @ (p * m)), rel=1e-9, abs=1e-9 * float(w @ np.abs(p)))


@pytest.mark.parametrize("phase", [0.0, 0.3])
def test_a_grid_oscillation_is_removed(phase):
    """Hertz's pressure with a +-50 % oscillation of the grid's period h = a / 6 along both axes
    (the point tractions of trilinear cells oscillate so): the fit within 1 % of p0 of Hertz's
    everywhere and its load beyond 0.95 a within 2 % of Hertz's (1 - 0.95^2)^(3/2) N."""
    pts, w = _disc_quadrature(120, 192)
    rho = np.hypot(pts[:, 0] / A, pts[:, 1] / B)
    hertz = np.sqrt(np.clip(1.0 - rho**2, 0.0, None))
    h = A / 6.0
    p = hertz * (1.0 + 0.5 * np.cos(2 * np.pi * (pts[:, 0] / h + phase)) * np.cos(2 * np.pi * (pts[:, 1] / h + phase)))
    fitted = _fit(pts, w, p).pressure(p)
    assert np.abs(fitted - hertz).max() < 0.01
    rim = rho > 0.95
    assert float(w[rim] @ fitted[rim]) / float(w @ hertz) == pytest.approx((1.0 - 0.95**2) ** 1.5, rel=0.02)


def test_low_rank_product_equals_the_dense_one():
    rng = np.random.default_rng(5)
    m = 40
    left = np.zeros((m, 6))
    left[rng.choice(m, 12, replace=False)] = rng.normal(size=(12, 6))
    right = np.zeros((6, m))
    right[:, rng.choice(m, 20, replace=False)] = rng.normal(size=(6, 20))
    np.testing.assert_allclose(low_rank(left, right, m).toarray(), left @ right, rtol=0, atol=1e-14)


@pytest.mark.slow
def test_the_example_rim_carries_hertz_load():
    """The fretting example (a ball on a flat, half model, a / h = 5.8) at its held normal load:
    the pressure Coulomb's law uses carries Hertz's share of N beyond 0.9 a and 0.95 a
    ((1 - r^2)^(3/2): 8.28 % and 3.04 %) within 10 % (measured: 8.09 % and 2.87 %; the point
    pressures of the terms carry 6.77 % and 0.59 %), and N itself is the terms' normal force."""
    from ibfem.solver.contact.friction_history3d import HistoryEllipseContact
    from ibfem.solver.reports.validate_fretting_sphere import EXAMPLE, amplitude_for, scene_data
    from ibfem.solver.io.scene import scene_from_dict
    from ibfem.solver.solving import solve

    records = []
    end_step = HistoryEllipseContact.end_step

    def recording(self, x, a, info):
        end_step(self, x, a, info)
        st = self.step_state
        records.append((self.normalised_radius(st["s"], a), st["pressure"], info[0].weights,
                        float(-self.force(x, a, info) @ self.frame.normal)))

    data = scene_data(amplitude_for(0.6), 0.05, 20)  # the normal load, then one small tangential step
    sc = scene_from_dict(data, label=str(EXAMPLE), base_dir=EXAMPLE.parent)
    HistoryEllipseContact.end_step = recording
    try:
        assert solve(sc.problem).converged
    finally:
        HistoryEllipseContact.end_step = end_step
    rho, p, w, normal_force = records[0]
    n = float(w @ p)
    assert n == pytest.approx(abs(normal_force), rel=1e-9)
    assert p.min() >= 0.0
    for r0 in (0.9, 0.95):
        assert float(w[rho > r0] @ p[rho > r0]) / n == pytest.approx((1.0 - r0**2) ** 1.5, rel=0.1)
