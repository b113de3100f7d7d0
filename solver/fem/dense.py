"""Dense helpers of the factorisations (:mod:`solver.fem.linalg`, :mod:`solver.fem.multifrontal`)."""

from __future__ import annotations

import numpy as np

__all__ = ["symmetric_from_lower"]


def symmetric_from_lower(a: np.ndarray, block: int = 512) -> np.ndarray:
    """Fill the upper triangle of the square ``a`` from its lower one, in place, by row blocks
    (no m x m temporaries: the Schur complement S and G = S^-1 are the largest dense arrays of a
    3D contact run). Returns ``a``."""
    m = len(a)
    for b0 in range(0, m, block):
        b1 = min(b0 + block, m)
        a[b0:b1, b1:] = a[b1:, b0:b1].T
        diag = a[b0:b1, b0:b1]
        diag[...] = np.tril(diag) + np.tril(diag, -1).T
    return a
