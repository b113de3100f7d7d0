"""Contact traction recovery (solver.contact.tractions): the projection onto
sqrt(1 - x^2) U_k (and T_k / sqrt(1 - x^2) for tied zones) against closed forms (Hertz,
Cattaneo-Mindlin, a flat punch's shear), with the cell-periodic noise of bilinear tractions
added; exact force and first moment; complementarity of what is reported; and the reported
profiles of a small solved scene turned on the grid against Hertz / Cattaneo-Mindlin."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ibfem.solver.contact import tractions as T
from ibfem.solver.reference import theory

from _contact_scenes import cylinder_on_block

A, H = 1.0, 0.09  # half-width and cell: about 11 cells per half-width, as the examples


def _quadrature(half: float, cell: float, origin: float = 0.0137, order: int = 4):
    """Gauss points (s, w) on |s| <= half split at grid lines origin + k cell."""
    lines = origin + cell * np.arange(math.floor((-half - origin) / cell), math.ceil((half - origin) / cell) + 1)
    cuts = np.unique(np.concatenate([[-half, half], lines[(lines > -half) & (lines < half)]]))
    g, gw = np.polynomial.legendre.leggauss(order)
    lo, hi = cuts[:-1, None], cuts[1:, None]
    s = (0.5 * (lo + hi) + 0.5 * (hi - lo) * g).ravel()
    w = (0.5 * (hi - lo) * gw).ravel()
    return s, w


def _cell_noise(s, cell, amplitude, origin=0.0137):
    """A grid-periodic oscillation with zero mean over every cell (the bilinear traction's)."""
    xi = ((s - origin) / cell) % 1.0
    return amplitude * np.cos(2 * np.pi * xi)


def test_hertz_with_cell_noise_is_recovered_and_force_and_moment_are_exact():
    s, w = _quadrature(A, H)
    p0 = 1.0
    exact = theory.hertz_pressure(s, A, p0)
    data = exact * (1.0 + _cell_noise(s, H, 0.1))  # +-10 % point to point, as measured
    n = T.modes_for(A, H)
    coef = T.project(s, w, data, A, n)
    assert w @ T._series(coef, s, A) == pytest.approx(w @ data, rel=1e-12)  # the force
    assert w @ (s * T._series(coef, s, A)) == pytest.approx(w @ (s * data), abs=1e-12)  # its moment
    x = np.linspace(-0.9, 0.9, 181)
    err = T._series(coef, x, A) - theory.hertz_pressure(x, A, p0)
    assert np.sqrt(np.mean(err**2)) < 0.005 * p0
    # many modes let the edge cells' structure back in: the rule keeps the modes few
    assert 2 <= n <= 4


def test_modes_grow_with_the_square_root_of_the_resolution():
    assert T.modes_for(11 * H, H) == 3
    assert T.modes_for(40 * H, H) == 6
    assert T.modes_for(1.5 * H, H) == T.MIN_MODES
    assert T.modes_for(1e4 * H, H) == T.MAX_MODES
    assert T.modes_for(0.0, H) == 0


def test_cattaneo_mindlin_shear_and_coulomb_bound():
    s, w = _quadrature(A, H)
    p0, mu, ca, sign = 1.0, 0.3, 0.6, -1.0
    p = theory.hertz_pressure(s, A, p0)
    q = theory.cattaneo_mindlin_shear(s, A, ca * A, mu, p0, sign=sign)
    q_noisy = q + sign * mu * _cell_noise(s, H, 0.08) * p
    r = sign * mu * p - q_noisy
    r[np.abs(s) > ca * A] = 0.0  # the slip zones carry mu p exactly (the friction traction)
    prof = T.TractionProfile(A, ca * A, sign, mu, T.project(s, w, p, A, T.modes_for(A, H)), np.zeros(0),
                             T.project(s, w, r, ca * A, T.modes_for(ca * A, H)))
    x = np.linspace(-0.95, 0.95, 191)
    ref = theory.cattaneo_mindlin_shear(x, A, ca * A, mu, p0, sign=sign)
    assert np.sqrt(np.mean((prof.shear(x) - ref) ** 2)) < 0.01 * mu * p0
    assert np.all(np.abs(prof.shear(x)) <= mu * prof.pressure(x) * (1 + 1e-12))
    assert w @ prof.shear(s) == pytest.approx(w @ (sign * mu * p - r), rel=1e-9)


def test_tied_zone_shear_with_square_root_edges():
    # a flat punch's tangential traction Q / (pi sqrt(c^2 - s^2)): the T_k / sqrt(1 - x^2) space
    c, big_q = 0.7, 2.0
    s, w = _quadrature(c, H)
    q = big_q / (math.pi * np.sqrt(c**2 - s**2))
    coef = T.project(s, w, q, c, T.modes_for(c, H), singular=True)
    assert w @ T._series(coef, s, c, singular=True) == pytest.approx(w @ q, rel=1e-12)
    x = np.linspace(-0.9 * c, 0.9 * c, 101)
    ref = big_q / (math.pi * np.sqrt(c**2 - x**2))
    assert np.max(np.abs(T._series(coef, x, c, singular=True) - ref)) < 1e-3 * ref.max()


def test_tension_is_not_reported():
    s, w = _quadrature(A, H)
    data = theory.hertz_pressure(s, A, 1.0) - 0.3 * (s / A) ** 8  # tensile at the edges
    prof = T.TractionProfile(A, 0.0, 0.0, 0.0, T.project(s, w, data, A, 12), np.zeros(0), np.zeros(0))
    x = np.linspace(-1.25, 1.25, 501)
    assert prof.pressure(x).min() >= 0.0
    assert np.all(prof.pressure(x[np.abs(x) >= A]) == 0.0)


@pytest.fixture(scope="module")
def turned_frictionless():
    from ibfem.solver.solving import solve

    problem = cylinder_on_block("frictionless", turn=25.0)
    return solve(problem)


def _hertz(c):
    e = theory.effective_modulus(2.0e11, 0.3, 2.0e11, 0.3)
    a = theory.hertz_half_width(c["normal_force"], 1.0, e)
    return a, theory.hertz_peak_pressure(c["normal_force"], a)


def test_reported_pressure_of_a_turned_scene_against_hertz(turned_frictionless):
    # the grid turned by 25 degrees (the former one-cell moving average: 4.2-7.1 % of p0 on the
    # examples turned by 25 degrees, benchmarks/tractions.py)
    c = turned_frictionless.contacts[0]
    assert turned_frictionless.converged
    a, p0 = _hertz(c)
    s, p = np.asarray(c["pressure"]["s"]), np.asarray(c["pressure"]["value"])
    inner = np.abs(s) <= 0.9 * a
    assert np.sqrt(np.mean((p[inner] - theory.hertz_pressure(s[inner], a, p0)) ** 2)) < 0.02 * p0
    assert p.min() >= 0.0
    # zero outside the region [e - a, e + a] (its centre e is the pressure's centroid, here
    # -1.2e-5 m off the contact point: |s| >= a is not "outside" on one side), and nought at its
    # two ends up to round-off (a sample can land on an end: 26 Pa of p0 = 1.1e9 Pa seen)
    lo, hi = c["region"]
    assert np.all(p[(s < lo) | (s > hi)] == 0.0)
    assert np.all(p[np.isclose(s, lo, rtol=0, atol=1e-12) | np.isclose(s, hi, rtol=0, atol=1e-12)] <= 1e-6 * p0)
    assert np.trapezoid(p, s) == pytest.approx(c["normal_force"], rel=2e-3)
    assert c["profile_recovery"]["clipped_force"] <= 1e-9 * c["normal_force"]


def test_reported_shear_of_a_turned_partial_slip_against_cattaneo_mindlin():
    from ibfem.solver.solving import solve

    sol = solve(cylinder_on_block("frictional", ux=4.1e-4, turn=25.0, friction=0.3))
    c = sol.contacts[0]
    assert sol.converged
    a, p0 = _hertz(c)
    s = np.asarray(c["shear"]["s"])
    q, p = np.asarray(c["shear"]["value"]), np.asarray(c["pressure"]["value"])
    ca = theory.cattaneo_mindlin_stick_ratio(c["tangential_force"], c["normal_force"], 0.3)
    inner = np.abs(s) <= 0.95 * a
    ref = theory.cattaneo_mindlin_shear(s[inner], a, ca * a, 0.3, p0, sign=np.sign(c["tangential_force"]))
    assert np.sqrt(np.mean((q[inner] - ref) ** 2)) < 0.05 * 0.3 * p0
    assert np.all(np.abs(q) <= 0.3 * p * (1 + 1e-12))
    assert np.trapezoid(q, s) == pytest.approx(c["tangential_force"], rel=5e-3)


def test_plots_know_when_a_contact_is_hertzian(turned_frictionless):
    from ibfem.solver.io.plots import hertz_reference

    c = turned_frictionless.contacts[0]
    ref = hertz_reference(turned_frictionless.problem, c)
    assert ref["R_eff"] == pytest.approx(1.0, rel=1e-9)  # the cylinder R = 1 on a flat
    assert ref["a"] == pytest.approx(_hertz(c)[0], rel=1e-12)
    assert hertz_reference(turned_frictionless.problem, {**c, "normal_force": 0.0}) is None
