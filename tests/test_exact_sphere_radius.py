"""The half-space contact radius of a sphere with its exact gap (reference.theory.exact_sphere_radius)
against the closed form of Sneddon's load for the sphere, N(a) = E* [(R^2 + a^2) / 2 ln((R + a) /
(R - a)) - a R] (the integral of r^3 / sqrt((R^2 - r^2)(a^2 - r^2)) done by hand), and Hertz's
radius in the limit a / R -> 0."""

from __future__ import annotations

import math

import pytest

from ibfem.solver.reference import theory

E_STAR = 2.0e11 / (2.0 * (1.0 - 0.3**2))


def sneddon_sphere_load(a: float, R: float, e_star: float) -> float:
    return e_star * (0.5 * (R * R + a * a) * math.log((R + a) / (R - a)) - a * R)


@pytest.mark.parametrize("ratio", [0.01, 0.045, 0.2, 0.5, 0.8])
def test_radius_is_the_root_of_the_closed_form_load(ratio):
    R = 0.7
    a = ratio * R
    load = sneddon_sphere_load(a, R, E_STAR)
    assert theory.exact_sphere_radius(load, R, E_STAR) == pytest.approx(a, rel=1e-10)


def test_small_contacts_are_hertzian_and_the_exact_gap_shrinks_the_radius():
    # N = 4 E* a^3 / (3 R) (1 + 2 (a / R)^2 / 5 + ...): a = a_Hertz (1 - (a / R)^2 / 7.5 + ...)
    for load in (1.0, 1e3):
        hertz = theory.hertz_sphere_radius(load, 1.0, E_STAR)
        assert theory.exact_sphere_radius(load, 1.0, E_STAR) == pytest.approx(hertz * (1.0 - hertz**2 / 7.5), rel=1e-9)
    big = 4.0 * 3.388567e6  # the sphere on a flat's force: a / R = 0.045
    ratio = theory.exact_sphere_radius(big, 1.0, E_STAR) / theory.hertz_sphere_radius(big, 1.0, E_STAR)
    assert -3e-4 < ratio - 1.0 < -2.5e-4   # (a / R)^2 / 7.5 = 2.7e-4 below Hertz


def test_bad_input_is_refused():
    with pytest.raises(ValueError, match="R"):
        theory.exact_sphere_radius(1.0, -1.0, E_STAR)
    with pytest.raises(ValueError, match="contact radius"):
        theory.exact_sphere_radius(1e15, 1.0, E_STAR)
    assert theory.exact_sphere_radius(0.0, 1.0, E_STAR) == 0.0
