"""The compiled kernels of :mod:`solver.fem.pair_blocks` (numba): each cell pair's sums over its
points, one pass over the points with the pair's (48 x 48) sum held in the cache, instead of the
per-point (48 x 3) factors, their tensor products and a small matrix product per pair built one
after the other in memory. At module level so that numba's on-disk cache (``cache=True``) keeps
them between processes; they release the GIL (``nogil``), so two threads sum two ranges of
pairs side by side.

The points are in :class:`~solver.fem.pair_blocks.PairBlocks`' stored order (grouped by pair),
per-point tensors in the caller's order read through ``order``."""

from __future__ import annotations

import numpy as np
from numba import njit

jit = njit(cache=True, nogil=True, error_model="numpy", fastmath={"reassoc", "contract"})


@jit
def band_pair_sums(shape, traction, pen, wp, order, consistency, bounds, first, last, out):
    """out[p] for pairs first..last-1: sum over the pair's points of M_q + M_q^T with
    M_q[A, 3 b + j] = X_q[A, j] n_q[b], X_q[3 a + i, j] = n_q[a] pen_q[i, j] / 2 -
    consistency sum_l traction_q[l, 3 a + i] wp_q[l, j] (n_q = shape[k], 16 values; traction
    (q, 3, 48) stored order; pen, wp (q, 3, 3) caller's order, point k's at ``order[k]``)."""
    nodes = shape.shape[1]
    width = 3 * nodes
    x = np.empty((width, 3))
    for p in range(first, last):
        o = out[p]
        o[:, :] = 0.0
        for k in range(bounds[p], bounds[p + 1]):
            c = order[k]
            for a in range(nodes):
                half = 0.5 * shape[k, a]
                for i in range(3):
                    row = 3 * a + i
                    for j in range(3):
                        x[row, j] = half * pen[c, i, j] - consistency * (
                            traction[k, 0, row] * wp[c, 0, j] + traction[k, 1, row] * wp[c, 1, j]
                            + traction[k, 2, row] * wp[c, 2, j])
            for row in range(width):
                x0, x1, x2 = x[row, 0], x[row, 1], x[row, 2]
                for b in range(nodes):
                    nb = shape[k, b]
                    o[row, 3 * b] += x0 * nb
                    o[row, 3 * b + 1] += x1 * nb
                    o[row, 3 * b + 2] += x2 * nb
        for r in range(width):
            for s in range(r, width):
                v = o[r, s] + o[s, r]
                o[r, s] = v
                o[s, r] = v


@jit
def outer_pair_sums(left, right, weights, bounds, first, last, out):
    """out[p] for pairs first..last-1: sum over the pair's points k of weights[k] left[k] right[k]^T
    (rows (q, l) and (q, r), weights (q,), all in stored order)."""
    nl, nr = left.shape[1], right.shape[1]
    for p in range(first, last):
        o = out[p]
        o[:, :] = 0.0
        for k in range(bounds[p], bounds[p + 1]):
            w = weights[k]
            if w == 0.0:
                continue
            for r in range(nl):
                v = w * left[k, r]
                if v != 0.0:
                    for s in range(nr):
                        o[r, s] += v * right[k, s]


@jit
def gather_weighted_traction(traction1, traction2, w1, w2, order, out):
    """out[k] = [w1 traction1[order[k]], w2 traction2[order[k]]] along the last axis: the flux
    blocks (q, 3, 48) of both bodies' traction blocks (q, 3, 24) in stored order."""
    width = traction1.shape[2]
    for k in range(order.shape[0]):
        c = order[k]
        for i in range(traction1.shape[1]):
            for j in range(width):
                out[k, i, j] = w1 * traction1[c, i, j]
                out[k, i, width + j] = w2 * traction2[c, i, j]
