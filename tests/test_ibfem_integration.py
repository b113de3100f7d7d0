"""Cut-cell quadrature and element matrices against independent references."""

import numpy as np
import pytest

from ibfem.geometry.shapes import profile_from_shape
from ibfem.solver.fem.grid import CUT, build_grid
from ibfem.solver.fem.space import exact_boundary, tessellated_boundary
from ibfem.solver.fem.integration import (
    cell_stiffness,
    full_cell_moments,
    gauss_legendre,
    monomial_stiffness,
    shape_functions,
    strain_matrix,
    polygon_contains,
)

C = np.array([[3.0, 1.2, 0.0], [1.2, 3.0, 0.0], [0.0, 0.0, 0.9]])


def _gauss_stiffness(xi_lo, xi_hi, eta_lo, eta_hi, order=3):
    """Tensor Gauss rule on a sub-rectangle of the reference square (independent reference)."""
    x, w = gauss_legendre(order)
    xi = 0.5 * (xi_lo + xi_hi) + 0.5 * (xi_hi - xi_lo) * x
    eta = 0.5 * (eta_lo + eta_hi) + 0.5 * (eta_hi - eta_lo) * x
    XI, ETA = np.meshgrid(xi, eta, indexing="ij")
    W = np.outer(w, w) * 0.25 * (xi_hi - xi_lo) * (eta_hi - eta_lo)
    _, g = shape_functions(XI.ravel(), ETA.ravel())
    b = strain_matrix(g)
    return np.einsum("q,qji,jk,qkl->il", W.ravel(), b, C, b)


def test_full_cell_stiffness_matches_gauss_and_has_rigid_modes():
    k = cell_stiffness(full_cell_moments(), monomial_stiffness(C))
    assert np.allclose(k, _gauss_stiffness(-1, 1, -1, 1), rtol=1e-13, atol=1e-13)
    nodes = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], float)
    rigid = [np.tile([1.0, 0.0], 4), np.tile([0.0, 1.0], 4), np.column_stack([-nodes[:, 1], nodes[:, 0]]).ravel()]
    for r in rigid:
        assert np.abs(k @ r).max() < 1e-13
    assert np.sum(np.linalg.eigvalsh(k) > 1e-10) == 5  # 8 dofs - 3 rigid modes


def test_sub_rectangle_stiffness_from_moments():
    # moments of [-0.3, 0.8] x [-1, 0.2] in closed form, against a Gauss rule on that part
    lo, hi = np.array([-0.3, -1.0]), np.array([0.8, 0.2])
    a = np.arange(3)
    mx = (hi[0] ** (a + 1) - lo[0] ** (a + 1)) / (a + 1)
    my = (hi[1] ** (a + 1) - lo[1] ** (a + 1)) / (a + 1)
    k = cell_stiffness(np.outer(mx, my), monomial_stiffness(C))
    assert np.allclose(k, _gauss_stiffness(-0.3, 0.8, -1.0, 0.2), rtol=1e-12, atol=1e-13)


def _moments_total(grid):
    """Area, first and second moments of the whole body from the cells' local moments."""
    h = grid.size
    c = grid.center
    m = grid.moments
    s = 0.5 * h
    area = (m[:, 0, 0] * s**2).sum()
    # x = c + s xi: x^2 = c^2 + 2 c s xi + s^2 xi^2
    ixx = (s**2 * (c[:, 1] ** 2 * m[:, 0, 0] + 2 * c[:, 1] * s * m[:, 0, 1] + s**2 * m[:, 0, 2])).sum()
    iyy = (s**2 * (c[:, 0] ** 2 * m[:, 0, 0] + 2 * c[:, 0] * s * m[:, 1, 0] + s**2 * m[:, 2, 0])).sum()
    ixy = (s**2 * (c[:, 0] * c[:, 1] * m[:, 0, 0] + s * (c[:, 0] * m[:, 0, 1] + c[:, 1] * m[:, 1, 0]) + s**2 * m[:, 1, 1])).sum()
    return area, ixx, iyy, ixy


def test_disk_area_and_second_moments_exact_vs_tessellated():
    # disk radius 0.7 centred at (0.3, -0.2), grid deliberately unaligned
    R, cx, cy = 0.7, 0.3, -0.2
    prof = profile_from_shape({"type": "disk", "center": [cx, cy], "radius": R})
    ref_area = np.pi * R**2
    ref_ixx = np.pi * R**4 / 4 + ref_area * cy**2  # integral of y^2
    ref_iyy = np.pi * R**4 / 4 + ref_area * cx**2
    ref_ixy = ref_area * cx * cy
    grid = build_grid(exact_boundary(prof), 0.1, offset=(0.37, 0.61))
    area, ixx, iyy, ixy = _moments_total(grid)
    assert abs(area - ref_area) < 1e-12 * ref_area
    assert abs(ixx - ref_ixx) < 1e-12 * ref_ixx and abs(iyy - ref_iyy) < 1e-12 * ref_iyy
    assert abs(ixy - ref_ixy) < 1e-12 * abs(ref_ixy)
    # the thesis's tessellated boundary (chord tolerance 0.01 h): error of order the chord area
    tess = build_grid(tessellated_boundary(prof, 1e-3), 0.1, offset=(0.37, 0.61))
    t_area = _moments_total(tess)[0]
    assert 1e-5 < (ref_area - t_area) / ref_area < 1e-2


def test_cut_cell_moments_match_brute_force_sampling():
    prof = profile_from_shape({"type": "half_disk", "center": [0.0, 0.0], "radius": 1.0, "side": "below", "rotate_deg": 23.0})
    grid = build_grid(exact_boundary(prof), 0.25, offset=(0.13, 0.29))
    cut = np.nonzero(grid.status == CUT)[0]
    assert len(cut) > 10
    # dense midpoint sampling of each cut cell (independent of the divergence theorem)
    n = 400
    g = (np.arange(n) + 0.5) / n * 2 - 1
    XI, ETA = np.meshgrid(g, g, indexing="ij")
    for c in cut[:: max(1, len(cut) // 8)]:
        pts = grid.center[c] + 0.5 * grid.size[c] * np.column_stack([XI.ravel(), ETA.ravel()])
        inside = prof.signed_distance(pts) > 0
        w = (2.0 / n) ** 2
        m00 = inside.sum() * w
        m11 = (XI.ravel() * ETA.ravel() * inside).sum() * w
        assert abs(grid.moments[c, 0, 0] - m00) < 2e-2
        assert abs(grid.moments[c, 1, 1] - m11) < 2e-2


def test_polygon_contains_square_with_hole():
    outer = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
    hole = np.array([[1, 1], [1, 3], [3, 3], [3, 1]], float)
    pts = np.array([[0.5, 0.5], [2, 2], [3.5, 2], [5, 5]])
    assert polygon_contains(pts, [outer, hole]).tolist() == [True, False, True, False]


def _clip_to_box(poly, lo, hi):
    """Sutherland-Hodgman clip of a closed polygon (k, 2) by the box [lo, hi] (reference code)."""
    out = list(map(tuple, poly))
    for axis in (0, 1):
        for bound, keep_le in ((lo[axis], False), (hi[axis], True)):
            src, out = out, []
            if not src:
                break
            for i in range(len(src)):
                p, q = np.array(src[i - 1]), np.array(src[i])
                pin = p[axis] <= bound if keep_le else p[axis] >= bound
                qin = q[axis] <= bound if keep_le else q[axis] >= bound
                if qin:
                    if not pin:
                        out.append(tuple(p + (bound - p[axis]) / (q[axis] - p[axis]) * (q - p)))
                    out.append(tuple(q))
                elif pin:
                    out.append(tuple(p + (bound - p[axis]) / (q[axis] - p[axis]) * (q - p)))
    return np.array(out)


def test_tessellated_variant_equals_clip_triangulate_gauss():
    # the thesis's integration: clip each cell by the tessellated boundary, fan-triangulate,
    # integrate with a degree-2 triangle rule; the moments must equal the polyline moments
    prof = profile_from_shape({"type": "disk", "center": [0.1, 0.2], "radius": 0.8})
    boundary = tessellated_boundary(prof, 0.02)
    grid = build_grid(boundary, 0.2, offset=(0.31, 0.17))
    poly = boundary.polygon_loops[0]
    bary = np.array([[2 / 3, 1 / 6, 1 / 6], [1 / 6, 2 / 3, 1 / 6], [1 / 6, 1 / 6, 2 / 3]])  # exact for degree 2
    checked = 0
    for c in np.nonzero(grid.status == CUT)[0]:
        lo = grid.lower[c]
        clipped = _clip_to_box(poly, lo, lo + grid.size[c])
        if len(clipped) < 3:
            continue
        local = 2 * (clipped - grid.center[c]) / grid.size[c]
        m = np.zeros((3, 3))
        for i in range(1, len(local) - 1):
            tri = np.array([local[0], local[i], local[i + 1]])
            e1, e2 = tri[1] - tri[0], tri[2] - tri[0]
            area = 0.5 * (e1[0] * e2[1] - e1[1] * e2[0])
            pts = bary @ tri
            for a in range(3):
                for b in range(3):
                    if a + b <= 2:
                        m[a, b] += area / 3 * np.sum(pts[:, 0] ** a * pts[:, 1] ** b)
        for a, b in ((0, 0), (1, 0), (0, 1), (1, 1), (2, 0), (0, 2)):
            assert abs(grid.moments[c, a, b] - m[a, b]) < 1e-12
        checked += 1
    assert checked > 10
