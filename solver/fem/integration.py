"""Quadrature for bilinear cells cut by an exact boundary.

Volume integrals of a bilinear cell only ever need the moments of the part of the cell inside
the body, ``m_ab = integral of xi^a eta^b`` over that part in the cell's local coordinates
(xi, eta in [-1, 1]): the stiffness integrand B^T C B and the body-force integrand N are
polynomials of degree <= 2 in each variable. The divergence theorem turns every moment into a
boundary integral,

    integral_A xi^a eta^b dA = closed integral of xi^(a+1) eta^b / (a+1) n_xi ds,

over the pieces of the exact boundary curves inside the cell (Gauss-Legendre in each curve's
own parameter, exact geometry) plus the inside parts of the cell's two vertical sides
(closed form; horizontal sides have n_xi = 0). No sub-triangulation, no mapping of curved
sub-cells: the moments are exact up to the Gauss rule on the curve pieces (machine precision
for lines and arcs at the orders used). With a polyline in place of the exact curves the same
code gives exactly what clipping the cell by the tessellated boundary, triangulating and
integrating with a Gauss rule of degree >= 2 gives (the thesis's method), since the integrands
are polynomials: that is the ``exact_geometry = false`` variant.

Pure functions over arrays of cells x quadrature points.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ibfem.geometry.quadrature import gauss_legendre

__all__ = [
    "REFERENCE_NODES",
    "gauss_legendre",
    "shape_functions",
    "strain_matrix",
    "monomial_stiffness",
    "cell_stiffness",
    "full_cell_moments",
    "body_force_vectors",
    "curve_gauss",
    "piece_moments",
    "vertical_side_moments",
    "Polyline",
    "polygon_contains",
]

# Counter-clockwise corners of the reference square [-1, 1]^2.
REFERENCE_NODES = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])

# The monomials xi^a eta^b appearing in B^T C B of a bilinear square.
STIFFNESS_MONOMIALS = ((0, 0), (1, 0), (0, 1), (2, 0), (0, 2), (1, 1))




def shape_functions(xi: np.ndarray, eta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Bilinear N (..., 4) and dN/d(xi, eta) (..., 4, 2) at local coordinates."""
    xi = np.asarray(xi, dtype=float)[..., None]
    eta = np.asarray(eta, dtype=float)[..., None]
    xn, yn = REFERENCE_NODES[:, 0], REFERENCE_NODES[:, 1]
    n = 0.25 * (1.0 + xi * xn) * (1.0 + eta * yn)
    dxi = 0.25 * xn * (1.0 + eta * yn)
    deta = 0.25 * yn * (1.0 + xi * xn)
    return n, np.stack([dxi, deta], axis=-1)


def strain_matrix(grad: np.ndarray) -> np.ndarray:
    """B (..., 3, 8) acting on [u1x, u1y, ..., u4y] -> [exx, eyy, 2 exy] from grad N (..., 4, 2)."""
    shape = grad.shape[:-2]
    b = np.zeros(shape + (3, 8))
    b[..., 0, 0::2] = grad[..., 0]
    b[..., 1, 1::2] = grad[..., 1]
    b[..., 2, 0::2] = grad[..., 1]
    b[..., 2, 1::2] = grad[..., 0]
    return b


def monomial_stiffness(elasticity: np.ndarray) -> np.ndarray:
    """(6, 8, 8) matrices K_k with B^T C B = sum_k xi^a_k eta^b_k K_k on the reference square.

    The stiffness of any part A of a square cell is sum_k m_k K_k with m_k the moments of A in
    local coordinates; it does not depend on the cell size (2D scaling), so one set serves every
    level of the quadtree.
    """
    # grad N = G0 + xi G_xi + eta G_eta (dN/dxi is linear in eta, dN/deta linear in xi)
    _, g0 = shape_functions(0.0, 0.0)
    _, g_xi = shape_functions(1.0, 0.0)
    _, g_eta = shape_functions(0.0, 1.0)
    b0 = strain_matrix(g0)
    bx = strain_matrix(g_xi) - b0
    be = strain_matrix(g_eta) - b0
    c = np.asarray(elasticity, dtype=float)

    def sym(p, q):
        return p.T @ c @ q + (q.T @ c @ p if p is not q else 0.0)

    return np.stack(
        [
            b0.T @ c @ b0,
            sym(b0, bx),
            sym(b0, be),
            bx.T @ c @ bx,
            be.T @ c @ be,
            sym(bx, be),
        ]
    )


def full_cell_moments() -> np.ndarray:
    """Moments m_ab (3, 3) of the whole reference square."""
    one_d = np.array([2.0, 0.0, 2.0 / 3.0])
    return np.outer(one_d, one_d)


def cell_stiffness(moments: np.ndarray, k_monomial: np.ndarray) -> np.ndarray:
    """Stiffness (..., 8, 8) of cell parts with moments (..., 3, 3)."""
    m = np.stack([moments[..., a, b] for a, b in STIFFNESS_MONOMIALS], axis=-1)
    return np.einsum("...k,kij->...ij", m, k_monomial)


def body_force_vectors(moments: np.ndarray, size: np.ndarray, force: np.ndarray) -> np.ndarray:
    """Consistent nodal loads (..., 8) of a uniform body force (2,) over cell parts."""
    xn, yn = REFERENCE_NODES[:, 0], REFERENCE_NODES[:, 1]
    # N_i = (1 + xi_i xi + eta_i eta + xi_i eta_i xi eta) / 4, dA = (h/2)^2 dxi deta
    integral_n = 0.25 * (
        moments[..., 0, 0, None]
        + xn * moments[..., 1, 0, None]
        + yn * moments[..., 0, 1, None]
        + xn * yn * moments[..., 1, 1, None]
    ) * (0.5 * np.asarray(size, dtype=float)[..., None]) ** 2
    f = np.zeros(integral_n.shape[:-1] + (8,))
    f[..., 0::2] = integral_n * force[0]
    f[..., 1::2] = integral_n * force[1]
    return f


def curve_gauss(curve, t0: np.ndarray, t1: np.ndarray, order: int):
    """Gauss-Legendre rule on pieces [t0, t1] (p,) of a curve, in its own parameter.

    Returns points (p, q, 2), weights ds (p, q), outward normals (p, q, 2) (the derivative
    turned by -90 degrees, the convention of ``geometry.bounded``), parameters (p, q).
    One vectorised evaluate/derivative call per curve (the BoundedCurve ``quadrature`` method
    takes one interval at a time, which would be a Python loop over cells here).
    """
    x, w = gauss_legendre(order)
    t0 = np.asarray(t0, dtype=float)[:, None]
    t1 = np.asarray(t1, dtype=float)[:, None]
    half = 0.5 * (t1 - t0)
    t = t0 + half * (1.0 + x[None, :])
    flat = t.ravel()
    pts = np.asarray(curve.evaluate(flat), dtype=float).reshape(t.shape + (2,))
    der = np.asarray(curve.derivative(flat), dtype=float).reshape(t.shape + (2,))
    speed = np.hypot(der[..., 0], der[..., 1])
    with np.errstate(invalid="ignore", divide="ignore"):
        normals = np.stack([der[..., 1], -der[..., 0]], axis=-1) / speed[..., None]
    normals = np.nan_to_num(normals)
    weights = speed * np.abs(half) * w[None, :]
    return pts, weights, normals, t


def piece_moments(points, weights, normals, centers, sizes) -> np.ndarray:
    """Contribution (p, 3, 3) of boundary-curve pieces to the local moments of their cells.

    points/weights/normals: a Gauss rule on each piece (p, q, ...); centers (p, 2) and sizes (p,)
    of the cell holding each piece. Divergence theorem with F = xi^(a+1) eta^b / (a+1).
    """
    scale = 2.0 / np.asarray(sizes, dtype=float)[:, None]
    xi = (points[..., 0] - centers[:, 0, None]) * scale
    eta = (points[..., 1] - centers[:, 1, None]) * scale
    wn = weights * scale * normals[..., 0]  # ds_local n_xi
    a = np.arange(3)
    xi_pow = xi[..., None] ** (a + 1) / (a + 1)  # (p, q, 3)
    eta_pow = eta[..., None] ** a
    return np.einsum("pq,pqa,pqb->pab", wn, xi_pow, eta_pow)


def vertical_side_moments(eta0, eta1, side) -> np.ndarray:
    """Moments (s, 3, 3) contributed by inside intervals [eta0, eta1] of the vertical sides
    xi = side (+1 right, -1 left; outward n_xi = side)."""
    eta0 = np.asarray(eta0, dtype=float)
    eta1 = np.asarray(eta1, dtype=float)
    side = np.asarray(side, dtype=float)
    a = np.arange(3)
    b = np.arange(3)
    xi_part = side[:, None] ** (a + 1) / (a + 1) * side[:, None]  # F(xi=side) * n_xi
    eta_part = (eta1[:, None] ** (b + 1) - eta0[:, None] ** (b + 1)) / (b + 1)
    return xi_part[:, :, None] * eta_part[:, None, :]


@dataclass(frozen=True)
class Polyline:
    """A piecewise-linear curve with the evaluation interface of ``geometry.bounded`` curves
    (parameter t in [0, m - 1], vertex k at t = k): the tessellated boundary of the
    ``exact_geometry = false`` variant, and a geometry-free curve for tests."""

    name: str
    vertices: np.ndarray

    def __post_init__(self):
        v = np.asarray(self.vertices, dtype=float)
        if v.ndim != 2 or v.shape[1] != 2 or len(v) < 2:
            raise ValueError(f"Polyline {self.name!r}: vertices must be (m >= 2, 2), got {v.shape}")
        object.__setattr__(self, "vertices", v)

    @property
    def t_start(self) -> float:
        return 0.0

    @property
    def t_end(self) -> float:
        return float(len(self.vertices) - 1)

    @property
    def start(self) -> np.ndarray:
        return self.vertices[0]

    @property
    def end(self) -> np.ndarray:
        return self.vertices[-1]

    @property
    def length(self) -> float:
        return float(np.hypot(*np.diff(self.vertices, axis=0).T).sum())

    def _segment(self, t):
        t = np.asarray(t, dtype=float)
        k = np.clip(np.floor(t).astype(int), 0, len(self.vertices) - 2)
        return k, t - k

    def evaluate(self, t) -> np.ndarray:
        k, s = self._segment(t)
        v = self.vertices
        return v[k] + s[..., None] * (v[k + 1] - v[k])

    def derivative(self, t) -> np.ndarray:
        k, _ = self._segment(t)
        return self.vertices[k + 1] - self.vertices[k]

    def normal(self, t) -> np.ndarray:
        d = self.derivative(t)
        return np.stack([d[..., 1], -d[..., 0]], axis=-1) / np.hypot(d[..., 0], d[..., 1])[..., None]

    def breakpoints(self) -> np.ndarray:
        """Parameters of the vertices (kinks: quadrature must not straddle them)."""
        return np.arange(len(self.vertices), dtype=float)

    def axis_crossings(self, axis: int, value: float) -> np.ndarray:
        """Sorted parameters where coordinate ``axis`` equals ``value`` (segments lying on the
        line contribute their end points only)."""
        c = self.vertices[:, axis] - value
        a, b = c[:-1], c[1:]
        cross = (a * b < 0.0)
        k = np.nonzero(cross)[0]
        t = k + a[k] / (a[k] - b[k])
        on = np.nonzero(c == 0.0)[0]
        return np.unique(np.concatenate([t, on.astype(float)]))


def polygon_contains(points: np.ndarray, loops: list[np.ndarray], chunk: int = 2_000_000) -> np.ndarray:
    """Even-odd point-in-polygon test of points (n, 2) against closed vertex loops.

    Hand-written (no shapely/matplotlib dependency on the solver path); chunked so that the
    points x segments work stays bounded.
    """
    points = np.asarray(points, dtype=float)
    a = np.concatenate([lp for lp in loops])
    b = np.concatenate([np.roll(lp, -1, axis=0) for lp in loops])
    inside = np.zeros(len(points), dtype=bool)
    step = max(1, chunk // max(len(a), 1))
    for s in range(0, len(points), step):
        p = points[s : s + step, None, :]
        ay, by = a[None, :, 1], b[None, :, 1]
        straddle = (ay > p[..., 1]) != (by > p[..., 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            x_cross = a[None, :, 0] + (p[..., 1] - ay) * (b[None, :, 0] - a[None, :, 0]) / (by - ay)
        inside[s : s + step] = np.count_nonzero(straddle & (p[..., 0] < x_cross), axis=1) % 2 == 1
    return inside
