"""Gauss-Jacobi rule of solver.fem.surface_quadrature (Golub-Welsch) against scipy's independent
implementation and against moments in closed form (Beta functions)."""

import math

import numpy as np
import pytest
from scipy.special import roots_jacobi

from ibfem.solver.fem.surface_quadrature import gauss_jacobi


@pytest.mark.parametrize("alpha,beta", [(1.0, 0.0), (0.5, 1.5), (2.0, 3.0), (0.0, 1.0)])
def test_gauss_jacobi_matches_scipy(alpha, beta):
    for n in range(1, 13):
        x, w = gauss_jacobi(n, alpha, beta)
        xs, ws = roots_jacobi(n, alpha, beta)
        assert np.max(np.abs(x - xs)) < 1e-13
        assert np.max(np.abs(w / ws - 1.0)) < 1e-12


def test_gauss_jacobi_exact_to_degree_2n_minus_1():
    # int_-1^1 (1 - x)^a (1 + x) x^0..: with t = (1 + x)/2, (1 - x)^a (1 + x) = 2^(a + 1) (1 - t)^a t
    alpha, beta, n = 1.0, 0.0, 5
    x, w = gauss_jacobi(n, alpha, beta)
    for m in range(2 * n):
        # expand x^m = (2t - 1)^m and integrate against 2^(alpha+beta+1) (1-t)^alpha t^beta dt
        exact = sum(math.comb(m, j) * 2.0**j * (-1.0) ** (m - j)
                    * math.gamma(alpha + 1) * math.gamma(beta + j + 1) / math.gamma(alpha + beta + j + 2)
                    for j in range(m + 1)) * 2.0 ** (alpha + beta + 1)
        assert abs(np.sum(w * x**m) - exact) < 1e-13 * max(1.0, abs(exact))
