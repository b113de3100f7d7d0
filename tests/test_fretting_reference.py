"""The line-contact Mindlin-Deresiewicz closed forms (solver.reference.fretting) against
invariants: equilibrium (the shear integrates to Q on every branch), Coulomb's law (|q| <= mu p,
equality in the slip annulus), symmetry of a full reversal, the slip's gradient against the
principal-value integral of the shear (computed numerically), the energy per cycle against the
friction work summed over small load increments, and its small-amplitude limit W ~ Q*^3."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from ibfem.solver.reference.fretting import (branch_stick_ratio, cattaneo_slip, energy_per_cycle, history_shear,
                                             stick_ratio)

N, MU, R, E_STAR = 1.0e8, 0.3, 1.0, 1.0989e11
A = math.sqrt(4.0 * N * R / (math.pi * E_STAR))
P0 = 2.0 * N / (math.pi * A)
X = np.linspace(-A, A, 40001)
P = P0 * np.sqrt(np.clip(1.0 - (X / A) ** 2, 0.0, None))


@pytest.mark.parametrize("turning, q", [([], 0.6e7), ([1.5e7], 0.4e7), ([1.5e7], -1.5e7), ([1.5e7, -1.5e7], 0.9e7)])
def test_shear_in_equilibrium_and_within_coulomb(turning, q):
    shear, c = history_shear(X, A, N, MU, turning, q)
    assert np.trapezoid(shear, X) == pytest.approx(q, rel=1e-6)
    assert np.all(np.abs(shear) <= MU * P * (1.0 + 1e-9) + 1e-9 * MU * P0)
    annulus = (np.abs(X) > c * 1.001) & (np.abs(X) < A * 0.999)
    assert np.allclose(np.abs(shear[annulus]), MU * P[annulus], rtol=1e-9)


def test_full_reversal_mirrors_the_first_loading():
    loaded, c1 = history_shear(X, A, N, MU, [], 1.5e7)
    reversed_, c2 = history_shear(X, A, N, MU, [1.5e7], -1.5e7)
    assert np.allclose(reversed_, -loaded, atol=1e-9 * MU * P0)
    assert c1 == pytest.approx(c2) == pytest.approx(A * stick_ratio(1.5e7, N, MU))
    assert branch_stick_ratio(-1.5e7, 1.5e7, N, MU) == pytest.approx(stick_ratio(1.5e7, N, MU))


def test_slip_gradient_is_the_principal_value_of_the_shear():
    """dh/dx = (2 / (pi E*)) PV int q(xi) / (x - xi) dxi for similar half-planes: the slip S of a
    Cattaneo term grows as that integral (relative to the stick zone, where it vanishes)."""
    c = A * stick_ratio(2.0e7, N, MU)
    k = MU * P0 / A

    def shear(xi):
        return k * (math.sqrt(max(A * A - xi * xi, 0.0)) - math.sqrt(max(c * c - xi * xi, 0.0)))

    for x in (0.5 * c, 0.5 * (c + A), 0.95 * A):
        pv = 0.0  # int q / (xi - x): the Cauchy weight on the piece holding x, plain quadrature elsewhere
        for lo, hi in ((-A, -c), (-c, c), (c, A)):
            if lo < x < hi:
                pv += quad(shear, lo, hi, weight="cauchy", wvar=x, limit=200)[0]
            else:
                pv += quad(lambda xi: shear(xi) / (xi - x), lo, hi, limit=200)[0]
        gradient = -2.0 / (math.pi * E_STAR) * pv
        h = 1e-7 * A
        numeric = (cattaneo_slip(x + h, c, MU, R) - cattaneo_slip(x - h, c, MU, R)) / (2 * h)
        assert float(numeric) == pytest.approx(gradient, rel=1e-4, abs=1e-9 * MU)


def test_energy_equals_the_friction_work_of_small_increments():
    """W from the closed form against the work mu p |d slip| summed over 2000 increments of each
    branch of the cycle (the superposed slips of the history)."""
    q_star = 1.8e7
    w = energy_per_cycle(q_star, N, MU, R, E_STAR)
    total, prev = 0.0, np.zeros_like(X)
    for q in np.linspace(q_star, -q_star, 801):
        c = A * branch_stick_ratio(q, q_star, N, MU)
        slip = 2.0 * cattaneo_slip(X, c, MU, R)
        total += np.trapezoid(MU * P * np.abs(slip - prev), X)
        prev = slip
    assert w == pytest.approx(2.0 * total, rel=2e-3)


def test_small_amplitude_energy_is_cubic():
    q = np.array([1e-3, 2e-3, 4e-3]) * MU * N
    w = np.array([energy_per_cycle(v, N, MU, R, E_STAR) for v in q])
    slope = np.polyfit(np.log(q), np.log(w), 1)[0]
    assert slope == pytest.approx(3.0, abs=0.02)


def test_gross_slip_is_refused():
    with pytest.raises(ValueError, match="gross slip"):
        energy_per_cycle(MU * N, N, MU, R, E_STAR)
