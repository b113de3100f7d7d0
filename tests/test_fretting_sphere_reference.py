"""The sphere-on-flat Mindlin-Deresiewicz closed forms (solver.reference.fretting_sphere) against
invariants and published limits: equilibrium (the shear integrates to Q on every branch),
Coulomb's law (|q| <= mu p, equality in the current branch's slip annulus), the tangential
stiffness as the derivative of the compliance, the energy per cycle as the area of the loop the
branch compliances draw (integrated numerically), Mindlin's initial stiffness 8 a G* (K. L.
Johnson, Contact Mechanics, 1985, section 7.2) and the small-amplitude limit W = Q*^3 /
(36 a G* mu N) of a loop whose branches are quadratic, with the slope 3 of log W against log Q*."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from ibfem.solver.reference.fretting_sphere import (branch_stick_ratio, displacement_from_stick_radii,
                                                    effective_shear_modulus, energy_per_cycle, hertz_radius, history_shear, small_amplitude_energy,
                                                    stick_ratio, tangential_displacement, tangential_stiffness)

E, NU, R, N, MU = 2.0e11, 0.3, 0.05, 1.0e4, 0.3
E_STAR = E / (2.0 * (1.0 - NU * NU))
G_STAR = effective_shear_modulus(E, NU, E, NU)
A = hertz_radius(N, R, E_STAR)
P0 = 3.0 * N / (2.0 * math.pi * A * A)
RR = np.linspace(0.0, A, 200001)
P = P0 * np.sqrt(np.clip(1.0 - (RR / A) ** 2, 0.0, None))


@pytest.mark.parametrize("turning, q", [([], 1.8e3), ([2.0e3], 0.5e3), ([2.0e3], -2.0e3), ([2.0e3, -2.0e3], 1.2e3)])
def test_shear_in_equilibrium_and_within_coulomb(turning, q):
    shear, c = history_shear(RR, A, N, MU, turning, q)
    assert np.trapezoid(shear * 2.0 * math.pi * RR, RR) == pytest.approx(q, rel=1e-5)
    assert np.all(np.abs(shear) <= MU * P * (1.0 + 1e-9) + 1e-12 * MU * P0)
    annulus = (RR > c * 1.001) & (RR < A * 0.999)
    assert annulus.any()
    assert np.allclose(np.abs(shear[annulus]), MU * P[annulus], rtol=1e-9)
    assert np.all(np.sign(shear[annulus]) == np.sign(q - ([0.0] + turning)[-1]))


def test_stick_radii():
    assert stick_ratio(0.0, N, MU) == 1.0
    assert stick_ratio(0.875 * MU * N, N, MU) == pytest.approx(0.5)  # (1 - 0.875)^(1/3)
    assert branch_stick_ratio(0.25 * MU * N, 2.0 * MU * N, N, MU) == pytest.approx(0.5)
    _, c = history_shear(np.zeros(1), A, N, MU, [0.6 * MU * N], -0.6 * MU * N)
    assert c / A == pytest.approx((1.0 - 1.2 / 2.0) ** (1.0 / 3.0))


def test_stiffness_is_the_compliance_derivative():
    assert tangential_stiffness(0.0, N, MU, A, G_STAR) == pytest.approx(8.0 * A * G_STAR)  # Mindlin
    h = 1e-3
    for turning, q in [([], 1.5e3), ([2.4e3], 0.3e3), ([2.4e3, -2.4e3], 0.7e3)]:
        slope = 2.0 * h / (tangential_displacement(q + h, N, MU, A, G_STAR, turning)
                           - tangential_displacement(q - h, N, MU, A, G_STAR, turning))
        assert slope == pytest.approx(tangential_stiffness(q, N, MU, A, G_STAR, turning), rel=1e-6)


@pytest.mark.parametrize("ratio", [0.3, 0.6, 0.9])
def test_energy_is_the_loop_area(ratio):
    qs = ratio * MU * N
    up = lambda q: tangential_displacement(q, N, MU, A, G_STAR, [qs, -qs])  # noqa: E731
    down = lambda q: tangential_displacement(q, N, MU, A, G_STAR, [qs])  # noqa: E731
    assert up(qs) == pytest.approx(down(qs), rel=1e-12)  # the loop closes at +Q*
    assert up(-qs) == pytest.approx(down(-qs), rel=1e-12)  # ... and at -Q*
    area, _ = quad(lambda q: down(q) - up(q), -qs, qs, epsabs=0.0, epsrel=1e-12, limit=200)
    assert energy_per_cycle(qs, N, MU, A, G_STAR) == pytest.approx(area, rel=1e-8)


def test_small_amplitude_limit():
    # the first loading curve to second order, delta = Q / k0 + beta Q^2 (k0 = 8 a G*), gives
    # branches delta* -+ 2 (dQ / 2 / k0 + beta dQ^2 / 4) and the loop area 4 beta Q*^3 / 3
    beta = (tangential_displacement(1e-3 * MU * N, N, MU, A, G_STAR) - 1e-3 * MU * N / (8.0 * A * G_STAR)) \
        / (1e-3 * MU * N) ** 2
    assert beta == pytest.approx(1.0 / (48.0 * A * G_STAR * MU * N), rel=2e-3)
    for ratio in (1e-4, 1e-3, 1e-2):
        qs = ratio * MU * N
        assert small_amplitude_energy(qs, N, MU, A, G_STAR) == pytest.approx(4.0 * beta * qs ** 3 / 3.0, rel=2e-3)
        assert energy_per_cycle(qs, N, MU, A, G_STAR) == pytest.approx(
            small_amplitude_energy(qs, N, MU, A, G_STAR), rel=2.0 * ratio)
    w = [energy_per_cycle(r * MU * N, N, MU, A, G_STAR) for r in (0.01, 0.02)]
    assert math.log(w[1] / w[0]) / math.log(2.0) == pytest.approx(3.0, abs=0.02)


def _sampled_cycle(ratio: float, per_branch: int):
    """Q at the steps of the first loading to +Q*, a branch to -Q* and one back to +Q*; the turning
    steps; the closed form's stick ratio at each step."""
    qs = ratio * MU * N
    q = np.concatenate([np.linspace(0.0, qs, per_branch // 2 + 1), np.linspace(qs, -qs, per_branch + 1)[1:],
                        np.linspace(-qs, qs, per_branch + 1)[1:]])
    turns = [per_branch // 2, per_branch // 2 + per_branch]
    c = np.array([stick_ratio(v, N, MU) if k <= turns[0] else
                  branch_stick_ratio(v, q[max(t for t in turns if t < k)], N, MU) for k, v in enumerate(q)])
    return q, turns, c


@pytest.mark.parametrize("ratio", [0.3, 0.9])
def test_displacement_from_the_closed_form_stick_radii(ratio):
    # Mindlin's incremental stiffness 8 a G* c integrated over the closed form's stick radii is the
    # closed form's compliance, at second order in the step: its loop is Mindlin-Deresiewicz's W
    errors = []
    for per_branch in (40, 80):
        q, turns, c = _sampled_cycle(ratio, per_branch)
        delta = displacement_from_stick_radii(q, c, turns, A, G_STAR)
        exact = np.array([tangential_displacement(v, N, MU, A, G_STAR, [q[t] for t in turns if t < k])
                          for k, v in enumerate(q)])
        assert np.max(np.abs(delta - exact)) < 2e-3 * np.max(np.abs(exact))
        lo, hi = turns[0], len(q) - 1
        area = -np.sum(0.5 * (q[lo + 1:hi + 1] + q[lo:hi]) * np.diff(exact[lo:hi + 1]))
        area_c = -np.sum(0.5 * (q[lo + 1:hi + 1] + q[lo:hi]) * np.diff(delta[lo:hi + 1]))
        errors.append(abs(area_c / area - 1.0))
        assert abs(area_c) == pytest.approx(energy_per_cycle(ratio * MU * N, N, MU, A, G_STAR), rel=0.01)
    assert errors[1] < 0.01 and errors[0] / errors[1] > 3.0  # second order: 4 per halving


def test_displacement_from_stick_radii_is_stiffer_for_larger_zones():
    # a stick zone larger than the closed form's at every step makes the contact stiffer: smaller |delta|
    q, turns, c = _sampled_cycle(0.6, 40)
    base = displacement_from_stick_radii(q, c, turns, A, G_STAR)
    larger = displacement_from_stick_radii(q, np.minimum(c + 0.01, 1.0), turns, A, G_STAR)
    assert abs(larger[turns[0]]) < abs(base[turns[0]])
    with pytest.raises(ValueError, match="stick_ratios"):
        displacement_from_stick_radii(q, np.zeros_like(q), turns, A, G_STAR)


def test_bad_input():
    with pytest.raises(ValueError, match="gross slip"):
        energy_per_cycle(MU * N, N, MU, A, G_STAR)
    with pytest.raises(ValueError, match="N must be a positive"):
        hertz_radius(-1.0, R, E_STAR)
