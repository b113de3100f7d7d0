"""The free end's value of a region with a corner (solver.contact.ends.free_end_value): its
weight vanishes quadratically at the corner, so an O(1) error of the discrete pressure's singular
value within the cells next to the corner (what a grid turned against the corner's edge leaves
uncancelled) moves the free end's value by about (h / a)^(5/2) of the corner's value, not
(h / a)^(3/2) as a weight vanishing linearly would."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ibfem.solver.contact.ends import _free_weight, free_end_value


def _nodes(n: int = 20000):
    theta = (np.arange(n) + 0.5) * np.pi / n
    return np.cos(theta), np.sin(theta) * np.pi / n  # x and ds / a (Gauss-Chebyshev)


@pytest.mark.parametrize("free", [1, -1])
def test_weight_vanishes_quadratically_at_the_corner(free):
    # w(x) = (1 + free x)^2 r(x), r(-free) != 0: ten times nearer the corner, a hundred times less
    near, nearer = (_free_weight(free, -free * (1.0 - d)) for d in (1e-4, 1e-5))
    assert near / nearer == pytest.approx(100.0, rel=1e-3)


@pytest.mark.parametrize("cells", [20.0, 40.0])
def test_an_error_at_the_corner_moves_the_free_end_by_its_weight_only(cells):
    # Johnson's tilted flat punch (Contact Mechanics, 1985, sec. 2.8): Q = P / pi (1 + x) with the
    # corner at x = +1, the free end x = -1 at Q = 0; the discrete pressure's error: +-100 % of the
    # singular value, alternating cell by cell over the two cells next to the corner
    a, load = 0.007, 1.0e6
    x, w = _nodes()
    s_w = a * w
    p = load / (math.pi * a) * (1.0 + x) / np.sqrt(1.0 - x * x)
    assert free_end_value(x, s_w, p, a, -1) == pytest.approx(0.0, abs=1e-6 * load / math.pi)
    r_cells = (1.0 - x) * cells  # distance from the corner in cells
    sign = np.where(np.floor(r_cells) % 2 == 0, 1.0, -1.0)
    wrong = p * np.where(r_cells < 2.0, 1.0 + sign, 1.0)
    moved = abs(free_end_value(x, s_w, wrong, a, -1)) / (2.0 * load / math.pi)  # of the corner's Q
    assert moved < 3.0 * cells ** -2.5  # a weight vanishing linearly: about cells^-1.5
