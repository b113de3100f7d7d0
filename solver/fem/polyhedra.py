"""Exact moments of convex polyhedra cut from cubes by planes: the cube is split into six
tetrahedra (Kuhn), each clipped by one half-space after the other (a tetrahedron clipped by a
plane leaves nothing, itself, one tetrahedron or a triangular prism of three), and every
tetrahedron carries a collapsed Gauss rule exact to degree 7, so the monomials x^a y^b z^c with
a, b, c <= 2 (degree 6) of the trilinear stiffness are integrated exactly: the moments of a
cube's part bounded by planar faces are exact to rounding. Vectorised over all pieces at once."""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from .surface_quadrature import gauss_jacobi

__all__ = ["clip_cubes", "tetrahedron_moments", "tetrahedron_rule"]

#: the six tetrahedra of the unit cube around its diagonal (0, 0, 0) - (1, 1, 1) (Kuhn)
_KUHN = np.array([[[0, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 1]], [[0, 0, 0], [1, 0, 0], [1, 0, 1], [1, 1, 1]],
                  [[0, 0, 0], [0, 1, 0], [1, 1, 0], [1, 1, 1]], [[0, 0, 0], [0, 1, 0], [0, 1, 1], [1, 1, 1]],
                  [[0, 0, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1]], [[0, 0, 0], [0, 0, 1], [0, 1, 1], [1, 1, 1]]], float)
#: a triangular prism (A0 A1 A2, B0 B1 B2, Ai joined to Bi) as three tetrahedra
_PRISM = np.array([[0, 1, 2, 5], [0, 1, 4, 5], [0, 3, 4, 5]])


@lru_cache(maxsize=None)
def tetrahedron_rule(n: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """Barycentric coordinates (n^3, 3) of the last three vertices and weights summing to 1/6 on
    the reference tetrahedron: the collapsed (Duffy) product of Gauss-Jacobi rules with the
    weights (1 - u)^2 and (1 - v) and a Gauss-Legendre rule, exact to degree 2n - 1."""
    xu, wu = gauss_jacobi(n, 2.0, 0.0)
    xv, wv = gauss_jacobi(n, 1.0, 0.0)
    xw, ww = np.polynomial.legendre.leggauss(n)
    u, v, w = (0.5 * (1.0 + x) for x in (xu, xv, xw))
    uu, vv, ww_ = np.meshgrid(u, v, w, indexing="ij")
    bary = np.stack([uu, (1.0 - uu) * vv, (1.0 - uu) * (1.0 - vv) * ww_], axis=-1).reshape(-1, 3)
    weight = np.einsum("i,j,k->ijk", wu / 8.0, wv / 4.0, ww / 2.0).ravel()
    bary.setflags(write=False)
    weight.setflags(write=False)
    return bary, weight


def _clip_tetrahedra(tets: np.ndarray, owner: np.ndarray, normal: np.ndarray, offset: np.ndarray):
    """The parts of tetrahedra (t, 4, 3) where normal . x + offset >= 0 (normal (t, 3), offset
    (t,) per tetrahedron) as tetrahedra, with their owners."""
    f = np.einsum("tvk,tk->tv", tets, normal) + offset[:, None]
    keep = f >= 0.0
    count = keep.sum(axis=1)
    order = np.argsort(~keep, axis=1, kind="stable")  # kept vertices first
    v = np.take_along_axis(tets, order[:, :, None], axis=1)
    g = np.take_along_axis(f, order, axis=1)

    def cut(i, j, rows):  # the point on edge (i, j) where the plane crosses it
        gi, gj = g[rows, i], g[rows, j]
        t = gi / np.where(gi != gj, gi - gj, 1.0)
        return v[rows, i] + t[:, None] * (v[rows, j] - v[rows, i])

    out, owners = [tets[count == 4]], [owner[count == 4]]
    r = np.flatnonzero(count == 1)
    out.append(np.stack([v[r, 0], cut(0, 1, r), cut(0, 2, r), cut(0, 3, r)], axis=1))
    owners.append(owner[r])
    for c, prism in ((2, lambda r: [v[r, 0], cut(0, 2, r), cut(0, 3, r), v[r, 1], cut(1, 2, r), cut(1, 3, r)]),
                     (3, lambda r: [v[r, 0], v[r, 1], v[r, 2], cut(0, 3, r), cut(1, 3, r), cut(2, 3, r)])):
        r = np.flatnonzero(count == c)
        corners = np.stack(prism(r), axis=1)  # (r, 6, 3)
        out.append(corners[:, _PRISM].reshape(-1, 4, 3))
        owners.append(np.repeat(owner[r], 3))
    return np.concatenate(out), np.concatenate(owners)


def clip_cubes(lower: np.ndarray, width: np.ndarray, normal: np.ndarray, offset: np.ndarray):
    """Tetrahedra (t, 4, 3) and owners (t,) of the parts of the cubes [lower, lower + width]
    (p, 3), (p,) where normal[:, i] . x + offset[:, i] >= 0 for every plane i (normal (p, k, 3),
    offset (p, k); a zero normal with a positive offset is no constraint)."""
    p = len(lower)
    tets = (lower[:, None, None, :] + width[:, None, None, None] * _KUHN[None]).reshape(-1, 4, 3)
    owner = np.repeat(np.arange(p), len(_KUHN))
    for i in range(normal.shape[1]):
        tets, owner = _clip_tetrahedra(tets, owner, normal[owner, i], offset[owner, i])
    return tets, owner


def tetrahedron_moments(tets: np.ndarray, owner: np.ndarray, m: int, chunk: int = 20000) -> np.ndarray:
    """Moments (m, 27) of the monomials x^a y^b z^c (a, b, c < 3; the order of
    hexahedra.STIFFNESS_EXPONENTS) over the tetrahedra (t, 4, 3), summed per owner."""
    bary, weight = tetrahedron_rule(4)
    out = np.zeros((m, 27))
    for start in range(0, len(tets), chunk):
        t, o = tets[start:start + chunk], owner[start:start + chunk]
        edges = t[:, 1:] - t[:, :1]  # (t, 3, 3)
        volume6 = np.abs(np.linalg.det(edges))
        x = t[:, None, 0, :] + bary @ edges  # (t, q, 3): a matrix product (einsum is 3x slower)
        w = volume6[:, None] * weight[None, :]
        xs, ys, zs = x[..., 0], x[..., 1], x[..., 2]
        wx = np.stack([w, w * xs, w * (xs * xs)], axis=1)  # (t, 3, q): weight times x^a
        y_pow, z_pow = (ys, ys * ys), (zs, zs * zs)
        yz = np.empty(x.shape[:2] + (9,))  # (t, q, 9): y^b z^c, b and c < 3
        yz[..., 0] = 1.0
        for b in range(3):
            for c in range(3):
                if b and c:
                    yz[..., 3 * b + c] = y_pow[b - 1] * z_pow[c - 1]
                elif b or c:
                    yz[..., 3 * b + c] = y_pow[b - 1] if b else z_pow[c - 1]
        mono = np.matmul(wx, yz)  # (t, 3, 9): x^a times y^b z^c
        np.add.at(out, o, mono.reshape(-1, 27))
    return out
