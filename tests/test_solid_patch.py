"""3D patch tests: a box under a constant stress, held by sliding symmetry faces and
loaded by tractions sigma n on the others, reproduces the constant stress; the boundary rule
split at the octree's planes integrates trilinear fields exactly on a turned plane."""

import numpy as np
import pytest

from ibfem.solver.fem.octree import build_octree
from ibfem.solver.fem.surface_quadrature import cell_split_quadrature
from ibfem.solver.model import problem as pb
from ibfem.solver.solving import solve

from _turned_box import TurnedBox, rotation

E, NU = 2.0e11, 0.3


def _patch(box, stress_local, h, offset):
    sigma = box.rotation @ stress_local @ box.rotation.T
    bcs = [pb.Sliding("box", f) for f in ("x0", "y0", "z0")]
    bcs += [pb.Traction("box", f"{'xyz'[k]}1", tuple(sigma @ box.rotation[:, k])) for k in range(3)]
    problem = pb.Problem("patch", "solid", 1.0, (pb.BodyModel("box", box, pb.Material("m", E, NU), h),), tuple(bcs))
    sol = solve(problem.with_options(grid_offset=offset))
    x = np.random.default_rng(1).uniform(0.02, 0.98, (300, 3)) * box.size
    voigt = np.array([sigma[0, 0], sigma[1, 1], sigma[2, 2], sigma[1, 2], sigma[0, 2], sigma[0, 1]])
    return sol, box.to_world(x), voigt


def test_constant_stress_exact_in_cells_cut_by_the_faces():
    # faces x0, x1 cut the cells (grid offset along x), y and z faces on grid planes
    box = TurnedBox([1.0, 0.8, 0.6], shift=(0.013, 0.0, 0.0))
    sol, pts, voigt = _patch(box, np.diag([1.0e8, -0.5e8, 0.3e8]), 0.2, (0.11, 0.0, 0.0))
    scale = np.abs(voigt).max()
    assert np.abs(sol.stress(pts, recovered=False) - voigt).max() < 1e-7 * scale
    assert np.abs(sol.stress(pts) - voigt).max() < 1e-7 * scale
    # the sliding faces carry the loads back along their exact normals
    assert sol.reactions["box/x0"] == pytest.approx([-1.0e8 * 0.48, 0, 0], abs=1e-7 * scale)


@pytest.mark.parametrize("angle", [0.0, 0.7])
def test_turned_box_stress_exact_with_the_default_settings(angle):
    # every face cuts cells at an angle and the box's edges and corners lie in cut cells, which
    # are integrated exactly (planar faces); the default fictitious stiffness acts on the cut
    # cells' non-linear modes only and leaves a constant stress alone (measured 7e-15 unturned,
    # 3e-14 at 0.7 rad; 2e-9 and 6e-8 when it stiffened the whole cell)
    box = TurnedBox([1.0, 0.8, 0.6], rotation([0.3, -0.5, 0.8], angle), (0.013, -0.021, 0.037))
    sol, pts, voigt = _patch(box, np.diag([1.0e8, -0.5e8, 0.3e8]), 0.17, (0.11, 0.23, 0.31))
    assert np.abs(sol.stress(pts, recovered=False) - voigt).max() < 1e-8 * np.abs(voigt).max()
    total = sum(np.asarray(r) for r in sol.reactions.values())
    load = np.zeros(3)
    sigma = box.rotation @ np.diag([1.0e8, -0.5e8, 0.3e8]) @ box.rotation.T
    for k, area in enumerate([0.48, 0.6, 0.8]):
        load += sigma @ box.rotation[:, k] * area
    np.testing.assert_allclose(total, -load, atol=1e-9 * np.abs(load).max())  # equilibrium


def test_split_rule_integrates_a_trilinear_field_on_a_turned_face_exactly():
    box = TurnedBox([1.0, 0.8, 0.6], rotation([1.0, 2.0, -0.5], 0.9), (0.1, 0.2, 0.3))
    lo, hi = box.bounds
    tree = build_octree((lo - 0.1, hi + 0.1), 0.13, (), lambda lower, size: np.ones(len(size), bool))
    face = box.faces["z1"]
    spacing = tree.h0 / 2.0**tree.max_level
    pts, w, n = cell_split_quadrature(face, tree.min_size, tree.origin, spacing)
    assert w.sum() == pytest.approx(0.8, rel=1e-13)
    # a piecewise trilinear field (the interpolant of a smooth function on the grid) against
    # its integral from a fine exact rule on each cell's part: compare with a 40x finer panel rule
    f = lambda p: np.sin(3 * p[:, 0]) * np.cos(2 * p[:, 1]) + p[:, 2] ** 2  # noqa: E731
    cells = tree.locate(pts - 1e-12 * n)
    assert (cells >= 0).all()
    local = tree.local_coordinates(pts, cells)
    from ibfem.solver.fem.hexahedra import shape_functions

    shape, _ = shape_functions(local)
    interp = np.einsum("qa,qa->q", shape, f(tree.nodes[tree.cells[cells]].reshape(-1, 3)).reshape(-1, 8))
    coarse = (w * interp).sum()
    fine_pts, fine_w, fine_n = cell_split_quadrature(face, tree.min_size / 8, tree.origin, spacing)
    fc = tree.locate(fine_pts - 1e-12 * fine_n)
    sh, _ = shape_functions(tree.local_coordinates(fine_pts, fc))
    fine = (fine_w * np.einsum("qa,qa->q", sh, f(tree.nodes[tree.cells[fc]].reshape(-1, 3)).reshape(-1, 8))).sum()
    assert coarse == pytest.approx(fine, rel=1e-12)
