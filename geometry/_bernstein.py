"""Polynomials in Bernstein form on [0, 1], vectorised over many polynomials at once.

Coefficient arrays are degree-major: a set of n polynomials of degree m is (m + 1, n)
(row j: the coefficient of the Bernstein basis polynomial B_j^m). Used to isolate the
stationary points of the distance along a B-spline cell (:mod:`geometry.bspline`): the
number of sign changes of the coefficients bounds the number of roots in (0, 1) and has
the same parity (Descartes' rule of signs in Bernstein form), and halving the interval
(de Casteljau) makes the bound exact once the roots are separated. All maps here are
convex combinations (or binomial sums of one sign), so they add no more than a few ulps of
relative round-off, unlike a collocation inverse, whose growth is ~6e4 at degree 13.
"""

from __future__ import annotations

import math

import numpy as np


def from_taylor(k: int) -> np.ndarray:
    """(k + 1, k + 1) matrix M: the Bernstein coefficients on [0, 1] of the polynomial
    ``sum_i a_i (s - 1/2)^i`` are ``M @ a``. With ``a_i = c_i L^i`` it maps the Taylor
    coefficients c_i of a piece about the middle of a cell of length L (local variable
    x = L (s - 1/2)) to the piece's Bezier net over the cell."""
    # power basis in s: (s - 1/2)^i = sum_j C(i, j) (-1/2)^(i - j) s^j
    shift = np.zeros((k + 1, k + 1))
    for i in range(k + 1):
        for j in range(i + 1):
            shift[j, i] = math.comb(i, j) * (-0.5) ** (i - j)
    # power to Bernstein: b_l = sum_{j <= l} C(l, j) / C(k, j) a_j
    to_bernstein = np.zeros((k + 1, k + 1))
    for ell in range(k + 1):
        for j in range(ell + 1):
            to_bernstein[ell, j] = math.comb(ell, j) / math.comb(k, j)
    return to_bernstein @ shift


def derivative(B: np.ndarray) -> np.ndarray:
    """Coefficients (m, n) of d/ds of the degree-m polynomials ``B`` (m + 1, n)."""
    m = B.shape[0] - 1
    return m * np.diff(B, axis=0)


def product(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """Coefficients (a + b + 1, n) of the products of polynomials ``X`` (a + 1, n) and
    ``Y`` (b + 1, n) (one-dimensional arrays: one polynomial, broadcast)."""
    a, b = X.shape[0] - 1, Y.shape[0] - 1
    shape = (a + b + 1,) + np.broadcast_shapes(X.shape[1:], Y.shape[1:])
    Z = np.zeros(shape)
    for i in range(a + 1):
        for j in range(b + 1):
            Z[i + j] += (math.comb(a, i) * math.comb(b, j) / math.comb(a + b, i + j)) * X[i] * Y[j]
    return Z


def elevate(X: np.ndarray, by: int) -> np.ndarray:
    """The same polynomials ``X`` (a + 1, n) written with degree a + by."""
    return product(X, np.ones(by + 1))


def halves(B: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """De Casteljau at s = 1/2: the coefficients of the polynomials ``B`` (m + 1, n)
    restricted to [0, 1/2] and to [1/2, 1], each rescaled to [0, 1]."""
    m = B.shape[0] - 1
    left, right = np.empty_like(B), np.empty_like(B)
    level = B.copy()
    for r in range(m + 1):
        left[r] = level[0]
        right[m - r] = level[m - r]
        level = 0.5 * (level[:-1] + level[1:])
    return left, right


def sign_changes(B: np.ndarray) -> np.ndarray:
    """Number of sign changes along each column of ``B`` (m + 1, n), zeros counted as
    positive (at least the number of roots in (0, 1), with the same parity, except for
    roots exactly at a coefficient's zero; a zero end coefficient is a root at that end)."""
    negative = B < 0.0
    return np.count_nonzero(negative[1:] != negative[:-1], axis=0)


# ---------------------------------------------------------------------------------------
# nets of the distance to a polynomial (or rational) piece C(x) = N(x) / w(x), given by
# its Taylor coefficients about the middle of a cell: coef ((k + 1) D, n), row i D + d the
# coefficient of x^i of homogeneous component d (D = 3: polynomial, D = 4: (w N, w))
# ---------------------------------------------------------------------------------------


def piece_nets(coef: np.ndarray, length: np.ndarray, k: int, D: int) -> list[np.ndarray]:
    """Bezier nets over the cells (local s in [0, 1]) of the D homogeneous components,
    each (k + 1, n), for cells of parameter length ``length`` (n,)."""
    scale = np.asarray(length, dtype=float)[None, :] ** np.arange(k + 1)[:, None]  # L^i
    T = from_taylor(k)
    return [T @ (coef[d::D] * scale) for d in range(D)]


def stationary_nets(coef: np.ndarray, length: np.ndarray, k: int, D: int) -> tuple[np.ndarray, np.ndarray]:
    """Bernstein coefficients over each cell of a positive multiple of ``g = C_s . (C - p)``
    for a point p: ``G0 - sum_d p_d G1[d]``, G0 (M + 1, n), G1 (3, M + 1, n). Polynomial:
    M = 2k - 1; rational (C = N / w): the numerator of ``g w^3 = (N_s w - N w_s) . (N - p
    w)``, M = 3k - 1."""
    net = piece_nets(coef, length, k, D)
    d_net = [derivative(x) for x in net]
    if D == 3:
        G0 = sum(product(d_net[d], net[d]) for d in range(3))
        G1 = [elevate(d_net[d], k) for d in range(3)]
    else:
        w, w_s = net[3], d_net[3]
        Q = [product(d_net[d], w) - product(net[d], w_s) for d in range(3)]
        G0 = sum(product(Q[d], net[d]) for d in range(3))
        G1 = [product(Q[d], w) for d in range(3)]
    return np.ascontiguousarray(G0), np.ascontiguousarray(np.stack(G1))


def distance_nets(coef: np.ndarray, length: np.ndarray, k: int, D: int) -> np.ndarray:
    """(5, 2k + 1, n): F0, F1 (3), F2 with ``|C - p|^2 w^2 = F0 - 2 p . F1 + |p|^2 F2``
    (w = 1 for a polynomial piece). F2 > 0, and the squared distance over the cell lies
    between the smallest and largest ratio (F0 - 2 p . F1 + |p|^2 F2)_j / F2_j (a convex
    combination of them)."""
    net = piece_nets(coef, length, k, D)
    w = net[3] if D == 4 else np.ones_like(net[0])
    F0 = sum(product(net[d], net[d]) for d in range(3))
    F1 = [product(net[d], w) for d in range(3)]
    F2 = product(w, w)
    return np.ascontiguousarray(np.stack([F0, *F1, F2]))
