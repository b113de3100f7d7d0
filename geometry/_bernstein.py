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
