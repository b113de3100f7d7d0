"""Bernstein-form polynomial helpers (geometry._bernstein) against direct evaluation, and
the nets of C'.(C - p) and of the distance against the curve's own values."""

from math import comb

import numpy as np
import pytest

from ibfem.geometry import _bernstein
from ibfem.geometry.bspline import BSplineCurve


def _evaluate(B, s):
    """Value at s of the Bernstein polynomials B (m + 1, n): the definition, term by term."""
    m = B.shape[0] - 1
    basis = np.array([comb(m, j) * s**j * (1 - s) ** (m - j) for j in range(m + 1)])
    return basis.T @ B


S = np.linspace(0.0, 1.0, 13)


def test_taylor_product_derivative_halves_against_direct_evaluation():
    rng = np.random.default_rng(0)
    for k in (1, 2, 3, 5, 7):
        a = rng.normal(size=(k + 1, 4))  # sum_i a_i (s - 1/2)^i
        B = _bernstein.from_taylor(k) @ a
        direct = sum(a[i] * (S[:, None] - 0.5) ** i for i in range(k + 1))
        assert np.allclose(_evaluate(B, S), direct, atol=1e-13)
        X, Y = B[:, :2], rng.normal(size=(3, 2))
        assert np.allclose(_evaluate(_bernstein.product(X, Y), S), _evaluate(X, S) * _evaluate(Y, S), atol=1e-13)
        # derivative: central differences of the direct polynomial
        h = 1e-6
        fd = (_evaluate(B, S[1:-1] + h) - _evaluate(B, S[1:-1] - h)) / (2 * h)
        assert np.allclose(_evaluate(_bernstein.derivative(B), S[1:-1]), fd, atol=1e-7)
        left, right = _bernstein.halves(B)
        assert np.allclose(_evaluate(left, S), _evaluate(B, S / 2), atol=1e-13)
        assert np.allclose(_evaluate(right, S), _evaluate(B, 0.5 + S / 2), atol=1e-13)


def test_sign_changes_bound_the_roots_with_their_parity():
    # (s - 0.2)(s - 0.5)(s - 0.9): three roots in (0, 1)
    a = np.polynomial.polynomial.polyfromroots([0.2 - 0.5, 0.5 - 0.5, 0.9 - 0.5])  # in s - 1/2
    B = _bernstein.from_taylor(3) @ a[:, None]
    assert _bernstein.sign_changes(B)[0] == 3
    left, right = _bernstein.halves(B)
    assert _bernstein.sign_changes(left)[0] == 1 and _bernstein.sign_changes(right)[0] == 2
    # no root in (0, 1): (s + 0.5)^2 + 0.1
    B = _bernstein.from_taylor(2) @ np.array([[1.1], [2.0], [1.0]])
    assert _bernstein.sign_changes(B)[0] == 0


@pytest.mark.parametrize("rational", [False, True])
@pytest.mark.parametrize("k", [1, 2, 3, 5])
def test_curve_nets_of_the_distance_and_its_derivative(k, rational):
    """G0 - p.G1 is a positive multiple of C'.(C - p) over each cell (same sign, zero at the
    same places); the distance net's ratios bound |C - p|^2 over the cell from below."""
    rng = np.random.default_rng(k + 10 * rational)
    n = k + 6
    t = np.r_[[0.0] * (k + 1), np.sort(rng.uniform(0, 1, n - k - 1)), [1.0] * (k + 1)]
    c = BSplineCurve(k, t, np.cumsum(rng.uniform(-1, 1, (n, 3)), axis=0), np.exp(rng.uniform(-1.5, 1.5, n)) if rational else None)
    edges, mids, coef = c._pieces
    D = 4 if rational else 3
    G0, G1 = _bernstein.stationary_nets(coef, np.diff(edges), k, D)
    F = _bernstein.distance_nets(coef, np.diff(edges), k, D)
    for _ in range(5):
        p = rng.normal(size=3) * 2
        cell = int(rng.integers(len(mids)))
        L = edges[cell + 1] - edges[cell]
        x = edges[cell] + S * L
        C, C1 = c.derivatives(x, 1)
        g = np.einsum("ij,ij->i", C1, C - p)
        b = G0[:, cell] - sum(p[d] * G1[d][:, cell] for d in range(3))
        multiple = _evaluate(b[:, None], S)[:, 0]
        big = np.abs(g) > 1e-9 * np.abs(g).max()
        assert np.all(np.sign(multiple[big]) == np.sign(g[big]))
        ratio = multiple[big] / g[big]
        assert np.all(ratio > 0)
        f = np.sum((C - p) ** 2, axis=1)
        num = F[0, :, cell] - 2 * sum(p[d] * F[1 + d, :, cell] for d in range(3)) + (p @ p) * F[4, :, cell]
        assert (num / F[4, :, cell]).min() <= f.min() + 1e-12
        assert np.allclose(_evaluate(num[:, None], S)[:, 0] / _evaluate(F[4, :, cell][:, None], S)[:, 0], f, atol=1e-10)
