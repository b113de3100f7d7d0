"""Grid offsets of any sign and size: the background grid covers the body (every boundary
piece in a cell, the exact perimeter and area recovered), the grid lines repeat every whole
cell, and the constant-stress patch test stays exact at negative offsets (2D and 3D)."""

import numpy as np
import pytest

from ibfem.geometry.shapes import profile_from_shape
from ibfem.solver.fem.grid import RefinementZone, build_grid, grid_origin
from ibfem.solver.fem.octree import build_octree
from ibfem.solver.fem.space import exact_boundary
from ibfem.solver.model import problem as pb
from ibfem.solver.solving import solve

from _turned_box import TurnedBox, rotation

E, NU = 2.0e11, 0.3
A, B = 1.0, 2.0
OFFSETS = [(-0.3, 0.4), (-1.0, -1.0), (-0.999, 0.25), (1.7, -2.4), (3.25, -0.5), (0.0, 0.0), (1.0, 1.0)]


def _annulus():
    return profile_from_shape({"type": "profile", "rotate_deg": 17.0, "edges": [
        {"name": "bottom", "type": "line", "start": [A, 0.0], "end": [B, 0.0]},
        {"name": "outer", "type": "arc", "center": [0, 0], "radius": B, "start_angle": 0, "end_angle": 90},
        {"name": "left", "type": "line", "start": [0.0, B], "end": [0.0, A]},
        {"name": "inner", "type": "arc", "center": [0, 0], "radius": A, "start_angle": 90, "end_angle": 0}]})


@pytest.mark.parametrize("offset", OFFSETS)
def test_quadtree_covers_the_body_at_any_offset(offset):
    boundary = exact_boundary(_annulus())
    h = 0.1
    grid = build_grid(boundary, h, (RefinementZone(2, 0.2, np.array([1.0, 0.5])),), offset)
    lo, hi = (np.asarray(b) for b in boundary.bounds)
    assert np.all(grid.origin <= lo) and np.all(grid.origin + h * np.array(grid.shape) >= hi)
    # every piece of every curve lies in a cell and the pieces make up the whole curve
    assert np.all(grid.pieces.cell >= 0)
    for name, curve in boundary.curves.items():
        sel = grid.pieces.of(name)
        assert np.abs(grid.pieces.t1[sel] - grid.pieces.t0[sel]).sum() == pytest.approx(
            abs(curve.t_end - curve.t_start), rel=1e-12)
    # exact perimeter and area of the quarter annulus
    assert grid.boundary_length.sum() == pytest.approx(2 * (B - A) + 0.5 * np.pi * (A + B), rel=1e-10)
    assert grid.inside_area.sum() == pytest.approx(0.25 * np.pi * (B * B - A * A), rel=1e-10)
    # the grid lines are those of the offset's fractional part (a whole-cell shift changes nothing)
    f = np.asarray(offset) - np.floor(offset)
    lines = (grid.origin - (lo - f * h)) / h
    assert np.allclose(lines, np.round(lines), atol=1e-9)


def test_grid_origin_refuses_non_finite_offsets():
    with pytest.raises(ValueError, match="grid offset"):
        grid_origin(np.zeros(2), (np.nan, 0.0), 0.1)


@pytest.mark.parametrize("offset", [(-0.3, 0.4), (-1.0, -0.61), (0.45, -0.999)])
def test_patch_test_exact_at_negative_offsets(offset):
    rot = 23.0
    c, s = np.cos(np.deg2rad(rot)), np.sin(np.deg2rad(rot))
    r = np.array([[c, -s], [s, c]])
    prof = profile_from_shape({"type": "rectangle", "min": [0, 0], "max": [2, 1], "rotate_deg": rot})
    s0 = 1e8
    problem = pb.Problem("patch", "plane_stress", 1.0, (pb.BodyModel("plate", prof, pb.Material("m", E, NU), 0.13),),
                         (pb.Sliding("plate", "left"), pb.Sliding("plate", "bottom"),
                          pb.Traction("plate", "right", tuple(r @ [s0, 0.0]))))
    sol = solve(problem.with_options(grid_offset=offset))
    loc = np.random.default_rng(0).uniform([0, 0], [2, 1], (400, 2))
    st = np.asarray(sol.stress(loc @ r.T, recovered=False))
    sig = np.array([[st[:, 0], st[:, 2]], [st[:, 2], st[:, 1]]]).transpose(2, 0, 1)
    local = np.einsum("ji,qjk,kl->qil", r, sig, r)
    assert np.abs(local[:, 0, 0] - s0).max() < 1e-8 * s0
    assert max(np.abs(local[:, 1, 1]).max(), np.abs(local[:, 0, 1]).max()) < 1e-8 * s0


@pytest.mark.parametrize("offset", [(-0.3, 0.4, -0.2), (-1.0, 2.5, -0.75)])
def test_octree_covers_the_bounds_at_any_offset(offset):
    lo, hi = np.array([0.1, -0.2, 0.3]), np.array([1.1, 0.6, 0.9])
    h = 0.17
    tree = build_octree((lo, hi), h, (), None, offset)
    assert np.all(tree.origin <= lo) and np.all(tree.origin + h * np.array(tree.shape) >= hi)
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
    assert np.all(tree.locate(lo + (hi - lo) * np.random.default_rng(2).uniform(size=(200, 3))) >= 0)
    assert np.all(tree.locate(0.999999 * corners + 1e-6 * 0.5 * (lo + hi)) >= 0)


def test_solid_patch_exact_at_a_negative_offset():
    box = TurnedBox([1.0, 0.8, 0.6], rotation([0.3, -0.5, 0.8], 0.7), (0.013, -0.021, 0.037))
    sigma = box.rotation @ np.diag([1.0e8, -0.5e8, 0.3e8]) @ box.rotation.T
    bcs = [pb.Sliding("box", f) for f in ("x0", "y0", "z0")]
    bcs += [pb.Traction("box", f"{'xyz'[k]}1", tuple(sigma @ box.rotation[:, k])) for k in range(3)]
    problem = pb.Problem("patch", "solid", 1.0, (pb.BodyModel("box", box, pb.Material("m", E, NU), 0.17),), tuple(bcs))
    sol = solve(problem.with_options(grid_offset=(-0.3, 0.4, -0.8)))
    pts = box.to_world(np.random.default_rng(1).uniform(0.02, 0.98, (300, 3)) * box.size)
    voigt = np.array([sigma[0, 0], sigma[1, 1], sigma[2, 2], sigma[1, 2], sigma[0, 2], sigma[0, 1]])
    assert np.abs(sol.stress(pts, recovered=False) - voigt).max() < 1e-8 * np.abs(voigt).max()
    total = sum(np.asarray(r) for r in sol.reactions.values())
    load = sum(sigma @ box.rotation[:, k] * a for k, a in enumerate([0.48, 0.6, 0.8]))
    np.testing.assert_allclose(total, -load, atol=1e-9 * np.abs(load).max())
