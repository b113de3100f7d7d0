"""Bounding boxes of Bezier cells and the branch-and-bound search over them (the global
check of B-spline projection, see :mod:`geometry.bspline`).

Arrays here are component-major ("structure of arrays"): a set of n vectors is (3, n), a
table of n boxes is (15, n). numpy then runs every operation over long contiguous rows;
with (n, 3) rows and a broadcast (n, 1) factor it runs a 3-long inner loop per row, which
measured 5-7 times slower (260 us against 39 us for 16384 products).
"""

from __future__ import annotations

import math

import numpy as np

# top level of a box hierarchy: the deepest level with at most this many nodes; it is
# tested against all points with one matrix product
_TOP_NODES = 64
# points per matrix product at the top level (bounds the (nodes, points) temporaries)
_TOP_ENTRIES = 1 << 18


def bernstein_inverse(k: int) -> np.ndarray:
    """Inverse of the Bernstein collocation matrix at the equally spaced nodes m / k: maps
    k + 1 values of a degree-k polynomial piece to its Bezier control points."""
    x = np.arange(k + 1) / k
    ell = np.arange(k + 1)
    B = np.array([math.comb(k, i) for i in ell]) * x[:, None] ** ell * (1.0 - x[:, None]) ** (k - ell)
    return np.linalg.inv(B)


def rowdot(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Row-wise dot product of (n, 3) arrays."""
    return np.einsum("ij,ij->i", x, y)


def coldot(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Column-wise dot product of component-major (3, n) arrays."""
    return np.einsum("ij,ij->j", x, y)


def rows_as_columns(table: np.ndarray, idx: np.ndarray) -> np.ndarray:
    """Rows ``idx`` of a row-per-cell table, turned component-major (width, n): a cell's
    row is contiguous, so gathering rows and turning them once is the fast order."""
    return np.ascontiguousarray(np.take(table, idx, axis=0).T)


def oriented_boxes(pts: np.ndarray, e1: np.ndarray, e2: np.ndarray, margin: float):
    """Boxes of control nets ``pts`` (n, m, 3) in per-cell orthonormal frames built from
    the directions e1, e2 (n, 3) (Gram-Schmidt; a degenerate direction falls back to the
    coordinate axes): (origin (n, 3), frame rows (n, 3, 3), lo, hi (n, 3)). Aligned with a
    cell's tangents, the box is only as thick as the cell bends (~ curvature h^2 / 8), so
    its distance bounds the cell's distance far more tightly than an axis-aligned box."""

    def unit(v, fallback):
        n = np.linalg.norm(v, axis=1, keepdims=True)
        return np.where(n > 1e-300, v / np.where(n > 1e-300, n, 1.0), fallback)

    x, y = np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
    a = unit(e1, x)
    b = e2 - rowdot(e2, a)[:, None] * a
    alt = np.where(np.abs(a[:, :1]) < 0.9, x, y)
    alt = alt - rowdot(alt, a)[:, None] * a
    usable = np.linalg.norm(b, axis=1, keepdims=True) > 1e-9 * np.linalg.norm(e2, axis=1, keepdims=True) + 1e-300
    b = unit(np.where(usable, b, alt), alt / np.linalg.norm(alt, axis=1, keepdims=True))
    c = np.cross(a, b)
    R = np.stack([a, b, c], axis=1)
    origin = pts[:, 0]
    L = _in_frames(pts - origin[:, None], R)
    return origin, R, L.min(axis=1) - margin, L.max(axis=1) + margin


def _in_frames(nets: np.ndarray, R: np.ndarray) -> np.ndarray:
    """Coordinates (n, m, 3) of nets (n, m, 3) in frames R (n, 3, 3): a batched matmul
    (6x faster than the equivalent einsum, which numpy 2 runs as many tiny products)."""
    return np.matmul(nets, R.transpose(0, 2, 1))


def frame_boxes(nets: np.ndarray, R: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Boxes (lo, hi), each (3, n), of control nets (n, m, 3) in the cells' frames R (n, 3, 3)."""
    L = _in_frames(nets, R)
    lo, hi = L.min(axis=1), L.max(axis=1)
    pad = 1e-9 * np.maximum(np.abs(lo), np.abs(hi)).max(axis=1, keepdims=True)
    return np.ascontiguousarray((lo - pad).T), np.ascontiguousarray((hi + pad).T)


def box_levels(pts: np.ndarray, e1: np.ndarray, e2: np.ndarray, branch: int, margin: float, top: int = _TOP_NODES) -> list[tuple]:
    """Hierarchy of oriented boxes (see :func:`oriented_boxes`) over cells with control
    nets ``pts`` (n, m, 3) in a spatially coherent order: node i of a level bounds the
    nodes ``branch i .. branch i + branch - 1`` of the level below (its frame from their
    summed directions); top level (at most ``top`` nodes) first, the cells' own boxes last."""

    def unit(v):
        return v / np.maximum(np.linalg.norm(v, axis=1, keepdims=True), 1e-300)

    levels = [oriented_boxes(pts, e1, e2, margin)]
    e1, e2 = levels[0][1][:, 0], levels[0][1][:, 1]
    while len(pts) > top:
        m = -(-len(pts) // branch)
        fill = np.arange(m * branch) % len(pts)  # pad with repeated cells (harmless)
        pts = pts[fill].reshape(m, -1, 3)
        e1 = unit(e1[fill].reshape(m, branch, 3).sum(axis=1))
        e2 = unit(e2[fill].reshape(m, branch, 3).sum(axis=1))
        levels.append(oriented_boxes(pts, e1, e2, margin))
        e1, e2 = levels[-1][1][:, 0], levels[-1][1][:, 1]
    return levels[::-1]


def _frame_offsets(T: np.ndarray, x: np.ndarray) -> list[np.ndarray]:
    """Per frame axis k, ``(R x)_k - c_k`` for points ``x`` (3, n) and oriented boxes ``T``
    (rows: frame R (9), frame centre c (3), half widths (3), ...)."""
    out = []
    for k in range(3):
        y = T[3 * k] * x[0]
        y += T[3 * k + 1] * x[1]
        y += T[3 * k + 2] * x[2]
        y -= T[9 + k]
        out.append(y)
    return out


def _gap2(y: list[np.ndarray], T: np.ndarray) -> np.ndarray:
    """Squared distance to the boxes from the frame offsets ``y``."""
    d2 = np.zeros(len(y[0]))
    for k in range(3):
        g = np.abs(y[k])
        g -= T[12 + k]
        np.maximum(g, 0.0, out=g)
        g *= g
        d2 += g
    return d2


class CellSearch:
    """Branch and bound over a box hierarchy (levels from :func:`box_levels`): every
    (point, cell) pair whose cell box lies closer to the point than a per-point bound,
    with interval bounds of ``V . (S - p)`` over the cell for the vector fields V whose
    boxes ``extra`` (pairs (lo, hi), each (3, n_cells), in the cells' frames) are given:
    S in the cell's box, V in its box.

    The top level (at most ``_TOP_NODES`` nodes) is screened for all points at once by the
    nodes' bounding spheres (one matrix product, a few operations per (point, node)); then
    level by level the pairs that pass by the nodes' oriented boxes, and all children of a
    kept node. The cells' own boxes and the bounds share one gather per pair."""

    def __init__(self, levels: list[tuple], branch: int, extra: tuple = ()):
        self.branch = branch
        tables = []
        for depth, (origin, R, lo, hi) in enumerate(levels):
            # rows: frame R (9), R origin + box centre (3), box half widths (3); a point's
            # gap to the box is then max(|R p - c| - h, 0) per frame axis
            t = np.concatenate(
                [R.reshape(-1, 9), np.einsum("nkj,nj->nk", R, origin) + 0.5 * (lo + hi), 0.5 * (hi - lo)], axis=1
            )
            if depth == len(levels) - 1:
                t = np.concatenate([t] + [np.concatenate([a.T, b.T], axis=1) for a, b in extra], axis=1)
            n = len(t) if depth == 0 else -(-len(t) // branch) * branch
            pad = np.zeros((n - len(t), t.shape[1]))
            pad[:, 12:15] = -1e150  # padding nodes are never within reach (finite: no nan in the bounds)
            tables.append(np.ascontiguousarray(np.concatenate([t, pad]).T))
        origin, R, lo, hi = levels[0]
        # bounding spheres of the top boxes: centre c = origin + R^T (box centre), radius
        # the half diagonal (rounded up); the sphere test |p - c| < bound + radius is
        # -2 (c.p + radius bound) + (|c|^2 - radius^2) + (|p|^2 - bound^2) < 0, its first
        # term one matrix product of [c, radius] with [p, bound]
        centre = origin + np.einsum("nkj,nk->nj", R, 0.5 * (lo + hi))
        radius = np.linalg.norm(0.5 * (hi - lo), axis=1) * (1.0 + 1e-12)
        self.top_m2 = np.ascontiguousarray(-2.0 * np.column_stack([centre, radius]))
        self.top_cc = np.einsum("ij,ij->i", centre, centre)
        self.top_const = self.top_cc - radius * radius
        self.tables = tables
        self.n_extra = len(extra)

    def flat_nodes(self) -> tuple[np.ndarray, np.ndarray]:
        """All levels' nodes as one (n_nodes, 15 + 6 extra fields) table (rows of
        :meth:`pairs`' tables, zero-padded) and the first node of each level (see
        :mod:`geometry._jit`)."""
        width = 15 + 6 * self.n_extra
        rows = [np.pad(t, ((0, width - t.shape[0]), (0, 0))).T for t in self.tables]
        level_start = np.cumsum([0] + [len(r) for r in rows])
        return np.ascontiguousarray(np.concatenate(rows)), level_start.astype(np.int64)

    def pairs(self, p: np.ndarray, bound2: np.ndarray) -> tuple[np.ndarray, np.ndarray, list]:
        """(point index, cell index) of all pairs whose cell box is closer to the point
        (``p`` (3, m)) than ``sqrt(bound2)``, and per extra field the bounds (low, high)."""
        m = p.shape[1]
        n_top = len(self.top_const)
        chunk = max(256, _TOP_ENTRIES // n_top)
        X = np.empty((4, m))
        X[:3] = p
        X[3] = np.sqrt(bound2)
        rest = np.einsum("ij,ij->j", p, p)
        # the round-off of the expanded squares: a little slack (never fewer pairs)
        slack = 1e-14 * (self.top_cc.max() + rest.max())
        rest -= bound2
        pis, nodes = [], []
        for i0 in range(0, m, chunk):
            sl = slice(i0, i0 + chunk)
            d = self.top_m2 @ X[:, sl]
            d += (self.top_const - slack)[:, None]
            d += rest[sl]
            node, pt = np.nonzero(d < 0.0)
            pis.append(pt + i0)
            nodes.append(node)
        pi, node = np.concatenate(pis), np.concatenate(nodes)
        kids = np.arange(self.branch)
        last = len(self.tables) - 1
        for depth, tab in enumerate(self.tables):
            if depth:  # all children of the kept nodes
                node = (node[:, None] * self.branch + kids).ravel()
                pi = np.repeat(pi, self.branch)
            T = np.take(tab if depth == last else tab[:15], node, axis=1)
            y = _frame_offsets(T, np.take(p, pi, axis=1))
            keep = np.flatnonzero(_gap2(y, T) < bound2[pi])
            if depth < last:
                pi, node = pi[keep], node[keep]
        bounds = []
        for e in range(self.n_extra):
            # S - p lies in [-h - y, h - y] (frame coordinates), V in [vlo, vhi]
            low, high = np.zeros(len(pi)), np.zeros(len(pi))
            for k in range(3):
                slo = -T[12 + k] - y[k]
                shi = slo + 2.0 * T[12 + k]
                vlo, vhi = T[15 + 6 * e + k], T[18 + 6 * e + k]
                a, b, c, d = vlo * slo, vlo * shi, vhi * slo, vhi * shi
                low += np.minimum(np.minimum(a, b), np.minimum(c, d))
                high += np.maximum(np.maximum(a, b), np.maximum(c, d))
            bounds.append((low[keep], high[keep]))
        return pi[keep], node[keep], bounds


def morton_order(cu: int, cv: int) -> np.ndarray:
    """The cells i cv + j of a cu x cv grid in Morton (Z) order: groups of 4^n consecutive
    cells are 2^n x 2^n tiles, so that a box hierarchy over them stays compact."""
    I, J = np.repeat(np.arange(cu), cv), np.tile(np.arange(cv), cu)
    key = np.zeros(len(I), dtype=np.int64)
    for bit in range(16):
        key |= ((I >> bit) & 1) << (2 * bit + 1) | ((J >> bit) & 1) << (2 * bit)
    return np.argsort(key, kind="stable")


def best_per_point(pi: np.ndarray, f: np.ndarray, m: int) -> np.ndarray:
    """Index into the pair arrays of the smallest ``f`` of each of the points 0 .. m - 1
    (every point has at least one pair)."""
    best = np.full(m, np.inf)
    np.minimum.at(best, pi, f)
    win = np.flatnonzero(f == best[pi])
    out = np.empty(m, dtype=np.int64)
    out[pi[win]] = win  # ties: any of them
    return out


def middle_leaves(level_start: np.ndarray, branch: int, n_leaves: int) -> np.ndarray:
    """For every node of a flat hierarchy (see :meth:`CellSearch.flat_nodes`) the leaf in
    the middle of its run of leaves (clamped for padding nodes): where the compiled
    kernels take a point of the spline in the node, whose distance bounds the answer."""
    n_levels = len(level_start) - 1
    out = []
    for lvl in range(n_levels):
        span = branch ** (n_levels - 1 - lvl)
        i = np.arange(level_start[lvl + 1] - level_start[lvl])
        out.append(np.minimum(i * span + span // 2, n_leaves - 1))
    return np.concatenate(out).astype(np.int64)
