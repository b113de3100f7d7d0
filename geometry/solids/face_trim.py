"""Whether a point of a CAD face's untrimmed surface lies on the trimmed face, by the face's
exact trimming edges.

A face's triangles only say so within their chord sag: a foot just beyond a curved trimming edge
(beside a quarter model's symmetry plane, outside a ball's rim) still lies within that band of
the triangles. Here a foot within the band of some trimming edge is judged against the edges'
exact curves instead: the nearest point e of the trimming edges (the curve's foot, clipped to the
edge's ends) and the face's inward direction there, m = N x T (N the face's outward normal, T the
edge's tangent, the sign fixed once per edge by the side the face's own triangles lie on). The
foot f is on the face when (f - e) . m >= 0. Where e is a vertex shared by two edges, m is the
sum of both edges' inward directions there (the pseudo-normal of a corner: Baerentzen and
Aanaes, IEEE TVCG 11 (2005) 243, in two dimensions), which decides convex and reflex corners
alike. A seam (an edge a periodic face meets twice) bounds nothing and is left out; an edge
without an exact curve is taken as its polyline.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np

from .mesh_jit import box_gaps, mesh_kernels
from .trim_strips import boundary_chords

__all__ = ["FaceTrim", "TrimEdge"]

#: feet within this many tolerances of an edge's box are judged by the exact edges
BAND = 3.0


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.maximum(np.linalg.norm(v, axis=1), 1e-300)[:, None]


def _nearest_on_polyline(p: np.ndarray, line: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Nearest points (n, 3) of the polyline, their distances and the direction (n, 3) of the
    segment they lie on (from the polyline's first point towards its last)."""
    kernels = mesh_kernels()
    if kernels is not None and len(line) >= 2:  # compiled: the same steps without a pass per segment
        p, line = np.ascontiguousarray(p, float), np.ascontiguousarray(line, float)
        foot, best, seg = np.zeros_like(p), np.full(len(p), np.inf), np.zeros(len(p), np.int64)
        kernels.nearest_on_polyline(p, line, foot, best, seg)
        return foot, best, _unit((line[1:] - line[:-1])[seg])
    best = np.full(len(p), np.inf)
    foot, direction = np.zeros_like(p), np.zeros_like(p)
    for u, v in zip(line[:-1], line[1:]):
        e = v - u
        t = np.clip(((p - u) @ e) / max(float(e @ e), 1e-300), 0.0, 1.0)
        x = u + t[:, None] * e
        d = np.linalg.norm(p - x, axis=1)
        better = d < best
        best[better], foot[better], direction[better] = d[better], x[better], e
    return foot, best, _unit(direction)


#: a trimming edge's polyline is sampled at most this many times for :meth:`TrimEdge.lower_bound`
#: (the samples at most the tolerance apart, or the polyline's length over this)
BOUND_SAMPLES = 4096


class TrimEdge:
    """One trimming edge of a face: its exact curve (or polyline), ends and box."""

    def __init__(self, edge, tol: float):
        self.id, self.curve = edge.id, edge.curve
        self.line = np.asarray(edge.polyline, float).reshape(-1, 3)
        ends = [np.asarray(v, float) for v in (edge.start, edge.end) if v is not None]
        self.ends = ends if len(ends) == 2 else [self.line[0], self.line[-1]]
        self.closed = float(np.linalg.norm(self.ends[0] - self.ends[1])) <= tol
        self.lo, self.hi = self.line.min(axis=0) - tol, self.line.max(axis=0) + tol
        self.tol = tol

    @cached_property
    def _samples(self):
        """A k-d tree of points along the polyline (its vertices and points between them at most
        ``spacing`` apart) and how far the edge may lie from the nearest of them: half the
        spacing, plus the tolerance (the exact edge lies within it of its polyline, as it lies in
        the polyline's box widened by it), plus round-off."""
        from scipy.spatial import cKDTree

        seg = self.line[1:] - self.line[:-1]
        length = np.linalg.norm(seg, axis=1)
        spacing = max(self.tol, float(length.sum()) / BOUND_SAMPLES, 1e-300)
        pieces = np.maximum(np.ceil(length / spacing).astype(np.int64), 1)
        owner = np.repeat(np.arange(len(seg)), pieces)
        t = (np.arange(len(owner)) - np.repeat(np.cumsum(pieces) - pieces, pieces)) / np.repeat(pieces, pieces)
        points = np.concatenate([self.line[owner] + t[:, None] * seg[owner], self.line[-1:]]) if len(seg) else self.line
        scale = float(np.abs(self.line).max(initial=0.0)) + float(length.sum())
        reach = (0.5 * spacing + self.tol) * (1.0 + 1e-9) + 1e-12 * scale
        return cKDTree(points), reach

    def lower_bound(self, p: np.ndarray, upper: float = np.inf) -> np.ndarray:
        """Distances (n,) from points p (n, 3) to the edge from below (its polyline's samples'
        nearest less how far the edge may lie from them); inf where above ``upper``."""
        tree, reach = self._samples
        d, _ = tree.query(np.asarray(p, float).reshape(-1, 3), distance_upper_bound=upper + reach)
        return np.maximum(d - reach, 0.0)

    def foot(self, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The nearest points (n, 3) of the edge and its unit tangents there (n, 3), running
        from the polyline's first point to its last."""
        e, t0 = self.clipped(p)
        return e, self.tangent(e, t0)

    def clipped(self, p: np.ndarray, feet: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The nearest points (n, 3) of the edge: the curve's foot where it lies on the edge
        (within the tolerance of its polyline and not past an end), else the nearer end; and the
        direction of the polyline's segment nearest to each of those points. ``feet``: the
        curve's feet of p when already projected."""
        if self.curve is None:
            near, _, t0 = _nearest_on_polyline(p, self.line)
            return near, t0
        e = np.array(self.curve.project(p).points if feet is None else feet, dtype=float)
        _, off, t0 = _nearest_on_polyline(e, self.line)
        out = off > self.tol
        if not self.closed:  # a foot past an end (on the curve carried on) is that end
            for v, w in ((self.ends[0], self.line[1] if len(self.line) > 1 else self.ends[1]),
                         (self.ends[1], self.line[-2] if len(self.line) > 1 else self.ends[0])):
                step = w - v
                r = e - v
                out |= ((r @ step) < 0.0) & ((r * r).sum(axis=1) < float(step @ step))
        if out.any():
            ends = np.stack(self.ends)
            k = np.argmin(np.linalg.norm(p[out, None, :] - ends[None], axis=2), axis=1)
            e[out] = ends[k]
            t0[out] = _nearest_on_polyline(e[out], self.line)[2]
        return e, t0

    def tangent(self, e: np.ndarray, t0: np.ndarray) -> np.ndarray:
        """The curve's unit tangent at its points e, signed as the polyline's directions t0:
        the difference of the curve's feet of e +- h t0 (exact to O(h^2))."""
        if self.curve is None:
            return t0
        h = 1e-4 * max(float(np.linalg.norm(self.hi - self.lo)), 1e-12)
        a = np.asarray(self.curve.project(e + h * t0).points, float)
        b = np.asarray(self.curve.project(e - h * t0).points, float)
        t = _unit(a - b)
        return np.where(((t * t0).sum(axis=1) < 0.0)[:, None], -t, t)


class FaceTrim:
    """The trimmed region of a face with an exact surface (``face``: a PartFace) bounded by its
    trimming ``edges`` (those of its loops, a seam listed twice); ``tol``: how far the
    tessellation strays from the exact faces; ``size``: the part's size (round-off scale)."""

    def __init__(self, face, edges, tol: float, size: float):
        self.face, self.tol, self.size = face, tol, size
        ids = [e.id for e in edges]
        self.edges = [TrimEdge(e, tol) for k, e in enumerate(edges)
                      if ids.count(e.id) == 1 and len(np.asarray(e.polyline).reshape(-1, 3)) >= 2]

    @cached_property
    def _boxes(self) -> tuple[np.ndarray, np.ndarray]:
        """The trimming edges' boxes: lower and upper corners (edges, 3)."""
        return (np.array([e.lo for e in self.edges]).reshape(-1, 3), np.array([e.hi for e in self.edges]).reshape(-1, 3))

    @cached_property
    def _sides(self) -> list[float]:
        """+1 where the face lies on the side N x T of an edge (T along its polyline), -1 where
        on the other, 0 where its triangles do not reach the edge: the side the triangles along
        the edge lie on (a triangle wound outward has its inside to the left of its edges seen
        from outside: n x (v - u) for its edge u -> v)."""
        u, v, n = boundary_chords(self.face.triangles)
        if not len(u):
            return [0.0] * len(self.edges)
        mid, inward = 0.5 * (u + v), _unit(np.cross(n, v - u))
        from scipy.spatial import cKDTree

        tree = cKDTree(mid)
        sides = []
        for edge in self.edges:
            q = 0.5 * (edge.line[1:] + edge.line[:-1])
            e, t = edge.foot(q)
            w = _unit(np.cross(self.face.project_surface(e)[1], t))
            reach = np.linalg.norm(edge.line[1:] - edge.line[:-1], axis=1) + 2.0 * self.tol
            d, k = tree.query(e)
            vote = np.where(d <= reach, (inward[k] * w).sum(axis=1), 0.0)
            sides.append(float(np.sign(vote.sum())))
        return sides

    def contains(self, feet: np.ndarray) -> np.ndarray:
        """Whether each foot (n, 3) on the face's untrimmed surface lies on the trimmed face."""
        feet = np.asarray(feet, float).reshape(-1, 3)
        on = self.face.mesh.within(feet, self.tol)
        idx = np.flatnonzero(on)
        if not len(idx) or not self.edges:
            return on
        q = feet[idx]
        best = np.full(len(q), np.inf)
        at, inward = np.full_like(q, np.inf), np.zeros_like(q)
        same = 1e-7 * self.size  # two edges' feet this close are their shared vertex
        band = BAND * self.tol
        gaps = box_gaps(q, self._boxes[0], self._boxes[1])  # (edges, n)
        for k, (edge, side) in enumerate(zip(self.edges, self._sides)):
            if side == 0.0:
                continue
            gap = gaps[k]
            sel = np.flatnonzero((gap < band) & (gap <= best + same))
            if len(sel):  # the box's gap, then the samples' bound: the edge is at least that far
                gap = edge.lower_bound(q[sel], band)
                sel = sel[(gap < band) & (gap <= best[sel] + same)]
            if not len(sel):
                continue
            e, t = edge.foot(q[sel])
            m = side * _unit(np.cross(self.face.project_surface(e)[1], t))
            d = np.linalg.norm(q[sel] - e, axis=1)
            tie = np.linalg.norm(e - at[sel], axis=1) <= same  # the same point: a shared vertex
            closer = (d < best[sel]) & ~tie
            i, j = sel[closer], sel[tie]
            best[i], at[i], inward[i] = d[closer], e[closer], m[closer]
            inward[j] += m[tie]
        judged = best <= band
        on[idx[judged]] = ((q[judged] - at[judged]) * inward[judged]).sum(axis=1) >= -same
        return on
