"""The pressure moments and stick ratios a gap of revolution implies, against Sneddon's and
Jaeger's closed forms (Hertz's paraboloid, a cone, a ball's exact profile)."""

import math

import numpy as np
import pytest

from ibfem.solver.contact.gap_moments import (HERTZ_SECOND_MOMENT, axis_second_moment, axis_stick_ratio,
                                              second_moment_targets, stick_ratio_targets)

T = np.linspace(0.0, 0.8, 257)


def test_hertz_paraboloid_has_the_fifth_and_the_cube_root():
    """p = p0 sqrt(1 - r^2 / a^2): <X^2> = 1/5; P ~ a^3, so c / a = (1 - Q / (mu N))^(1/3)."""
    assert axis_second_moment(T, T / 0.3) == pytest.approx(0.2, rel=2e-5)
    for share in (0.05, 0.4, 0.9):
        assert axis_stick_ratio(T, 3.0 * T, share) == pytest.approx(share ** (1.0 / 3.0), abs=1e-12)


def test_a_cone_has_the_sixth_and_the_square_root():
    """p ~ arccosh(a / r): <r^2> = a^2 / 3, so <X^2> = 1/6; P ~ a^2, so c / a = sqrt(share)."""
    slope = np.full_like(T, math.tan(math.radians(10.0)))
    assert axis_second_moment(T, slope) == pytest.approx(1.0 / 6.0, rel=1e-4)
    for share in (0.05, 0.4, 0.9):
        assert axis_stick_ratio(T, slope, share) == pytest.approx(math.sqrt(share), abs=2e-4)


def test_a_balls_exact_profile_is_nearly_hertzian():
    """R - sqrt(R^2 - r^2) at a / R = 0.045: its quartic part moves <X^2> by O((a / R)^2)."""
    t = np.linspace(0.0, 0.045, 257)
    moment = axis_second_moment(t, t / np.sqrt(1.0 - t * t)) - axis_second_moment(t, t) + HERTZ_SECOND_MOMENT
    assert 0.2 < moment < 0.2 * (1.0 + 0.045 ** 2)


def test_axis_samples_of_a_quadratic_gap_give_hertz_on_both_axes_of_an_ellipse():
    """Galin: a quadratic gap's pressure is Hertz's shape on any ellipse: 1/5 on both axes at
    b / a = 0.4, and the cube root for the stick ratio; samples on both sides of the point."""
    s_line = np.linspace(-0.1, 0.1, 401)
    s = np.concatenate([np.c_[s_line, 0 * s_line], np.c_[0 * s_line, s_line]])
    axis = np.repeat([0, 1], len(s_line))
    gap = 0.5 * (3.0 * s[:, 0] ** 2 + 19.0 * s[:, 1] ** 2)
    tx, ty = second_moment_targets(s, gap, axis, (0.05, 0.02))
    assert tx == pytest.approx(0.2, abs=1e-12) and ty == pytest.approx(0.2, abs=1e-12)
    assert stick_ratio_targets(s, gap, axis, (0.05, 0.02), 0.5) == pytest.approx(0.5 ** (1.0 / 3.0), abs=1e-9)
    # samples that stop short of the edge: Hertz's values
    assert second_moment_targets(s, gap, axis, (0.2, 0.2)) == (HERTZ_SECOND_MOMENT, HERTZ_SECOND_MOMENT)
