"""Stability of the 3D stiffness on ill-supported cut cells (solver.fem.aggregation): a face a
hair beyond a grid plane leaves a layer of slivers whose nodes only the slivers hold. Aggregated,
the stiffness with its boundary terms is positive definite with bounded conditioning; the
extension of the ill-supported nodes reproduces linear fields (with hanging nodes), so a
constant stress stays exact."""

import numpy as np
import pytest

from ibfem.solver.fem.aggregation import AGGREGATION_THRESHOLD, aggregate
from ibfem.solver.fem.assembly import boundary_terms
from ibfem.solver.fem.grid import RefinementZone
from ibfem.solver.fem.octree import build_octree
from ibfem.solver.fem.solid_space import discretise_solid
from ibfem.solver.fem.space import number_dofs
from ibfem.solver.model import problem as pb
from ibfem.solver.model.options import SolverOptions
from ibfem.solver.solving import solve

from _conditioning import conditioning
from _turned_box import TurnedBox, rotation

E, NU = 2.0e11, 0.3
MATERIAL = pb.Material("m", E, NU)
H = 0.2
HELD = (pb.Fixed("box", "z1"), pb.Sliding("box", "x0"), pb.Sliding("box", "y0"))


def _body(box, h, zones=(), threshold=AGGREGATION_THRESHOLD):
    body = discretise_solid("box", box, MATERIAL.lame("solid"), MATERIAL.elasticity_matrix("solid"), NU, h, zones,
                            aggregation_threshold=threshold)
    number_dofs([body])
    return body


def _k0(body, bcs=HELD):
    """Dense volume stiffness plus the thin-band terms of ``bcs`` (the K0 of a solve)."""
    settings = SolverOptions(grid_offset=(0.0, 0.0, 0.0))
    problem = pb.Problem("p", "solid", 1.0, (pb.BodyModel("box", body.boundary, MATERIAL, body.element_size),), bcs)
    k, _, _ = boundary_terms(problem, [body], settings, body.stiffness(settings.fictitious_stiffness))
    return k.toarray()


def _sliver_box(gap):
    """A box whose face z1 lies ``gap`` cells above the grid plane z = 2 H."""
    return TurnedBox([0.5, 0.4, (2.0 + gap) * H])


@pytest.mark.parametrize("gap", [1e-9, 1e-5])
def test_face_a_hair_beyond_a_grid_plane_gives_a_positive_definite_stiffness(gap):
    box = _sliver_box(gap)
    body = _body(box, H)
    k = _k0(body)
    np.linalg.cholesky(k)  # raises unless positive definite
    smallest, ratio = conditioning(k)
    # measured 177 (1e-9 and 1e-5 alike): the slivers add nothing to it
    assert smallest > 0 and ratio < 1e4
    # the bands on the face in the slivers are sized by the aggregate (the sliver and the cell
    # below it: 2 V / A, H/2 for the half-full column at x1 with its faces x1 and z1), not by the
    # sliver's own thickness (2 gap H)
    _, _, _, cells = body.face_rules["z1"]
    assert body.inside_volume[cells].max() < 1.01 * gap * H**3
    t = body.material_thickness[cells]
    assert t.min() >= 0.5 * H * (1 - 1e-6) and t.max() <= H


def test_without_aggregation_the_sliver_makes_the_stiffness_indefinite():
    # the defect the aggregation removes (the same body and conditions as above)
    smallest, _ = conditioning(_k0(_body(_sliver_box(1e-9), H, threshold=None)))
    assert smallest < 0


def test_hanging_nodes_and_extended_nodes_reproduce_linear_fields():
    box = _sliver_box(1e-9)
    zones = (RefinementZone(2, 0.15, np.array([0.25, 0.2, 0.4])),)  # fine cells at the sliver face
    body = _body(box, H, zones)
    g = body.grid
    ill = np.ones(len(g.nodes), dtype=bool)
    ill[g.cells[body.inside_volume >= AGGREGATION_THRESHOLD * g.size**3].ravel()] = False
    hanging = (g.constraint != 0).sum(axis=1).A1 > 1
    assert (ill & hanging).any() and (~ill & hanging).any()  # both kinds of constrained nodes
    a = np.array([[0.3, -1.2, 0.7], [2.0, 0.1, -0.4], [-0.5, 0.9, 1.1]])
    b = np.array([0.2, -0.3, 0.05])
    u = g.constraint @ (g.nodes[g.free_nodes] @ a.T + b)
    np.testing.assert_allclose(u, g.nodes @ a.T + b, atol=1e-12)
    k = _k0(body)
    np.linalg.cholesky(k)
    smallest, ratio = conditioning(k)
    assert smallest > 0 and ratio < 1e4  # measured 88


def test_turned_box_stiffness_is_positive_definite_and_bounded():
    box = TurnedBox([0.5, 0.4, 0.3], rotation([0.3, -0.5, 0.8], 0.7), (0.013, -0.021, 0.037))
    k = _k0(_body(box, 0.1))
    np.linalg.cholesky(k)
    smallest, ratio = conditioning(k)
    assert smallest > 0 and ratio < 1e7  # measured 1.1e5 (2.3e11 without aggregation)


def test_constant_stress_exact_with_a_layer_of_slivers():
    # sliding faces x0, y0, z0 on grid planes, z1 a hair above one: the slivers' nodes extended
    box = _sliver_box(1e-9)
    sigma = np.diag([1.0e8, -0.5e8, 0.3e8])
    bcs = [pb.Sliding("box", f) for f in ("x0", "y0", "z0")]
    bcs += [pb.Traction("box", f"{'xyz'[k]}1", tuple(sigma[:, k])) for k in range(3)]
    problem = pb.Problem("patch", "solid", 1.0, (pb.BodyModel("box", box, MATERIAL, H),), tuple(bcs))
    sol = solve(problem.with_options(grid_offset=(0.0, 0.0, 0.0)))
    x = np.random.default_rng(2).uniform(0.02, 0.98, (200, 3)) * box.size
    voigt = np.array([1.0e8, -0.5e8, 0.3e8, 0.0, 0.0, 0.0])
    assert np.abs(sol.stress(x, recovered=False) - voigt).max() < 1e-7 * 1.0e8


def test_threshold_out_of_range_is_refused():
    with pytest.raises(ValueError, match="aggregation threshold"):
        _body(_sliver_box(1e-9), H, threshold=1.5)


def test_aggregates_follow_the_material_across_a_gap():
    # a row of eight cells: part A (a full cell, a sliver), an empty cell, part B (four slivers,
    # a full cell). B's first sliver is nearer A's root (3 cells) than B's (4 cells), but only
    # through the empty cell: its root, and the extension of the nodes on the gap's B side, come
    # from B
    tree = build_octree(((0.0, 0.0, 0.0), (7.5, 0.5, 0.5)), 1.0)
    assert len(tree.level) == 8
    order = np.argsort(tree.index[:, 0])
    fraction = np.empty(8)
    fraction[order] = [1.0, 1e-9, 0.0, 1e-9, 1e-9, 1e-9, 1e-9, 1.0]
    agg = aggregate(tree, fraction, 0.05)
    np.testing.assert_array_equal(tree.index[agg.root[order], 0], [0, 0, 0, 7, 7, 7, 7, 7])
    # the nodes on the planes x = 2 ... 6 are extended: x = 2 from A's nodes (x <= 1), the
    # others from B's (x >= 7), each reproducing x itself
    x_free = tree.nodes[tree.free_nodes, 0]
    x_kept = x_free[agg.kept]
    e = agg.extension.tocoo()
    extended = np.setdiff1d(np.arange(len(x_free)), agg.kept)
    np.testing.assert_array_equal(np.unique(x_free[extended]), [2, 3, 4, 5, 6])
    rows = ~np.isin(e.row, agg.kept)
    from_a = x_free[e.row[rows]] == 2
    assert (x_kept[e.col[rows][from_a]] <= 1).all() and (x_kept[e.col[rows][~from_a]] >= 7).all()
    np.testing.assert_allclose(agg.extension @ x_kept, x_free, atol=1e-12)
