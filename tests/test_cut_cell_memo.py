"""The cut cells' moments are integrated once per solid and cell: a second grid over the same solid
(a line contact's coarse pass solved again one level finer, the run's own grid, its error
estimate's) asks the signed distance only about its new cells, and every cell's moments are the
numbers a fresh integration gives (to round-off; a ball's exact volume checks them too)."""

from __future__ import annotations

import math

import numpy as np

from ibfem.geometry.solids import solid_from_dict
from ibfem.solver.fem.cut_cells3d import CUT, classify_cells, inside_moments
from ibfem.solver.fem.solid_space import cut_cell_moments


class _Counted:
    """A solid whose signed distance counts the points it is asked."""

    def __init__(self, solid):
        self.solid, self.asked = solid, 0

    def signed_distance(self, points):
        self.asked += len(points)
        return self.solid.signed_distance(points)


def _cut_cells(solid, h: float, shift: float):
    ijk = np.stack(np.meshgrid(*(np.arange(-4, 4),) * 3, indexing="ij"), axis=-1).reshape(-1, 3)
    lower = ijk * h + shift
    size = np.full(len(lower), h)
    cut = classify_cells(lower, size, solid.signed_distance) == CUT
    return lower[cut], size[cut]


def test_a_second_grid_asks_only_about_its_new_cells():
    ball = _Counted(solid_from_dict({"type": "sphere", "center": [0, 0, 0], "radius": 0.9}))
    lower, size = _cut_cells(ball.solid, 0.25, 0.013)
    first = cut_cell_moments(ball, lower[::2], size[::2])
    asked_first = ball.asked
    assert asked_first > 0
    both = cut_cell_moments(ball, lower, size)  # half of the cells seen already
    asked_second = ball.asked - asked_first
    alone = _Counted(ball.solid)
    inside_moments(lower[1::2], size[1::2], alone.signed_distance, 0)
    assert asked_second == alone.asked  # the new cells' points only
    np.testing.assert_array_equal(both[::2], first)
    fresh = inside_moments(lower, size, ball.solid.signed_distance, 0)
    np.testing.assert_allclose(both, fresh, rtol=0, atol=1e-13)
    again = ball.asked
    cut_cell_moments(ball, lower, size)
    assert ball.asked == again  # nothing new


def test_the_memo_keeps_the_balls_volume():
    ball = solid_from_dict({"type": "sphere", "center": [0, 0, 0], "radius": 0.9})
    h = 0.25
    ijk = np.stack(np.meshgrid(*(np.arange(-4, 4),) * 3, indexing="ij"), axis=-1).reshape(-1, 3)
    lower, size = ijk * h + 0.013, np.full(len(ijk), h)
    status = classify_cells(lower, size, ball.signed_distance)
    cut = status == CUT
    m = cut_cell_moments(ball, lower[cut], size[cut])
    volume = float(m[:, 0].sum() / 8.0 * h**3 + (status == 1).sum() * h**3)
    assert abs(volume - 4.0 / 3.0 * math.pi * 0.9**3) < 1e-6 * volume  # cells of R / 3.6, no subdivision
