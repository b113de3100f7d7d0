"""The condensed operators of bodies that K0 does not couple: one block per body.

Two bodies in contact are coupled only by the contact terms, never by K0 (unless a body held only
through the contact keeps a small fixed region in K0). Then the Schur complement S of the contact
dofs, and G = S^-1, are block diagonal: one block per body's contact dofs. Factoring each body on
its own with its contact dofs last keeps two blocks of (m/2)^2 entries instead of one of m^2 and
does a quarter of the dense work (the root fronts' factorisation and G are cubic in their size).

:class:`BlockDiagonal` holds the blocks (dense arrays or operators with ``@`` and ``toarray``)
at their positions in the m condensed dofs; :class:`BlockFactor` solves K0 u = f body by body.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

__all__ = ["BlockDiagonal", "BlockFactor", "uncoupled_groups"]


def uncoupled_groups(k: sp.spmatrix, dofs: np.ndarray) -> np.ndarray | None:
    """Group of each dof of ``k`` (n,) such that k couples no two groups and each group holds
    some of ``dofs`` (the parts of k without any of them join group 0); None when there is one
    group only."""
    n_parts, label = connected_components(k, directed=False)
    if n_parts < 2:
        return None
    with_dofs = np.unique(label[dofs])
    if len(with_dofs) < 2:
        return None
    group_of_part = np.zeros(n_parts, dtype=np.int64)
    group_of_part[with_dofs] = np.arange(len(with_dofs))
    return group_of_part[label]


class BlockFactor:
    """K0^-1 f from the factors of K0's uncoupled blocks (``parts``: the global dofs of each),
    the blocks solved side by side on threads (``IBFEM_THREADS``, default the cores) when every
    factor says its solves may run so (``threaded_solve``: the multifrontal factor's compiled
    solves release the GIL; SuperLU's are left one at a time)."""

    def __init__(self, parts: list[np.ndarray], factors: list):
        self.parts, self.factors = parts, factors

    def solve(self, f: np.ndarray) -> np.ndarray:
        from ..model.estimate import factor_threads

        f = np.asarray(f, dtype=np.float64)
        out = np.empty_like(f)

        def one(k: int) -> None:
            idx = self.parts[k]
            out[idx] = self.factors[k].solve(np.ascontiguousarray(f[idx]))

        threaded = all(getattr(factor, "threaded_solve", False) for factor in self.factors)
        workers = min(len(self.factors), factor_threads()) if threaded else 1
        if workers > 1:
            with ThreadPoolExecutor(workers) as pool:
                list(pool.map(one, range(len(self.factors))))
        else:
            for k in range(len(self.factors)):
                one(k)
        return out


class BlockDiagonal:
    """An m x m block-diagonal matrix: block k (dense or an operator with ``@`` and ``toarray``)
    on the condensed positions ``positions[k]`` (disjoint, together all of 0..m-1)."""

    def __init__(self, blocks: list, positions: list[np.ndarray]):
        self.blocks, self.positions = blocks, positions
        m = int(sum(len(p) for p in positions))
        self.shape, self.ndim = (m, m), 2
        self._block_of = np.empty(m, dtype=np.int64)
        self._local = np.empty(m, dtype=np.int64)
        for k, p in enumerate(positions):
            self._block_of[p] = k
            self._local[p] = np.arange(len(p))

    def __matmul__(self, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=np.float64)
        out = np.zeros(x.shape)
        for block, p in zip(self.blocks, self.positions):
            out[p] = block @ x[p]
        return out

    def take(self, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
        """The dense sub-matrix on ``rows`` x ``cols`` (zeros between blocks; a block that is not
        an array gives its entries by its own ``take``)."""
        out = np.zeros((len(rows), len(cols)))
        for k, block in enumerate(self.blocks):
            r = np.flatnonzero(self._block_of[rows] == k)
            c = np.flatnonzero(self._block_of[cols] == k)
            if len(r) and len(c):
                lr, lc = self._local[rows[r]], self._local[cols[c]]
                out[np.ix_(r, c)] = block[np.ix_(lr, lc)] if isinstance(block, np.ndarray) else block.take(lr, lc)
        return out

    def diagonal_blocks(self, rows: np.ndarray):
        """(where, dense block): for each block holding some of ``rows``, the positions in
        ``rows`` of its dofs and its sub-matrix on them (the sub-matrix of this matrix on
        ``rows`` is zero outside these blocks)."""
        for k in range(len(self.blocks)):
            where = self.block_positions(rows, k)
            if len(where):
                yield where, self.block_take(rows, where, k)

    def block_positions(self, rows: np.ndarray, k: int) -> np.ndarray:
        """The positions in ``rows`` of block k's dofs."""
        return np.flatnonzero(self._block_of[rows] == k)

    def block_take(self, rows: np.ndarray, where: np.ndarray, k: int) -> np.ndarray:
        """Block k's dense sub-matrix on ``rows[where]`` (``where``: :meth:`block_positions`)."""
        block, local = self.blocks[k], self._local[rows[where]]
        return block[np.ix_(local, local)] if isinstance(block, np.ndarray) else block.take(local, local)

    def toarray(self) -> np.ndarray:
        out = np.zeros(self.shape)
        for block, p in zip(self.blocks, self.positions):
            out[np.ix_(p, p)] = block if isinstance(block, np.ndarray) else block.toarray()
        return out

    def __array__(self, dtype=None, copy=None):
        a = self.toarray()
        return a if dtype is None else a.astype(dtype)
