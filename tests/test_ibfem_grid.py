"""Background grids: classification, refinement, hanging nodes, point location."""

import numpy as np
import pytest

from ibfem.geometry.shapes import profile_from_shape
from ibfem.solver.fem.grid import CUT, INSIDE, RefinementZone, build_grid, polyline_boundary
from ibfem.solver.fem.space import exact_boundary


def _area(grid):
    return float((grid.moments[:, 0, 0] * (0.5 * grid.size) ** 2).sum())


@pytest.mark.parametrize("offset", [(0.0, 0.0), (0.5, 0.5), (1e-9, 0.3), (0.999999, 0.0)])
def test_rectangle_on_grid_lines_and_nodes(offset):
    # edges along grid lines / through nodes, and shifted by round-off amounts
    prof = profile_from_shape({"type": "rectangle", "min": [0.0, 0.0], "max": [1.0, 0.6]})
    grid = build_grid(exact_boundary(prof), 0.1, offset=offset)
    assert abs(_area(grid) - 0.6) < 1e-12
    assert np.all(grid.inside_fraction > 0)
    # every boundary piece is in exactly one cell and the pieces cover every edge once
    for name, length in [("bottom", 1.0), ("right", 0.6), ("top", 1.0), ("left", 0.6)]:
        sel = grid.pieces.of(name)
        assert abs(np.abs(grid.pieces.t1[sel] - grid.pieces.t0[sel]).sum() - length) < 1e-12


def test_thin_sliver_and_bulge_through_one_side_are_found():
    # the top edge lies 1e-7 h above a grid line: a sliver cell row with no corner inside
    h = 0.1
    prof = profile_from_shape({"type": "rectangle", "min": [0.0, 0.0], "max": [1.0, 0.5 + 1e-8]})
    grid = build_grid(exact_boundary(prof), h)
    assert abs(_area(grid) - (0.5 + 1e-8)) < 1e-13
    assert np.any((grid.status == CUT) & (grid.inside_fraction < 1e-6))
    # a disk bulging 1e-3 h through the side of a cell whose corners are all outside
    R = 0.30001
    prof = profile_from_shape({"type": "disk", "center": [0.0, 0.0], "radius": R})
    grid = build_grid(exact_boundary(prof), h, offset=(0.9999, 0.4999))  # x = -0.3 a grid line, y = 0 mid-cell
    assert abs(_area(grid) - np.pi * R**2) < 1e-12
    corners_out = np.all(np.hypot(*grid.nodes[grid.cells].transpose(2, 0, 1)) > R, axis=1)
    assert np.any(corners_out & (grid.status == CUT))


def test_refinement_levels_grading_and_balance():
    prof = profile_from_shape({"type": "rectangle", "min": [-2.0, -1.0], "max": [2.0, 1.0]})
    zone = RefinementZone(3, 0.3, np.array([0.4, 0.95]))
    grid = build_grid(exact_boundary(prof), 0.2, (zone,), offset=(0.23, 0.41))
    d = np.hypot(*(grid.center - zone.center).T)
    assert np.all(grid.level[d < 0.3] == 3)
    assert grid.min_size == pytest.approx(0.2 / 8)
    assert np.all(grid.level[d > 2.0] == 0)
    assert abs(_area(grid) - 8.0) < 1e-12
    # 2:1 balance: cells sharing any node differ by at most one level
    node_level_max = np.zeros(len(grid.nodes), int)
    node_level_min = np.full(len(grid.nodes), 99)
    np.maximum.at(node_level_max, grid.cells.ravel(), np.repeat(grid.level, 4))
    np.minimum.at(node_level_min, grid.cells.ravel(), np.repeat(grid.level, 4))
    assert np.all(node_level_max - node_level_min <= 1)
    assert grid.n_hanging > 0


def test_hanging_node_constraints_reproduce_linear_fields():
    prof = profile_from_shape({"type": "disk", "center": [0.0, 0.0], "radius": 1.0})
    zones = (RefinementZone(4, 0.1, np.array([0.3, 0.2])), RefinementZone(2, 0.2, np.array([-0.6, 0.0])))
    grid = build_grid(exact_boundary(prof), 0.25, zones)
    f = lambda p: 1.5 + 2.0 * p[:, 0] - 0.7 * p[:, 1]  # noqa: E731
    u = grid.constraint @ f(grid.nodes[grid.free_nodes])
    assert np.allclose(u, f(grid.nodes), atol=1e-13)
    # and a constant stays a constant (rows sum to one)
    assert np.allclose(np.asarray(grid.constraint.sum(axis=1)).ravel(), 1.0)


def test_locate_points_in_quadtree():
    prof = profile_from_shape({"type": "rectangle", "min": [0.0, 0.0], "max": [1.0, 1.0]})
    grid = build_grid(exact_boundary(prof), 0.125, (RefinementZone(2, 0.2, np.array([0.5, 0.5])),))
    rng = np.random.default_rng(3)
    pts = rng.uniform(0, 1, (5000, 2))
    pts[:4] = [[1.0, 1.0], [0.0, 0.0], [1.0, 0.3], [0.5, 0.5]]  # corners and shared nodes
    cell = grid.locate(pts)
    assert np.all(cell >= 0)
    lo = grid.lower[cell]
    hi = lo + grid.size[cell, None]
    assert np.all((pts >= lo - 1e-12) & (pts <= hi + 1e-12))
    assert np.all(grid.locate(np.array([[1.5, 0.5], [-0.1, 0.2]])) == -1)


def test_polyline_boundary_with_hole_area_is_polygon_area():
    outer = {"o1": [[0, 0], [3, 0], [3, 2]], "o2": [[3, 2], [0, 2], [0, 0]]}
    hole = {"h": [[1, 0.5], [1.3, 1.5], [2.2, 1.1], [1, 0.5]]}
    grid = build_grid(polyline_boundary([outer, hole]), 0.17, offset=(0.3, 0.1))
    hole_area = 0.5 * abs(0.3 * 0.6 - 1.0 * 1.2)
    assert abs(_area(grid) - (6.0 - hole_area)) < 1e-12
    assert set(np.unique(grid.status)) <= {INSIDE, CUT}


def test_bad_element_size_is_a_clear_error():
    prof = profile_from_shape({"type": "rectangle", "min": [0.0, 0.0], "max": [1.0, 1.0]})
    with pytest.raises(ValueError, match="element_size"):
        build_grid(exact_boundary(prof), -0.1)


def _quarter_annulus(rot):
    return profile_from_shape({"type": "profile", "rotate_deg": rot, "edges": [
        {"name": "bottom", "type": "line", "start": [1.0, 0.0], "end": [2.0, 0.0]},
        {"name": "outer", "type": "arc", "center": [0, 0], "radius": 2.0, "start_angle": 0, "end_angle": 90},
        {"name": "left", "type": "line", "start": [0.0, 2.0], "end": [0.0, 1.0]},
        {"name": "inner", "type": "arc", "center": [0, 0], "radius": 1.0, "start_angle": 90, "end_angle": 0}]})


@pytest.mark.parametrize("rot", [0.0, 27.3, 45.0, 90.0])
def test_quarter_annulus_cells_are_exact_and_bounded(rot):
    prof = _quarter_annulus(rot)
    grid = build_grid(exact_boundary(prof), 0.05, (RefinementZone(2, 0.2, np.array([0.0, 1.0])),))
    assert abs(_area(grid) - 0.75 * np.pi) < 1e-12
    # every cell's inside part is a fraction of the cell, and cut cells hold boundary length
    assert np.all(grid.inside_fraction > -1e-14) and np.all(grid.inside_fraction < 1 + 1e-12)
    lengths = {"bottom": 1.0, "left": 1.0, "inner": 0.5 * np.pi, "outer": np.pi}
    assert abs(grid.boundary_length.sum() - sum(lengths.values())) < 1e-12
