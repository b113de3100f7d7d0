"""Summation of cell matrices into the global sparse matrix, on node blocks."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["assemble_blocks"]


def assemble_blocks(cell_nodes: np.ndarray, k_cells: np.ndarray, n_nodes: int) -> sp.csr_matrix:
    """Sum cell matrices (m, 8, 8) over node dofs [x0, y0, x1, ...] into a sparse matrix.

    Works on 2x2 node blocks (16 per cell instead of 64 scalar triplets): the node-node pattern
    is the sparse product of the node-cell incidence with its transpose, each cell's 16 node
    pairs are found in it by one binary search, and four bincounts sum the blocks into a BSR
    matrix. Hand-written because scipy's COO -> CSR conversion sorts all 64 scalar triplets
    per cell, 2 to 3 times slower here.
    """
    m = len(cell_nodes)
    inc = sp.csr_matrix((np.ones(4 * m), (cell_nodes.ravel(), np.repeat(np.arange(m), 4))), shape=(n_nodes, m))
    pattern = (inc @ inc.T).tocsr()
    pattern.sort_indices()
    rows = np.repeat(np.arange(n_nodes, dtype=np.int64), np.diff(pattern.indptr))
    keys = rows * n_nodes + pattern.indices
    nodes = cell_nodes.astype(np.int64)
    position = np.searchsorted(keys, (nodes[:, :, None] * n_nodes + nodes[:, None, :]).ravel())
    blocks = np.ascontiguousarray(k_cells.reshape(m, 4, 2, 4, 2).transpose(0, 1, 3, 2, 4)).reshape(-1, 4)
    summed = np.empty((len(keys), 4))
    for j in range(4):
        summed[:, j] = np.bincount(position, blocks[:, j], minlength=len(keys))
    return sp.bsr_matrix(
        (summed.reshape(-1, 2, 2), pattern.indices, pattern.indptr), shape=(2 * n_nodes, 2 * n_nodes)
    ).tocsr()
