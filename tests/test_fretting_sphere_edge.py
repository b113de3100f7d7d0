"""The stick boundary of the 3D friction history placed within the points' spacing
(solver.contact.friction_history_edge): for a stuck shear whose deficit below Coulomb's limit
vanishes with the square root of the distance from a straight boundary (Cattaneo's stick edge),
the points' shares of each zone add up to the stick zone ending at that boundary, whichever side
of the half-way point between the last stuck and the first slipping point it lies on."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.spatial import cKDTree
from types import SimpleNamespace

from ibfem.solver.contact.friction_history_edge import edge_shares

SPACING = 1.0 / 60.0
RADIUS = 0.1  # the zone rule's disc


def _lattice():
    g = np.arange(-30, 31) * SPACING
    s = np.array([(x, y) for x in g for y in g])
    pairs = cKDTree(s).query_pairs(RADIUS, output_type="ndarray")
    rows = np.r_[pairs[:, 0], pairs[:, 1], np.arange(len(s))]
    cols = np.r_[pairs[:, 1], pairs[:, 0], np.arange(len(s))]
    nb = sp.csr_matrix((np.full(len(rows), SPACING ** 2), (rows, cols)), shape=(len(s), len(s)))
    return SimpleNamespace(neighbours=nb, info=(SimpleNamespace(s=s),)), s


@pytest.mark.parametrize("boundary", [0.75 * SPACING, 0.2 * SPACING])
def test_shares_end_the_stick_zone_at_the_root(boundary):
    reg, s = _lattice()
    x = s[:, 0]
    slip = x > 0.5 * SPACING  # the zone rule's zones: the last stuck point at x = 0
    ratio = np.where(slip, 1.0, 1.0 - np.sqrt(3.0 * np.maximum(boundary - x, 0.0)))
    direction = np.where(slip[:, None], [1.0, 0.0, 0.0], 0.0)
    share, out_dir = edge_shares(reg, slip, direction, ratio, RADIUS)
    row = np.abs(s[:, 1]) < 1e-12
    inner = row & (x >= -0.2) & (x <= 0.2)
    stuck_length = SPACING * float(np.sum(1.0 - share[inner]))
    assert stuck_length == pytest.approx(boundary - (-0.2 - 0.5 * SPACING), abs=1e-9)
    assert np.all((share >= 0.0) & (share <= 1.0))
    partial = (share > 0.0) & ~slip
    assert np.allclose(out_dir[partial], [1.0, 0.0, 0.0])


def test_settled_zones_without_a_stick_zone_are_kept():
    reg, s = _lattice()
    slip = np.ones(len(s), dtype=bool)
    share, _ = edge_shares(reg, slip, np.zeros((len(s), 3)), np.ones(len(s)), RADIUS)
    assert np.all(share == 1.0)
