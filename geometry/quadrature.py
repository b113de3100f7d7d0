"""Gauss-Legendre rules and the triangles' midpoint split shared by the exact-geometry integrals
of geometry and solver."""

from __future__ import annotations

from functools import lru_cache

import numpy as np

__all__ = ["gauss_legendre", "quartered"]


@lru_cache(maxsize=None)
def gauss_legendre(order: int) -> tuple[np.ndarray, np.ndarray]:
    """Points and weights on [-1, 1] (numpy's leggauss, cached, read-only)."""
    x, w = np.polynomial.legendre.leggauss(order)
    x.setflags(write=False)
    w.setflags(write=False)
    return x, w


def quartered(triangles: np.ndarray) -> np.ndarray:
    """Each triangle (k, 3, d) split into four at its edges' midpoints, (4k, 3, d): the three
    corner triangles of every triangle, then the middle ones."""
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    ab, bc, ca = 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a)
    return np.concatenate([np.stack(t, 1) for t in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))])
