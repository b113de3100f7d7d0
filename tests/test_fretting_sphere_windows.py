"""The shear means of the 3D friction history's zone rule (solver.contact.friction_history3d):
a stuck point near the slip zone or near the region's edge is judged on the mean over a window
symmetric about it, so a field linear across that boundary is read at the point itself (the
mean of a linear field over a window symmetric about a point is its value there), where the
plain mean over the disc is pulled away from the boundary by about 0.4 of the disc's radius."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from ibfem.solver.contact import friction_history3d as fh
from ibfem.solver.contact.disc_means import DiscBins

A, H = 1.0, 0.2  # the region's radius and the cell size: the mean's disc has radius H / 2


def _fake(spacing: float = H / 12):
    """A circular region of radius A on a square lattice of points, each of weight spacing^2,
    with the contact's attributes the means use."""
    g = np.arange(-A, A + spacing / 2, spacing)
    s = np.array([(x, y) for x in g for y in g if x * x + y * y < A * A])
    radius = 0.5 * fh.MEAN_CELLS * H
    nb = DiscBins.build(s, np.full(len(s), spacing ** 2), radius)
    contact = SimpleNamespace(options=SimpleNamespace(window=1.0), h=H, local=lambda v: v,
                              normalised_radius=lambda v, a: np.hypot(v[:, 0], v[:, 1]) / a)
    contact._edge_distance = lambda reg: fh.HistoryEllipseContact._edge_distance(contact, reg)
    reg = SimpleNamespace(a=A, neighbours=nb, info=(SimpleNamespace(s=s),))
    return contact, reg, s


def _means(contact, reg, v, slip, edge_windows: bool, monkeypatch):
    monkeypatch.setattr(fh, "EDGE_WINDOWS", edge_windows)
    return fh.HistoryEllipseContact._means(contact, reg, v, slip)


def test_a_field_linear_towards_the_edge_is_read_at_the_point(monkeypatch):
    contact, reg, s = _fake()
    r = np.hypot(s[:, 0], s[:, 1])
    v = 5.0 * r  # linear in the distance from the edge
    stuck = np.zeros(len(s), dtype=bool)
    rim = (r > A - 0.5 * H) & (r < A - 0.05 * H)  # within the disc of the edge, not on it
    symmetric = _means(contact, reg, v, stuck, True, monkeypatch)
    plain = _means(contact, reg, v, stuck, False, monkeypatch)
    assert np.max(np.abs(symmetric[rim] - v[rim])) < 0.1 * 5.0 * 0.5 * H
    # the plain mean over the disc lies inside the region: its value is read too far in
    outermost = r > A - 0.1 * H
    assert np.mean(v[outermost] - plain[outermost]) > 0.2 * 5.0 * 0.5 * H
    deep = r < A - 0.6 * H  # beyond the disc of the edge both are the plain mean
    np.testing.assert_allclose(symmetric[deep], plain[deep], rtol=1e-12)


def test_the_slip_zone_and_the_edge_windows_together(monkeypatch):
    # a slip annulus beyond r = 0.9 A: a stuck point near it is read by the slip zone's window;
    # a field linear in r (the shear rising towards the stick zone's boundary) is read at the point
    contact, reg, s = _fake()
    r = np.hypot(s[:, 0], s[:, 1])
    slip = r > 0.9 * A
    v = np.column_stack([3.0 * r, np.zeros(len(s)), np.zeros(len(s))])
    out = _means(contact, reg, v, slip, True, monkeypatch)
    band = ~slip & (r > 0.9 * A - 0.45 * H) & (r < 0.9 * A - 0.15 * H)
    assert np.max(np.abs(out[band, 0] - v[band, 0])) < 0.15 * 3.0 * 0.5 * H
    # slipping points keep the plain mean over the slipping points of their disc
    assert np.all(np.isfinite(out[slip]))
