"""The knots of a region of general shape (solver.contact.star_region) spread along a line
contact's edge: each stretch of smooth edge between two knots longer than SPREAD_CELLS finest cells
is cut into equal lengths of at most that, the new knots on the present edge. Checked on a long
region whose edge is known in closed form (the quarter of a rounded rectangle 80 x 24 mm, the
crowned roller's proportions), against its own arc length measured independently on a fine
polyline: equal pieces, none longer than the bound, the edge reproduced by the refined spline,
and a flat contact left alone."""

from __future__ import annotations

import math

import numpy as np

from ibfem.solver.contact.star_region import KNOTS, SPREAD_CELLS, StarRegionContact

LENGTH, WIDTH, H = 0.1, 0.024, 0.00625  # the scale A along the line, the half-width B, the finest cell


def _edge_radius(phi: np.ndarray) -> np.ndarray:
    """rho(phi) of a superellipse |X / 0.78|^4 + |Y|^4 = 1 in the normalised coordinates
    (X, Y) = (s0 / A, s1 / B): a long region with flat sides and rounded ends."""
    c, s = np.abs(np.cos(phi)), np.abs(np.sin(phi))
    return ((c / 0.78) ** 4 + s**4) ** -0.25


def _region(isotropic: bool = False) -> StarRegionContact:
    """A quarter model's region (body 1's sector from 0 to 90 degrees), its knots at the 24 equal
    angles on the edge above; only what the knots' placement reads is set."""
    c = object.__new__(StarRegionContact)
    knots = np.linspace(0.0, 2.0 * math.pi, KNOTS, endpoint=False)
    c.__dict__.update(
        knots=knots, log_rho=np.log(_edge_radius(knots)), length=LENGTH, isotropic=isotropic, h=H,
        ranges=[(0.0, 0.5 * math.pi)], free_knots=np.zeros(KNOTS, dtype=bool), _spline=None, _spread=False,
        across=np.zeros(KNOTS, dtype=bool), extra_shape_updates=0, _before_split=None,
        _knot_history=[], _knot_since=np.zeros(KNOTS, dtype=int), knot_moments=np.full(KNOTS, math.nan))
    return c


def _points(c: StarRegionContact, phi: np.ndarray) -> np.ndarray:
    return c.rho(phi)[:, None] * np.stack([LENGTH * np.cos(phi), WIDTH * np.sin(phi)], axis=1)


def _arc(c: StarRegionContact, phi0: float, phi1: float) -> float:
    """The edge's length from phi0 to phi1 on a polyline of 20,000 pieces."""
    p = _points(c, np.linspace(phi0, phi1, 20001))
    return float(np.hypot(*np.diff(p, axis=0).T).sum())


def test_spread_knots_cut_a_long_regions_edge_into_equal_lengths():
    c = _region()
    before = c.knots.copy()
    phi = np.linspace(0.0, 0.5 * math.pi, 2001)
    edge = _points(c, phi)
    assert c.spread_knots(WIDTH)
    assert not c.spread_knots(WIDTH)  # once per load step
    inside = c.knots[c.knots <= 0.5 * math.pi + 1e-12]
    assert len(inside) > 7  # the quarter's 7 knots at equal angles had two on the 60 mm of side
    assert set(before).issubset(set(c.knots))  # the old knots stay where they were
    assert len(c.knots) == len(before) + len(inside) - 7  # knots inserted within the quarter only
    for k0, k1 in zip(before[:6], before[1:7]):  # each old stretch: equal pieces of at most the bound
        cuts = inside[(inside >= k0 - 1e-12) & (inside <= k1 + 1e-12)]
        pieces = np.array([_arc(c, a, b) for a, b in zip(cuts[:-1], cuts[1:])])
        assert pieces.max() <= SPREAD_CELLS * H * (1.0 + 1e-3)
        assert pieces.max() - pieces.min() <= 2e-3 * pieces.max()
        if len(cuts) > 2:  # cut: the bound forced it
            assert pieces.sum() > SPREAD_CELLS * H
    # the new knots lie on the present edge: the refined spline reproduces the edge it was given
    np.testing.assert_allclose(_points(c, phi), edge, atol=2e-3 * H)
    assert c._before_split is not None and c.extra_shape_updates > 0  # undone if the knots do not settle


def test_spread_knots_leave_a_flat_contact_alone():
    c = _region(isotropic=True)
    assert not c.spread_knots(WIDTH)
    assert len(c.knots) == KNOTS


def test_spread_knots_skip_a_stretch_at_a_free_edge():
    """A knot whose ray ends at body 1's free edge (complete contact) has no smooth edge: the
    stretches on either side of it are not cut, the others are."""
    c = _region()
    c.free_knots[5] = True  # 75 degrees, on the side between two long stretches
    c.spread_knots(WIDTH)
    deg = np.degrees(c.knots)
    assert np.count_nonzero((deg > 60.0 + 1e-9) & (deg < 90.0 - 1e-9)) == 1  # the free knot alone
    assert np.count_nonzero((deg > 45.0 + 1e-9) & (deg < 60.0 - 1e-9)) >= 1  # a long stretch elsewhere: cut
