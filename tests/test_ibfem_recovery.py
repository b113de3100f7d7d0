"""Stress recovery: exact for linear fields, accurate at the boundary."""

import numpy as np

from ibfem.geometry.shapes import profile_from_shape
from ibfem.solver.fem.grid import RefinementZone, build_grid
from ibfem.solver.fem.space import exact_boundary
from ibfem.solver.fem.recovery import nodal_stress


def test_linear_cell_field_is_recovered_exactly_at_every_node():
    # centroid values of a linear field -> exact nodal values: the plain mean is exact for
    # symmetric interior patches, the boundary fit for any patch
    prof = profile_from_shape({"type": "half_disk", "center": [0, 0], "radius": 1.0, "side": "above", "rotate_deg": 17})
    grid = build_grid(exact_boundary(prof), 0.1, (RefinementZone(2, 0.2, np.array([0.2, 0.3])),))
    m = grid.moments
    cent = grid.center + 0.5 * grid.size[:, None] * np.column_stack([m[:, 1, 0], m[:, 0, 1]]) / m[:, 0, 0, None]
    f = lambda p: np.column_stack([1 + 2 * p[:, 0] - p[:, 1], 3 * p[:, 1], -0.5 * p[:, 0]])  # noqa: E731
    rec = nodal_stress(grid, cent, f(cent))
    # interior nodes of uniform patches and all nodes next to the boundary
    near = np.zeros(len(grid.nodes), bool)
    near[grid.cells[grid.status == 2].ravel()] = True
    assert np.allclose(rec[near], f(grid.nodes[near]), atol=1e-10)
    uniform = np.zeros(len(grid.nodes), bool)
    uniform[grid.cells[grid.level == 0].ravel()] = True
    interior = uniform & ~near
    # the mean of four centroids of equal squares around a node is exact for linear fields
    lv = np.zeros(len(grid.nodes), int)
    np.maximum.at(lv, grid.cells.ravel(), np.repeat(grid.level, 4))
    same = interior & (lv == 0)
    assert same.sum() > 50
    assert np.allclose(rec[same], f(grid.nodes[same]), atol=1e-10)
