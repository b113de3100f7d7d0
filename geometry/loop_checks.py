"""Validity of a profile's loops: no loop crosses or touches itself, every hole lies inside
the outer loop and crosses neither it nor another hole, and no hole lies inside another.

The loops are walked as chord polylines (each edge's ``tessellate`` at ``1e-6`` of the
profile's size: exact for segments) and every pair of chords that are not neighbours along
a loop is tested for intersection. Pairs are found with a uniform grid of boxes (about one
cell per chord) so a loop of 10,000 chords checks in milliseconds. A chord pair hit where
a curved edge is involved is confirmed on the exact curves by Newton's method on
A(s) = B(t) started at the chords' intersection: a hit that does not converge to a common
point (two curves closer than the chord tolerance that do not meet) is dropped, and a
common point that is the vertex two consecutive edges share is not a crossing. Two loops
that overlap by less than the chord tolerance (1e-6 of the size) may go unnoticed.

Errors are ``ValueError`` messages naming the loop, the two edges and the crossing point.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from .bounded_curve import BoundedCurve
from .segments import Segment

__all__ = ["check_loops"]

#: chord tolerance of the crossing search, relative to the profile's size
CHORD_TOLERANCE = 1e-6
#: segments closer than this (relative to the size) touch
TOUCH_TOLERANCE = 1e-12


class _Chords:
    """All chords of all loops: ends a, b (m, 2), edge index, loop index, parameter range,
    and the chord's position along its loop (for the neighbour test)."""

    def __init__(self, loops: Sequence[Sequence[BoundedCurve]], size: float) -> None:
        X_all, t_all, counts = [], [], []
        self.curves: list[BoundedCurve] = [c for lp in loops for c in lp]
        self.edge_loop: list[int] = [li for li, lp in enumerate(loops) for _ in lp]
        self.edge_pos: list[int] = [j for lp in loops for j in range(len(lp))]
        self.loop_len: list[int] = [len(lp) for lp in loops]
        for curve in self.curves:
            if isinstance(curve, Segment):  # exact, and no call per edge
                X_all.append((curve.p0, curve.p1))
                t_all.append((0.0, curve.length))
                counts.append(1)
            else:
                X, t = curve.tessellate(CHORD_TOLERANCE * size)
                X_all.append(X)
                t_all.append(t)
                counts.append(len(X) - 1)
        counts = np.asarray(counts)
        ends = np.cumsum(counts + 1)  # the chords of edge k: points ends[k] - counts[k] - 1 ...
        X = np.vstack(X_all)
        t = np.concatenate([np.asarray(v, dtype=float) for v in t_all])
        first = np.repeat(ends - counts - 1, counts) + (np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts))
        self.a, self.b = X[first], X[first + 1]
        self.t0, self.t1 = t[first], t[first + 1]
        self.edge = np.repeat(np.arange(len(self.curves)), counts)
        #: how far a chord may stray from its curve (0 for segments)
        curved = np.array([not isinstance(c, Segment) for c in self.curves])
        self.deviation = np.where(curved[self.edge], 1.5 * CHORD_TOLERANCE * size, 0.0)
        self.loop = np.asarray(self.edge_loop)[self.edge]
        per_loop = np.bincount(self.loop, minlength=len(loops))
        start = np.cumsum(per_loop) - per_loop
        self.pos = np.arange(len(self.edge)) - start[self.loop]
        self.chords_in_loop = per_loop[self.loop]

    def neighbours(self, i: np.ndarray, j: np.ndarray) -> np.ndarray:
        """Chords i and j follow each other along the same loop (they share a vertex)."""
        same = self.loop[i] == self.loop[j]
        d = np.abs(self.pos[i] - self.pos[j])
        return same & ((d == 1) | (d == self.chords_in_loop[i] - 1))


def _candidate_pairs(lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pairs (i < j) of boxes [lo, hi] that overlap. Each box is entered in every cell it
    covers of a grid whose cells are about as large as most boxes (the 75th percentile of
    their widths and heights); boxes sharing a cell are paired. Boxes that would cover more
    than 64 cells (long edges) are tested against all boxes instead."""
    m = len(lo)
    origin = lo.min(axis=0)
    span = np.maximum(hi.max(axis=0) - origin, 1e-300)
    h = np.maximum(np.percentile(hi - lo, 75, axis=0), span / (m + 1))
    cells = np.minimum(np.ceil(span / h).astype(np.int64) + 1, 1 << 24)
    c0 = np.clip(((lo - origin) / h).astype(np.int64), 0, cells - 1)
    c1 = np.clip(((hi - origin) / h).astype(np.int64), 0, cells - 1)
    nx, ny = c1[:, 0] - c0[:, 0] + 1, c1[:, 1] - c0[:, 1] + 1
    big = nx * ny > 64
    count = np.where(big, 0, nx * ny)
    box = np.repeat(np.arange(m), count)
    k = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    cell = (c0[box, 0] + k % nx[box]) * cells[1] + c0[box, 1] + k // nx[box]
    order = np.argsort(cell, kind="stable")
    cell, box = cell[order], box[order]
    # entries of one cell are consecutive: pair each with the ones d places after it
    start = np.flatnonzero(np.concatenate([[True], cell[1:] != cell[:-1]]))
    size = np.diff(np.concatenate([start, [len(cell)]]))
    left = np.repeat(start + size, size) - np.arange(len(cell)) - 1  # entries after it in its cell
    active = np.flatnonzero(left > 0)
    pi, pj = [], []
    d = 1
    while active.size:
        pi.append(box[active])
        pj.append(box[active + d])
        d += 1
        active = active[left[active] >= d]
    for b in np.flatnonzero(big):  # long boxes against all boxes
        other = np.flatnonzero(np.all(lo <= hi[b], axis=1) & np.all(lo[b] <= hi, axis=1))
        pi.append(np.full(other.size, b))
        pj.append(other)
    if not pi:
        return np.empty(0, np.int64), np.empty(0, np.int64)
    i, j = np.concatenate(pi), np.concatenate(pj)
    i, j = np.minimum(i, j), np.maximum(i, j)
    key = np.sort(i * m + j)
    key = key[np.concatenate([[True], np.diff(key) != 0])]
    i, j = key // m, key % m
    keep = (i != j) & np.all(lo[i] <= hi[j], axis=1) & np.all(lo[j] <= hi[i], axis=1)
    return i[keep], j[keep]


def _point_segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance from points p to segments [a, b] and the closest points (all (n, 2))."""
    ab = b - a
    L2 = np.einsum("ij,ij->i", ab, ab)
    s = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.where(L2 > 0.0, L2, 1.0), 0.0, 1.0)
    c = a + s[:, None] * ab
    return np.hypot(p[:, 0] - c[:, 0], p[:, 1] - c[:, 1]), c


def _straddling(ch: _Chords, i: np.ndarray, j: np.ndarray, touch: np.ndarray) -> np.ndarray:
    """Which pairs have neither chord with both ends on one side of the other's line by more
    than ``touch`` (the others cannot come within ``touch``)."""

    def apart(p, q, u, v):  # u, v both beyond the line through p, q on the same side
        d = q - p
        L = np.hypot(d[:, 0], d[:, 1])
        su = (d[:, 0] * (u[:, 1] - p[:, 1]) - d[:, 1] * (u[:, 0] - p[:, 0])) / np.where(L > 0.0, L, 1.0)
        sv = (d[:, 0] * (v[:, 1] - p[:, 1]) - d[:, 1] * (v[:, 0] - p[:, 0])) / np.where(L > 0.0, L, 1.0)
        return ((su > touch) & (sv > touch)) | ((su < -touch) & (sv < -touch))

    a1, b1, a2, b2 = ch.a[i], ch.b[i], ch.a[j], ch.b[j]
    return ~(apart(a1, b1, a2, b2) | apart(a2, b2, a1, b1))


def _segment_hits(a1, b1, a2, b2, touch: float) -> tuple[np.ndarray, np.ndarray]:
    """Which segment pairs [a1, b1], [a2, b2] cross or come within ``touch`` of each other,
    and a common point of each (the crossing, or the midpoint of the closest approach)."""
    r, q = b1 - a1, b2 - a2
    w = a2 - a1
    den = r[:, 0] * q[:, 1] - r[:, 1] * q[:, 0]
    safe = np.where(den != 0.0, den, 1.0)
    s = (w[:, 0] * q[:, 1] - w[:, 1] * q[:, 0]) / safe
    u = (w[:, 0] * r[:, 1] - w[:, 1] * r[:, 0]) / safe
    proper = (den != 0.0) & (s >= 0.0) & (s <= 1.0) & (u >= 0.0) & (u <= 1.0)
    point = a1 + s[:, None] * r
    # closest approach: an end of one segment to the other segment
    cands = [(a1, a2, b2), (b1, a2, b2), (a2, a1, b1), (b2, a1, b1)]
    best = np.full(len(a1), np.inf)
    near = np.zeros_like(a1)
    for p, a, b in cands:
        d, c = _point_segment_distance(p, a, b)
        better = d < best
        best = np.where(better, d, best)
        near = np.where(better[:, None], 0.5 * (p + c), near)
    hit = proper | (best <= touch)
    return hit, np.where(proper[:, None], point, near)


def _newton_common_point(A: BoundedCurve, B: BoundedCurve, s: float, t: float, tol: float):
    """A common point A(s) = B(t) near the start (s, t) by Newton's method (parameters kept
    in the curves' domains), or None when it does not converge to within ``tol``."""
    for _ in range(60):
        F = A.evaluate(s)[0] - B.evaluate(t)[0]
        if np.hypot(F[0], F[1]) <= tol:
            return s, t
        dA, dB = A.derivative(s)[0], B.derivative(t)[0]
        det = -dA[0] * dB[1] + dA[1] * dB[0]
        if det == 0.0 or not np.isfinite(det):
            return None
        # J = [dA, -dB]; solve J (ds, dt) = -F
        ds = (-F[0] * -dB[1] - -dB[0] * -F[1]) / det
        dt = (dA[0] * -F[1] - dA[1] * -F[0]) / det
        s = float(np.clip(s + ds, A.t_start, A.t_end))
        t = float(np.clip(t + dt, B.t_start, B.t_end))
    return None


def _confirmed(ch: _Chords, i: int, j: int, point: np.ndarray, tol: float, vtx_tol: float) -> np.ndarray | None:
    """The exact common point of the curves of chords i and j near ``point``, or None when
    the curves do not meet there or meet only at a vertex their edges share."""
    ea, eb = int(ch.edge[i]), int(ch.edge[j])
    A, B = ch.curves[ea], ch.curves[eb]
    if isinstance(A, Segment) and isinstance(B, Segment):
        found = point
    else:
        def along(k, p):  # the chord's parameter at the point, interpolated
            d = ch.b[k] - ch.a[k]
            f = np.clip(np.dot(p - ch.a[k], d) / max(np.dot(d, d), 1e-300), 0.0, 1.0)
            return float(ch.t0[k] + f * (ch.t1[k] - ch.t0[k]))

        st = _newton_common_point(A, B, along(i, point), along(j, point), tol)
        if st is None:
            return None
        if ea == eb and abs(st[0] - st[1]) <= 1e-9 * (A.t_end - A.t_start):
            return None  # the same point of one edge
        found = A.evaluate(st[0])[0]
    if _shared_vertex(ch, ea, eb, found, vtx_tol):
        return None
    return found


def _shared_vertex(ch: _Chords, ea: int, eb: int, p: np.ndarray, tol: float) -> bool:
    """``p`` is (within ``tol`` of) a vertex where edges ea and eb follow each other along
    their loop, directly or across edges shorter than ``tol`` together (tiny CAD edges)."""
    if ch.edge_loop[ea] != ch.edge_loop[eb]:
        return False
    n = ch.loop_len[ch.edge_loop[ea]]
    A = ch.curves[ea]
    if ea == eb and np.hypot(*(A.end - A.start)) <= tol:  # a closed edge meets itself at its start
        return bool(np.hypot(*(p - A.start)) <= tol)
    first = ea - ch.edge_pos[ea]  # the loop's edges are consecutive in ch.curves
    for x, y in ((ea, eb), (eb, ea)):
        between = 0.0
        for step in range(1, n):
            k = first + (ch.edge_pos[x] + step) % n
            if k == y:
                if np.hypot(*(p - ch.curves[x].end)) <= tol + between:
                    return True
                break
            between += ch.curves[k].length
            if between > tol:
                break
    return False


def _first_crossing(ch: _Chords, size: float, tol: float) -> tuple[int, int, np.ndarray] | None:
    """The first (edge a, edge b, point) where two loops or one loop cross or touch."""
    touch = TOUCH_TOLERANCE * size
    reach = (touch + ch.deviation)[:, None]  # curved edges may meet where their chords do not
    i, j = _candidate_pairs(np.minimum(ch.a, ch.b) - reach, np.maximum(ch.a, ch.b) + reach)
    keep = ~ch.neighbours(i, j)
    i, j = i[keep], j[keep]
    near = touch + ch.deviation[i] + ch.deviation[j]
    keep = _straddling(ch, i, j, near)
    i, j, near = i[keep], j[keep], near[keep]
    hit, point = _segment_hits(ch.a[i], ch.b[i], ch.a[j], ch.b[j], near)
    fold = _folds(ch, touch)
    for k in np.flatnonzero(hit):
        found = _confirmed(ch, int(i[k]), int(j[k]), point[k], touch + 1e-13 * size, tol)
        if found is not None:
            return int(ch.edge[i[k]]), int(ch.edge[j[k]]), found
    if fold is not None:
        return fold
    return None


def _folds(ch: _Chords, touch: float) -> tuple[int, int, np.ndarray] | None:
    """Two neighbouring chords that run back along each other (a spike of zero width)."""
    nxt = np.arange(len(ch.a)) + 1
    wrap = ch.pos + 1 == ch.chords_in_loop
    nxt[wrap] -= ch.chords_in_loop[wrap]
    u, v = ch.b - ch.a, ch.b[nxt] - ch.a[nxt]
    cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    dot = np.einsum("ij,ij->i", u, v)
    short = np.minimum(np.hypot(u[:, 0], u[:, 1]), np.hypot(v[:, 0], v[:, 1]))
    back = (dot < 0.0) & (np.abs(cross) <= 1e-12 * np.abs(dot)) & (short > touch)
    k = np.flatnonzero(back)
    if k.size == 0:
        return None
    k0 = int(k[0])
    return int(ch.edge[k0]), int(ch.edge[nxt[k0]]), ch.b[k0]


def _inside_polyline(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> bool:
    """Point in a closed polyline of chords [a, b] (crossing number of a ray towards +x)."""
    up = (a[:, 1] <= p[1]) != (b[:, 1] <= p[1])
    if not up.any():
        return False
    a, b = a[up], b[up]
    x = a[:, 0] + (p[1] - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return bool(np.count_nonzero(x > p[0]) % 2)


def _fmt(p: np.ndarray) -> str:
    return "[" + ", ".join(f"{float(x):.6g}" for x in p) + "]"


def _loop_label(li: int) -> str:
    return "outer loop" if li == 0 else f"hole {li - 1}"


def check_loops(loops: Sequence[Sequence[BoundedCurve]], size: float, tolerance: float) -> None:
    """Refuse (ValueError) loops that cross themselves or each other, holes outside the outer
    loop and holes inside other holes. ``loops`` are chained (outer first); ``size`` is the
    profile's size and ``tolerance`` its gap tolerance (a shared vertex may be off by it)."""
    ch = _Chords(loops, size)
    crossing = _first_crossing(ch, size, tolerance)
    if crossing is not None:
        ea, eb, p = crossing
        la, lb = ch.edge_loop[ea], ch.edge_loop[eb]
        na, nb = ch.curves[ea].name, ch.curves[eb].name
        if la == lb:
            raise ValueError(f"{_loop_label(la)} crosses itself (edges {na!r} and {nb!r} at {_fmt(p)})")
        raise ValueError(f"{_loop_label(lb)} crosses {_loop_label(la)} (edges {nb!r} and {na!r} at {_fmt(p)})")
    first = {li: ch.a[np.flatnonzero(ch.loop == li)[0]] for li in range(len(loops))}
    outer = ch.loop == 0
    for li in range(1, len(loops)):
        if not _inside_polyline(first[li], ch.a[outer], ch.b[outer]):
            raise ValueError(f"hole {li - 1} lies outside the outer loop (it starts at {_fmt(first[li])})")
    for li in range(1, len(loops)):
        for lj in range(1, len(loops)):
            m = ch.loop == lj
            if li != lj and _inside_polyline(first[li], ch.a[m], ch.b[m]):
                raise ValueError(f"hole {li - 1} lies inside hole {lj - 1} (it starts at {_fmt(first[li])})")
