"""The 3D IBFEM core end to end on Lame's thick sphere: one octant of a shell with inner
radius 1 and outer radius 2 under internal pressure, three sliding symmetry faces, on an octree
with exact cut cells and the step-boundary terms on the exact faces, against Lame's radial
displacement u_r = p a^3 / (E (b^3 - a^3)) ((1 - 2 nu) r + (1 + nu) b^3 / (2 r^2)).

The solid is written here (its faces' exact quadrature, its signed distance as the intersection
of the shell and three half-spaces), independently of geometry's solids."""

from __future__ import annotations

import numpy as np
import pytest

from ibfem.geometry.quadrature import gauss_legendre
from ibfem.solver.fem.linalg import linear_solve
from ibfem.solver.fem.solid_space import discretise_solid
from ibfem.solver.fem.space import number_dofs
from ibfem.solver.fem.step_boundary import projector, thin_band_terms
from ibfem.solver.model.elasticity import elasticity_matrix, lame_parameters

E, NU, P, A, B = 2.0e11, 0.3, 1.0e8, 1.0, 2.0


def lame_radial(r):
    return P * A**3 / (E * (B**3 - A**3)) * ((1 - 2 * NU) * r + (1 + NU) * B**3 / (2 * r**2))


def _panels(lo, hi, resolution, order=3):
    n = max(1, int(np.ceil((hi - lo) / resolution)))
    x, w = gauss_legendre(order)
    edges = np.linspace(lo, hi, n + 1)
    mid, half = 0.5 * (edges[1:] + edges[:-1]), 0.5 * np.diff(edges)
    return (mid[:, None] + half[:, None] * x).ravel(), (half[:, None] * w).ravel()


class _Face:
    def __init__(self, rule):
        self.rule = rule

    def quadrature(self, resolution):
        return self.rule(resolution)


class ShellOctant:
    """{a <= |x| <= b, x, y, z >= 0}: faces inner, outer, x0, y0, z0."""

    bounds = (np.zeros(3), np.full(3, B))

    def signed_distance(self, p):
        r = np.linalg.norm(p, axis=1)
        return np.min(np.stack([r - A, B - r, p[:, 0], p[:, 1], p[:, 2]]), axis=0)

    @property
    def faces(self):
        return {"inner": _Face(lambda res: self._sphere(A, -1.0, res)), "outer": _Face(lambda res: self._sphere(B, 1.0, res)),
                "x0": _Face(lambda res: self._plane(0, res)), "y0": _Face(lambda res: self._plane(1, res)),
                "z0": _Face(lambda res: self._plane(2, res))}

    @staticmethod
    def _sphere(radius, sign, res):
        t, wt = _panels(0.0, np.pi / 2, res / radius)
        f, wf = _panels(0.0, np.pi / 2, res / radius)
        tt, ff = np.meshgrid(t, f, indexing="ij")
        w = np.outer(wt, wf) * radius**2 * np.sin(tt)
        n = np.stack([np.sin(tt) * np.cos(ff), np.sin(tt) * np.sin(ff), np.cos(tt)], axis=-1).reshape(-1, 3)
        return radius * n, w.ravel(), sign * n

    @staticmethod
    def _plane(axis, res):
        rho, wr = _panels(A, B, res)
        psi, wp = _panels(0.0, np.pi / 2, res / B)
        rr, pp = np.meshgrid(rho, psi, indexing="ij")
        u, v = (k for k in range(3) if k != axis)
        pts = np.zeros(rr.shape + (3,))
        pts[..., u], pts[..., v] = rr * np.cos(pp), rr * np.sin(pp)
        normal = np.zeros(3)
        normal[axis] = -1.0
        return pts.reshape(-1, 3), (np.outer(wr, wp) * rr).ravel(), np.broadcast_to(normal, (rr.size, 3)).copy()


def solve_shell(h, offset=(0.0, 0.0, 0.0)):
    lam, mu = lame_parameters(E, NU, "solid")
    body = discretise_solid("shell", ShellOctant(), (lam, mu), elasticity_matrix(lam, mu, 3), NU, h, offset=offset)
    n = number_dofs([body])
    k = body.stiffness(1e-9)
    f = np.zeros(n)
    for face in ("x0", "y0", "z0"):
        bp = body.edge_points(face)
        kb, fb = thin_band_terms(bp, projector("sliding", bp.normals), np.zeros_like(bp.normals), lam, mu, 0.25, 1.0)
        k, f = k + kb, f + fb
    bp = body.edge_points("inner")
    f = f + bp.displacement.T @ (-P * bp.normals * bp.weights[:, None]).ravel()
    u = linear_solve(k.tocsr(), f, [body], "auto")
    return body, u


def test_lame_sphere_octant_radial_displacement():
    body, u = solve_shell(0.125, offset=(0.013, 0.021, 0.017))
    rng = np.random.default_rng(0)
    d = rng.normal(size=(200, 3))
    d = np.abs(d) / np.linalg.norm(d, axis=1)[:, None]
    r = rng.uniform(1.2, 1.8, 200)
    pts = d * r[:, None]
    cells = body.grid.locate(pts)
    disp = (body.displacement_operator(pts, cells) @ u).reshape(-1, 3)
    radial = np.einsum("qi,qi->q", disp, d)
    err = np.abs(radial - lame_radial(r)) / lame_radial(r)
    tangential = np.linalg.norm(disp - radial[:, None] * d, axis=1) / lame_radial(r)
    assert err.max() < 0.01, err.max()
    assert tangential.max() < 0.01, tangential.max()


def test_volume_of_the_shell_octant_from_the_cut_cells():
    lam, mu = lame_parameters(E, NU, "solid")
    body = discretise_solid("shell", ShellOctant(), (lam, mu), elasticity_matrix(lam, mu, 3), NU, 0.25)
    volume = (body.moments[:, 0] * (body.grid.size / 2) ** 3).sum()
    exact = np.pi / 6 * (B**3 - A**3)
    assert volume == pytest.approx(exact, rel=2e-3)


def test_a_3d_body_held_on_one_symmetry_face_only_can_move_rigidly():
    from ibfem.solver.fem.assembly import rigid_modes_check

    lam, mu = lame_parameters(E, NU, "solid")
    body = discretise_solid("shell", ShellOctant(), (lam, mu), elasticity_matrix(lam, mu, 3), NU, 0.25)
    number_dofs([body])
    k = body.stiffness(1e-9)
    bp = body.edge_points("x0")
    kb, _ = thin_band_terms(bp, projector("sliding", bp.normals), np.zeros_like(bp.normals), lam, mu, 0.25, 1.0)
    with pytest.raises(ValueError, match="not held against rigid-body motion"):
        rigid_modes_check((k + kb).tocsr(), [body])
    for face in ("y0", "z0"):
        bp = body.edge_points(face)
        kb = kb + thin_band_terms(bp, projector("sliding", bp.normals), np.zeros_like(bp.normals), lam, mu, 0.25, 1.0)[0]
    rigid_modes_check((k + kb).tocsr(), [body])  # three symmetry planes hold all six motions
