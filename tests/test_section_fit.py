"""The plane-strain edge condition of a long region's sides read by the fit of the square-root
form on merged squares (solver.contact.section_fit): for pressures of the form
p0(X) (q0 + q2 t^2) / sqrt(1 - t^2) across each section it reads the square-root coefficient
q0 + q2 as the points' moment does (0 for Hertz's p0 sqrt(1 - t^2), 2/3 for a flat punch's, 0.8
for q0 = 1, q2 = 1/2: the closed-form integrals of the moment), and a sliver's tension balanced
by the rest of its merged square, which pulls the points' moment down, leaves it unchanged."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ibfem.solver.contact.section_fit import _groups
from ibfem.solver.contact.star_region import KNOTS, section_moments

SIZE = 0.23  # the squares' side, in the region's normalised coordinates (about 4 across its half-width)


def _superellipse_radius(phi):
    """The normalised radius of the edge X^4 + Y^2 = 1 (width sqrt(1 - X^4))."""
    c4, s2 = np.cos(phi) ** 4, np.sin(phi) ** 2
    return np.sqrt(2.0 / (s2 + np.sqrt(s2**2 + 4.0 * c4)))


def _region():
    phi = np.linspace(0.0, 2.0 * math.pi, 4000, endpoint=False)
    boundary = _superellipse_radius(phi)[:, None] * np.stack([np.cos(phi), np.sin(phi)], axis=1)
    x, wx = np.polynomial.legendre.leggauss(300)
    theta, wt = np.polynomial.legendre.leggauss(30)
    theta, wt = 0.5 * math.pi * theta, 0.5 * math.pi * wt  # Y = w sin(theta): the edge's 1 / sqrt exact
    width = np.sqrt(1.0 - x**4)
    X, t = np.repeat(x, len(theta)), np.tile(np.sin(theta), len(x))
    points = np.stack([X, np.repeat(width, len(theta)) * t], axis=1)
    area = (wx[:, None] * width[:, None] * np.cos(theta)[None, :] * wt[None, :]).ravel()
    knots = np.linspace(0.0, 2.0 * math.pi, KNOTS, endpoint=False)
    knot_xy = _superellipse_radius(knots)[:, None] * np.stack([np.cos(knots), np.sin(knots)], axis=1)
    sides = np.abs(np.sin(knots)) > 0.6
    return boundary, points, area, t, knot_xy, sides


@pytest.mark.parametrize("peaked, tolerance", [(False, 1e-3), (True, 1e-2)])
def test_fit_reads_the_square_root_coefficient(peaked, tolerance):
    """Constant load along the line: the fit is exact but for the points' rule (1e-3); a load
    peaking threefold over a tenth of the length (a crown's peak, sharper than a real one) varies
    within a column of squares, which the fit's constant q0, q2 per column follow to 1e-2."""
    boundary, points, area, t, knot_xy, sides = _region()
    X = points[:, 0]
    load = 1.0 + 2.0 * np.exp(-(((np.abs(X) - 0.6) / 0.1) ** 2)) if peaked else np.ones_like(X)
    squares = (points, area, np.full(len(knot_xy), SIZE))
    for q0, q2, expected in ((1.0, -1.0, 0.0), (1.0, 0.0, 2.0 / 3.0), (1.0, 0.5, 0.8)):
        pressure = load * (q0 + q2 * t**2) / np.sqrt(1.0 - t**2)
        moment, total, covered = section_moments(points, area * pressure, knot_xy, boundary, sides, squares)
        assert covered[sides].all()
        np.testing.assert_allclose(moment[sides] / total[sides], expected, atol=tolerance)


def test_a_slivers_balanced_tension_leaves_the_fit_unchanged():
    """Hertz's pressure with every sliver (a square filled below three quarters) made tensile by
    0.6 and the force moved to the rest of its merged square at the same station: the points'
    moment reads the edge as too large (below -0.02 on every side knot), the fit as before."""
    boundary, points, area, t, knot_xy, sides = _region()
    hertz = np.sqrt(1.0 - t**2)
    key = np.floor(points / SIZE + 1e-6).astype(np.int64)
    group = _groups(key, area, SIZE)
    _, square = np.unique(key, axis=0, return_inverse=True)
    fill = np.bincount(square.ravel(), weights=area) / SIZE**2
    sliver = fill[square.ravel()] < 0.75
    moved = hertz.copy()
    station = np.unique(points[:, 0], return_inverse=True)[1].ravel()
    for g, x in set(zip(group[sliver], station[sliver])):
        out, inside = (group == g) & (station == x) & sliver, (group == g) & (station == x) & ~sliver
        if inside.any():
            moved[out] -= 0.6
            moved[inside] += 0.6 * area[out].sum() / area[inside].sum()
    squares = (points, area, np.full(len(knot_xy), SIZE))
    before = [section_moments(points, area * p, knot_xy, boundary, sides) for p in (hertz, moved)]
    after = [section_moments(points, area * p, knot_xy, boundary, sides, squares) for p in (hertz, moved)]
    read = [m[sides] / w[sides] for m, w, _ in before + after]
    assert (read[1] < read[0] - 0.02).all()
    np.testing.assert_allclose(read[3], read[2], atol=1e-9)
    np.testing.assert_allclose(read[2], 0.0, atol=1e-3)
