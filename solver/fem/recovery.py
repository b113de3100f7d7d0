"""Recovered (smoothed) stresses from the stresses at cell centroids.

Bilinear squares have their most accurate stresses at the cell centres (superconvergence).
Nodal values are the inside-area weighted mean of the centroid stresses of the cells around a
node; at nodes touching a cut cell, where the node may lie outside the body and the one-ring of
centroids is lopsided, a weighted least-squares linear fit over the two-ring of cells is
evaluated at the node instead (superconvergent patch recovery in the manner of Zienkiewicz and
Zhu), so peaks at the boundary are extrapolated rather than averaged away. The recovered field
is the bilinear interpolation of these nodal values.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .grid import CUT, Grid

__all__ = ["nodal_stress"]


def nodal_stress(grid: Grid, centroids: np.ndarray, stress: np.ndarray) -> np.ndarray:
    """(N, k) recovered nodal values of cell values ``stress`` (m, k) given at ``centroids``."""
    m, n = len(grid.level), len(grid.nodes)
    w = grid.inside_area
    rows = grid.cells.ravel()
    cols = np.repeat(np.arange(m), 4)
    inc = sp.csr_matrix((np.ones(4 * m), (rows, cols)), shape=(n, m))
    with np.errstate(invalid="ignore", divide="ignore"):
        out = (inc @ (w[:, None] * stress)) / (inc @ w)[:, None]
    boundary = np.nonzero((inc @ (grid.status == CUT).astype(float)) > 0)[0]
    if len(boundary) == 0:
        return out
    ring2 = (inc[boundary] @ inc.T @ inc).tocoo()
    node, cell = boundary[ring2.row], ring2.col
    scale = np.full(n, np.inf)
    np.minimum.at(scale, rows, np.repeat(grid.size, 4))
    d = (centroids[cell] - grid.nodes[node]) / scale[node][:, None]
    basis = np.column_stack([np.ones(len(d)), d])  # (pairs, 3)
    local = np.searchsorted(boundary, node)
    wk = w[cell]
    mat = np.zeros((len(boundary), 3, 3))
    rhs = np.zeros((len(boundary), 3, stress.shape[1]))
    for i in range(3):
        for j in range(3):
            mat[:, i, j] = np.bincount(local, wk * basis[:, i] * basis[:, j], minlength=len(boundary))
        for k in range(stress.shape[1]):
            rhs[:, i, k] = np.bincount(local, wk * basis[:, i] * stress[cell, k], minlength=len(boundary))
    ev = np.linalg.eigvalsh(mat)
    ok = ev[:, 0] > 1e-8 * ev[:, -1]
    coef = np.linalg.solve(mat[ok], rhs[ok])
    out[boundary[ok]] = coef[:, 0, :]
    return out
