"""Bisection of many brackets at once: the midpoints the next steps may take, laid out as a
heap, so that one call of a costly function can answer several bisection steps together."""

from __future__ import annotations

import numpy as np

__all__ = ["bisection_tree"]


def bisection_tree(a: np.ndarray, b: np.ndarray, levels: int) -> np.ndarray:
    """(m, 2^levels - 1) the midpoints the next ``levels`` bisection steps of [a, b] may take, in
    heap order: node i's bracket halves to node 2i + 1 (the zero above its midpoint) and 2i + 2
    (below it), each midpoint 0.5 (lo + hi) as one bisection step computes it."""
    lo, hi = a[:, None], b[:, None]  # the brackets of one level's nodes, left to right
    mids = []
    for _ in range(levels):
        mid = 0.5 * (lo + hi)
        mids.append(mid)
        # node j's children 2j (the zero above its midpoint: [mid, hi]) and 2j + 1 ([lo, mid])
        shape = (len(a), 2 * mid.shape[1])
        lo, hi = np.stack([mid, lo], axis=2).reshape(shape), np.stack([hi, mid], axis=2).reshape(shape)
    return np.concatenate(mids, axis=1)
