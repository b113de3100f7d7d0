"""Stress recovery (solver.fem.recovery): nodes whose two-ring of cells is uncut take a
quadratic least-squares fit of the centroid stresses, so a quadratic stress field is recovered
exactly there (the plain mean of four centroids is off by h^2/8 of its Laplacian); nodes at the
boundary keep the linear fit, exact for linear fields (tests/test_ibfem_recovery.py)."""

import numpy as np

from ibfem.geometry.shapes import profile_from_shape
from ibfem.solver.fem.grid import CUT, RefinementZone, build_grid
from ibfem.solver.fem.recovery import nodal_stress
from ibfem.solver.fem.space import exact_boundary


def _grid():
    prof = profile_from_shape({"type": "half_disk", "center": [0, 0], "radius": 1.0, "side": "above", "rotate_deg": 17})
    grid = build_grid(exact_boundary(prof), 0.1, (RefinementZone(2, 0.2, np.array([0.2, 0.3])),))
    m = grid.moments
    cent = grid.center + 0.5 * grid.size[:, None] * np.column_stack([m[:, 1, 0], m[:, 0, 1]]) / m[:, 0, 0, None]
    return grid, cent


def _quadratic(p):
    x, y = p[:, 0], p[:, 1]
    return np.column_stack([1 + x * x - 2 * x * y, 3 * y * y + x, -0.5 * x * x + y * y - x * y])


def test_quadratic_field_is_recovered_exactly_where_the_two_ring_is_uncut():
    grid, cent = _grid()
    rec = nodal_stress(grid, cent, _quadratic(cent))
    cut = np.zeros(len(grid.nodes), bool)
    cut[grid.cells[grid.status == CUT].ravel()] = True
    # nodes two cells of their own size away from every cut cell
    near = np.zeros(len(grid.nodes), bool)
    for k in np.nonzero(grid.status == CUT)[0]:
        lo = grid.lower[k] - 2.01 * grid.size[k]
        hi = grid.lower[k] + 3.01 * grid.size[k]
        near |= np.all((grid.nodes >= lo) & (grid.nodes <= hi), axis=1)
    clear = ~near & np.isfinite(rec).all(axis=1)
    assert clear.sum() > 50
    assert np.allclose(rec[clear], _quadratic(grid.nodes[clear]), atol=1e-9)
    # the plain mean of the four centroids would not be: h^2/8 of the Laplacian (here 2, 6, 1)
    inc = np.zeros(len(grid.nodes))
    np.add.at(inc, grid.cells.ravel(), 1.0)
    mean = np.zeros((len(grid.nodes), 3))
    np.add.at(mean, grid.cells.ravel(), np.repeat(_quadratic(cent), 4, axis=0))
    mean /= np.maximum(inc, 1)[:, None]
    assert np.abs(mean[clear] - _quadratic(grid.nodes[clear])).max() > 1e-4
