"""The star-shaped region's quadrature graded by the cells it lies in
(solver.contact.graded_quadrature): on an octree with coarse leaves on one side of a plane and
leaves half as large on the other, the rule integrates the sphere's exact area over the region,
integrates a function kinked at every leaf's face (u (1 - u) in each leaf's own coordinates u, as
the finite element fields are: a piece straddling two leaves misses its integral there by 40 %)
as a fine midpoint sum in the tangent plane does, and uses fewer points than the rule spaced by
the finest leaf everywhere."""

from __future__ import annotations

import numpy as np
import pytest

from ibfem.solver.contact.ellipse_geometry import contact_frame_3d, region_points, sectors
from ibfem.solver.contact.graded_quadrature import leaf_size, points_per_cell_face

from _solids3d import HalfBall
from _turned_box import TurnedBox

RADIUS, A, FINE = 1.0, 0.05, 0.005
ORIGIN = np.array([-1.0, -1.0, -1.0])


class TwoLevelGrid:
    """Leaves of 2 FINE for x < 0 and FINE for x >= 0, on the lattices ORIGIN + j size."""

    size = np.array([2 * FINE, FINE])

    def locate(self, points):
        return (np.asarray(points, dtype=float).reshape(-1, 3)[:, 0] >= 0.0).astype(np.int64)


def _kinked(x):
    size = np.where(x[:, 0] >= 0.0, FINE, 2 * FINE)
    local = (x[:, :2] - ORIGIN[:2]) / size[:, None]
    u = local - np.floor(local)
    return (u * (1.0 - u)).sum(axis=1)


def _rule(graded: bool, rho=lambda phi: 1.0 + 0.3 * np.cos(phi) ** 2):
    ball = HalfBall([0, 0, RADIUS + 1e-4], RADIUS)
    block = TurnedBox([2, 2, 1], shift=(-1, -1, -1))
    frame = contact_frame_3d(ball, block, np.zeros(3), 0.01)
    grids = [(ORIGIN, FINE), (ORIGIN, FINE)]
    cells = (leaf_size(TwoLevelGrid(), FINE),) * 2 if graded else None
    return frame, region_points(ball, block, frame, A, A, sectors(ball, frame, 0.01, 0.1), grids, FINE, 0.1,
                                radius=rho, cells=cells)


def test_graded_rule_integrates_the_exact_cap():
    """rho = 1: the disc of radius A, the sphere's cap over it."""
    _, pts = _rule(True, rho=lambda phi: np.ones(len(phi)))
    cap = 2 * np.pi * RADIUS * (RADIUS - np.sqrt(RADIUS**2 - A**2))
    assert pts.weights.sum() == pytest.approx(cap, rel=1e-8)


def test_graded_rule_keeps_each_piece_in_one_leaf():
    """The kinked function of each leaf's coordinates, against a midpoint sum on a 1600^2 grid
    of the tangent plane with the sphere's area element R / sqrt(R^2 - s^2) (converged to 1e-5:
    4800^2 gives the same to that). The rule is within 0.14 %; clipped at the coarse leaves'
    planes alone it is 0.73 % low."""
    frame, pts = _rule(True)
    n = 1600
    s = (np.arange(n) + 0.5) / n * 2.6 * A - 1.3 * A
    s0, s1 = (v.ravel() for v in np.meshgrid(s, s, indexing="ij"))
    st = np.column_stack([s0, s1])
    phi = np.arctan2(s1, s0)
    inside = np.hypot(s0, s1) <= A * (1.0 + 0.3 * np.cos(phi) ** 2)
    st = st[inside]
    y = frame.point + st[:, :1] * frame.axes[0] + st[:, 1:] * frame.axes[1]
    r2 = (st**2).sum(axis=1)
    x = y + (RADIUS - np.sqrt(RADIUS**2 - r2))[:, None] * frame.normal
    reference = (_kinked(x) * RADIUS / np.sqrt(RADIUS**2 - r2)).sum() * (2.6 * A / n) ** 2
    assert (_kinked(pts.x1) * pts.weights).sum() == pytest.approx(reference, rel=3e-3)


def test_graded_rule_puts_fewer_points_in_coarse_leaves():
    """The half of the region in leaves twice as large holds about a quarter of the points the
    finest spacing puts there."""
    _, graded = _rule(True)
    _, uniform = _rule(False)
    coarse = graded.x1[:, 0] < 0.0
    fine_side = (graded.x1[:, 0] >= 0.0).sum() / (uniform.x1[:, 0] >= 0.0).sum()
    coarse_side = coarse.sum() / (uniform.x1[:, 0] < 0.0).sum()
    assert fine_side == pytest.approx(1.0, abs=0.15)
    assert coarse_side < 0.4


def test_point_estimate_counts_each_cell_size_by_its_faces():
    assert points_per_cell_face([(1e-4, 0.01), (1e-4, 0.005)]) == pytest.approx(200.0 * (1.0 + 4.0))
