"""Contact geometry (solver.contact.geometry): chord matching, Delta and the contact-curve quadrature,
checked against closed forms for circles and lines."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from ibfem.geometry.bounded import Arc
from ibfem.geometry.shapes import profile_from_shape
from ibfem.solver.contact.geometry import contact_geometry, contact_quadrature, parameter_at_chord, sample_points
from ibfem.solver.fem.grid import RefinementZone, build_grid
from ibfem.solver.fem.space import exact_boundary
from ibfem.solver.fem.integration import Polyline


def _body(shape, h=0.1, levels=3):
    prof = profile_from_shape(shape)
    boundary = exact_boundary(prof)
    grid = build_grid(boundary, h, (RefinementZone(levels, 0.15, np.zeros(2)),))
    return SimpleNamespace(profile=prof, boundary=boundary, grid=grid)


def test_parameter_at_chord_exact_on_arc_and_polyline():
    arc = Arc(np.array([0.0, 1.0]), 1.0, -math.pi, 0.0, "a")
    c = arc.evaluate(np.array([math.pi / 2]))[0]
    chord = np.array([0.0, 1e-5, 0.01, 0.2, 1.0])
    for direction in (1, -1):
        t = parameter_at_chord(arc, c, chord, math.pi / 2, direction)
        # closed form on a circle: chord = 2 R sin(dt / 2)
        np.testing.assert_allclose(np.abs(t - math.pi / 2), 2 * np.arcsin(chord / 2), atol=1e-14)
        assert np.all(np.sign(t[1:] - math.pi / 2) == direction)
    poly = Polyline("p", np.array([[0.0, 0.0], [1.0, 0.1], [2.0, 0.0]]))
    t = parameter_at_chord(poly, np.zeros(2), np.array([0.5, 1.3, 5.0]), 0.0, 1)
    np.testing.assert_allclose(np.hypot(*poly.evaluate(t[:2]).T), [0.5, 1.3], rtol=1e-14)
    assert np.isnan(t[2])  # the polyline ends first


def test_matching_of_two_equal_cylinders_gives_normal_delta():
    upper = _body({"type": "half_disk", "center": [0.0, 1.0], "radius": 1.0, "side": "below"})
    lower = _body({"type": "half_disk", "center": [0.0, -1.0], "radius": 1.0, "side": "above"})
    geom = contact_geometry((upper, lower), ("upper", "lower"), np.zeros(2), 0.1)
    np.testing.assert_allclose(geom.normal, [0.0, 1.0], atol=1e-12)
    np.testing.assert_allclose(geom.tangent, [-1.0, 0.0], atol=1e-12)
    s = np.linspace(-0.08, 0.08, 17)
    pts = sample_points(geom, s)
    # chord matching: both points at chord |s| from the origin, on the same side (x of equal sign)
    np.testing.assert_allclose(np.hypot(*pts.x1.T), np.abs(s), atol=1e-14)
    np.testing.assert_allclose(np.hypot(*pts.x2.T), np.abs(s), atol=1e-14)
    np.testing.assert_allclose(pts.x1[:, 0], pts.x2[:, 0], atol=1e-14)
    # s is positive along the tangent (-x here)
    assert np.all(np.sign(pts.x1[s != 0, 0]) == -np.sign(s[s != 0]))
    # Delta = X1 - X2 (eq. 5-2): vertical, 2 (1 - cos(theta)) with chord = 2 sin(theta / 2)
    theta = 2 * np.arcsin(np.abs(s) / 2)
    np.testing.assert_allclose(pts.delta[:, 0], 0.0, atol=1e-15)
    np.testing.assert_allclose(pts.delta[:, 1], 2 * (1 - np.cos(theta)), atol=1e-15)
    # the contact normal of the matched pairs is the global normal for mirror-image curves
    np.testing.assert_allclose(pts.normal, np.tile([0.0, 1.0], (len(s), 1)), atol=1e-12)


def test_quadrature_length_and_pieces_inside_cells():
    cyl = _body({"type": "half_disk", "center": [0.0, 1.0], "radius": 1.0, "side": "below"}, h=0.1, levels=3)
    block = _body({"type": "rectangle", "min": [-1.0, -1.0], "max": [1.0, 0.0]}, h=0.07, levels=3)
    geom = contact_geometry((cyl, block), ("cyl", "block"), np.zeros(2), 0.12)
    a = 0.05
    q = contact_quadrature(geom, (cyl.grid, block.grid), -a, a, order=4)
    # arc length between chords -a and a on a unit circle
    assert q.weights.sum() == pytest.approx(2 * 2 * math.asin(a / 2), rel=1e-13)
    # flat block: the matched point lies straight below along the frame's normal (same x) on
    # y = 0, and Delta is the initial gap of Hertz's setting, 1 - sqrt(1 - x^2), all normal
    np.testing.assert_allclose(q.x2[:, 0], q.x1[:, 0], atol=1e-14)
    np.testing.assert_allclose(q.x2[:, 1], 0.0, atol=1e-15)
    np.testing.assert_allclose(q.delta[:, 0], 0.0, atol=1e-15)
    np.testing.assert_allclose(q.delta[:, 1], q.x1[:, 0] ** 2 / (1.0 + np.sqrt(1.0 - q.x1[:, 0] ** 2)), atol=1e-15)
    # split at both grids' lines: the 4 points of each piece share a cell in each grid
    for grid, x, n in ((cyl.grid, q.x1, q.n1), (block.grid, q.x2, q.n2)):
        cells = grid.locate(x - 1e-9 * n).reshape(-1, 4)
        assert np.all(cells == cells[:, :1])


def test_pairing_along_the_normal_of_two_unequal_circles():
    # frame mode: pairs at equal tangential offset (x); pair mode: equal chords from the
    # contact point (circles of radius 1 and 3 touching at the origin)
    small = _body({"type": "half_disk", "center": [0.0, 1.0], "radius": 1.0, "side": "below"})
    large = _body({"type": "half_disk", "center": [0.0, -3.0], "radius": 3.0, "side": "above"})
    s = np.linspace(-0.1, 0.1, 21)
    geom = contact_geometry((small, large), ("small", "large"), np.zeros(2), 0.12)
    pts = sample_points(geom, s)
    np.testing.assert_allclose(pts.x2[:, 0], pts.x1[:, 0], atol=1e-14)
    np.testing.assert_allclose(pts.x2[:, 1], -3.0 + np.sqrt(9.0 - pts.x1[:, 0] ** 2), atol=1e-14)
    np.testing.assert_allclose(np.hypot(*pts.x1.T), np.abs(s), atol=1e-14)  # s stays body 1's chord
    geom = contact_geometry((small, large), ("small", "large"), np.zeros(2), 0.12)
    geom.normal_mode = "pair"
    pts = sample_points(geom, s)
    np.testing.assert_allclose(np.hypot(*pts.x2.T), np.abs(s), atol=1e-14)


def test_contact_point_on_a_corner_closes_one_side():
    # the point sits on body 1's corner: the side along the contact's tangent (body 1's bottom
    # edge) stays open, the other is closed by the corner (a half model's symmetry line), and
    # its cause names the corner (not an edge's end or the refinement radius)
    seg = _body({"type": "rectangle", "min": [0.0, 0.0], "max": [1.0, 1.0]})
    other = _body({"type": "rectangle", "min": [-1.0, -1.0], "max": [1.0, 0.0]})
    geom = contact_geometry((seg, other), ("a", "b"), np.array([0.0, 0.0]), 0.1)
    side = geom.mirror_side()
    assert side != 0
    closed = geom.limits[0 if side < 0 else 1]
    assert closed.corner and closed.chord == 0.0 and "corner of body 'a'" in closed.cause
    opened = geom.limits[0 if side > 0 else 1]
    assert opened.chord == pytest.approx(0.1) and opened.cause == "refinement radius"
