"""Stability of the 2D stiffness on ill-supported cut cells (solver.fem.aggregation on the
quadtree): an edge a hair above a grid line leaves a row of slivers whose upper nodes only the
slivers hold. Aggregated, the stiffness with its boundary terms is positive definite with bounded
conditioning; the extension of the ill-supported nodes reproduces linear fields (with hanging
nodes), so a constant stress stays exact (the 2D counterpart of tests/test_solid_stability.py)."""

import numpy as np
import pytest

from ibfem.geometry.shapes import profile_from_shape
from ibfem.solver.fem.aggregation import _multilinear, _reference_corners
from ibfem.solver.fem.assembly import boundary_terms
from ibfem.solver.fem.elements import element_for
from ibfem.solver.fem.grid import QUADTREE_AGGREGATION_THRESHOLD, build_grid, polyline_boundary
from ibfem.solver.fem.octree import build_octree
from ibfem.solver.fem.space import discretise_body, number_dofs
from ibfem.solver.model import problem as pb
from ibfem.solver.model.options import SolverOptions
from ibfem.solver.solving import solve

from _conditioning import conditioning

E, NU = 2.0e11, 0.3
MATERIAL = pb.Material("m", E, NU)
H = 0.2
SETTINGS = SolverOptions(grid_offset=(0.0, 0.0))
HELD = (pb.Fixed("plate", "top"), pb.Sliding("plate", "left"), pb.Sliding("plate", "bottom"))


def _sliver_plate(gap, zones=()):
    """A 1 x 0.4 plate whose top edge lies ``gap`` cells above the grid line y = 2 H."""
    profile = profile_from_shape({"type": "rectangle", "min": [0, 0], "max": [5 * H, (2.0 + gap) * H]})
    return pb.BodyModel("plate", profile, MATERIAL, H, zones)


def _body(model, threshold=QUADTREE_AGGREGATION_THRESHOLD):
    body = discretise_body(model, 0, "plane_strain", True, SETTINGS, aggregation_threshold=threshold)
    number_dofs([body])
    return body


def _k0(model, body, bcs=HELD):
    """Dense volume stiffness plus the thin-band terms of ``bcs`` (the K0 of a solve)."""
    problem = pb.Problem("p", "plane_strain", 1.0, (model,), bcs)
    k, _, _ = boundary_terms(problem, [body], SETTINGS, body.stiffness(SETTINGS.fictitious_stiffness))
    return k.toarray()


@pytest.mark.parametrize("gap", [1e-9, 1e-5])
def test_edge_a_hair_above_a_grid_line_gives_a_positive_definite_stiffness(gap):
    model = _sliver_plate(gap)
    body = _body(model)
    g = body.grid
    assert (g.inside_fraction < 1.01 * gap).sum() == 5  # the row of slivers
    assert g.n_hanging == 6  # their upper nodes, extended from the cells below
    k = _k0(model, body)
    np.linalg.cholesky(k)  # raises unless positive definite
    smallest, ratio = conditioning(k)
    assert smallest > 0 and ratio < 1e3  # measured 26 (1e-9 and 1e-5 alike)
    # the top edge's band is sized by the aggregate (a sliver and the full cell below it:
    # 2 A / L = 2 H (1 + gap) in the middle, H (1 + gap) / (1 + gap / 2) at the corners, where
    # the sides x0 and x1 add H to L; at most the cell size H), not by the sliver's own width
    # (2 gap H)
    t = g.material_thickness[g.pieces.cell[g.pieces.of("top")]]
    np.testing.assert_allclose(t, H, rtol=1e-6)


def test_without_aggregation_the_slivers_make_the_stiffness_indefinite_or_ill_conditioned():
    # the defect the aggregation removes (the same plate and conditions as above)
    model = _sliver_plate(1e-9)
    smallest, _ = conditioning(_k0(model, _body(model, threshold=None)))
    assert smallest < 0
    model = _sliver_plate(1e-5)
    smallest, ratio = conditioning(_k0(model, _body(model, threshold=None)))
    assert ratio > 1e10 or smallest < 0  # measured 4e11


def test_hanging_nodes_and_extended_nodes_reproduce_linear_fields():
    zones = (pb.Refinement(2, 0.15, np.array([0.5, 0.4])),)  # fine cells at the sliver edge
    model = _sliver_plate(1e-9, zones)
    body = _body(model)
    g = body.grid
    ill = np.ones(len(g.nodes), dtype=bool)
    ill[g.cells[g.inside_fraction >= QUADTREE_AGGREGATION_THRESHOLD].ravel()] = False
    hanging = (g.constraint != 0).sum(axis=1).A1 > 1
    assert (ill & hanging).any() and (~ill & hanging).any()  # both kinds of constrained nodes
    a = np.array([[0.3, -1.2], [2.0, 0.1]])
    b = np.array([0.2, -0.3])
    u = g.constraint @ (g.nodes[g.free_nodes] @ a.T + b)
    np.testing.assert_allclose(u, g.nodes @ a.T + b, atol=1e-12)
    k = _k0(model, body)
    np.linalg.cholesky(k)
    smallest, ratio = conditioning(k)
    assert smallest > 0 and ratio < 1e3  # measured 64


def test_constant_stress_exact_with_a_row_of_slivers():
    # sliding edges left and bottom on grid lines, top a hair above one: the slivers' upper
    # nodes extended; tractions of a constant stress (no shear: the sliding edges carry none)
    # on top and right
    model = _sliver_plate(1e-9)
    sigma = np.array([[1.0e8, 0.0], [0.0, -0.5e8]])
    bcs = (pb.Sliding("plate", "left"), pb.Sliding("plate", "bottom"),
           pb.Traction("plate", "right", tuple(sigma[:, 0])), pb.Traction("plate", "top", tuple(sigma[:, 1])))
    problem = pb.Problem("patch", "plane_strain", 1.0, (model,), bcs)
    sol = solve(problem.with_options(grid_offset=(0.0, 0.0)))
    x = np.random.default_rng(3).uniform(0.01, 0.99, (300, 2)) * [5 * H, 2 * H]
    voigt = np.array([1.0e8, -0.5e8, 0.0])
    assert np.abs(sol.stress(x) - voigt).max() < 1e-6 * 1.0e8


@pytest.mark.parametrize("dim", [2, 3])
def test_the_extension_uses_the_cell_types_shape_functions(dim):
    # the aggregation evaluates the multilinear basis from the grid's corner order itself (it may
    # not import solver.fem.elements): the same values as the element's, inside and outside
    if dim == 2:
        grid = build_grid(polyline_boundary([{"edge": np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]], float)}]), 0.5)
    else:
        grid = build_octree(((0.0, 0.0, 0.0), (1.0, 1.0, 1.0)), 0.5)
    local = np.random.default_rng(dim).uniform(-3.0, 3.0, (50, dim))
    expected, _ = element_for(dim).shape_functions(local)
    np.testing.assert_allclose(_multilinear(local, _reference_corners(grid)), expected, atol=1e-14)


def test_threshold_out_of_range_is_refused():
    boundary = polyline_boundary([{"edge": np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]], float)}])
    with pytest.raises(ValueError, match="aggregation threshold"):
        build_grid(boundary, 0.25, aggregation_threshold=-0.1)
