"""Closed 2D profiles: an outer loop and holes, each a chain of bounded curves, with the
exact signed distance phi (positive inside: the thesis's level set), an inside test, the
closest boundary point and the outward normal.

Sign of phi: the distance is the minimum over all edges of the distance to the trimmed
curve (exact). The sign comes from the nearest point c: where c is interior to an edge,
sign((p - c) . n) (p - c is along the normal there); where c is a vertex (or within a
round-off distance of one) the sign of (p - c) . (n_in + n_out) with the unit normals of
the two edges meeting there (the 2D angle-weighted pseudo-normal of Baerentzen and Aanaes,
2005). If c is the nearest boundary point to p then p - c lies in the cone bounded by the
two normals, and that cone is on the material side exactly when the pseudo-normal points
into the material, so the sign is right at convex and reflex corners alike, for curved
edges too. Points on the boundary get phi = 0 (to round-off) and count as inside.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from typing import Any, Iterable, Sequence

import numpy as np

from ._base import real_array
from .bounded_curve import BoundedCurve
from .bspline_arc import BSplineArc
from .loop_checks import check_loops
from .segments import Segment, SegmentBatch

__all__ = ["Profile", "ProfileProjection", "UnknownEdgeError"]


class UnknownEdgeError(KeyError, ValueError):
    """An edge name the profile does not have (both a KeyError and a ValueError)."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""


@dataclass(frozen=True, eq=False)
class ProfileProjection:
    """Closest boundary points (n, 2), outward unit normals there (n, 2), the signed
    distance ``phi`` (n,) (positive inside), the index of the nearest edge into
    ``Profile.edge_names`` (n,) and that edge's parameter at the closest point (n,)."""

    points: np.ndarray
    normals: np.ndarray
    phi: np.ndarray
    edge_index: np.ndarray
    parameters: np.ndarray


def _query_points(points: Any, infinite: bool) -> np.ndarray:
    """Query points as a float (n, 2) array of real numbers; no NaN, and no infinity unless
    ``infinite``. A 1-D array is refused (it would be ambiguous: one point or n values)."""
    P = real_array(points, "points")
    if P.ndim != 2 or P.shape[1] != 2:
        raise ValueError(f"points must be an (n, 2) array (a single point is [[x, y]]), got shape {P.shape}")
    # the flat test first: a reduction along the rows of an (n, 2) array is some 30 times slower
    if not (np.isnan(P).any() if infinite else not np.isfinite(P).all()):
        return P
    bad = np.isnan(P).any(axis=1) if infinite else ~np.isfinite(P).all(axis=1)
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        what = "NaN" if infinite else "NaN or infinite"
        raise ValueError(f"points must not be {what}: points[{k}] = {P[k].tolist()}")
    return P


def _as_loop(loop: Any) -> list[BoundedCurve]:
    if isinstance(loop, BoundedCurve):
        return [loop]
    curves = list(loop)
    for c in curves:
        if not isinstance(c, BoundedCurve):
            raise ValueError(f"profile loops must hold bounded curves, got {type(c).__name__}")
    if not curves:
        raise ValueError("profile loop is empty")
    return curves


def _chain(curves: list[BoundedCurve], tol: float, label: str) -> list[BoundedCurve]:
    """Reverse curves as needed so that each ends where the next begins (order kept)."""
    n = len(curves)
    if n == 1:
        c = curves[0]
        gap = float(np.linalg.norm(c.end - c.start))
        if gap > tol:
            raise ValueError(f"{label}: the single edge {c.name!r} is not closed (gap {gap:.3g})")
        return [c]

    def close(a, b):
        return float(np.linalg.norm(a - b)) <= tol

    first, second = curves[0], curves[1]
    # orient the first edge so that its end meets the second edge (either end)
    if close(first.end, second.start) or close(first.end, second.end):
        out = [first]
    elif close(first.start, second.start) or close(first.start, second.end):
        out = [first.reversed()]
    else:
        raise ValueError(
            f"{label}: edges {first.name!r} and {second.name!r} do not meet "
            f"(ends {first.start.tolist()}, {first.end.tolist()} and {second.start.tolist()}, {second.end.tolist()})"
        )
    for c in curves[1:]:
        here = out[-1].end
        if close(c.start, here):
            out.append(c)
        elif close(c.end, here):
            out.append(c.reversed())
        else:
            raise ValueError(
                f"{label}: edge {c.name!r} does not start or end where {out[-1].name!r} ends "
                f"({here.tolist()}); its ends are {c.start.tolist()} and {c.end.tolist()}"
            )
    gap = float(np.linalg.norm(out[-1].end - out[0].start))
    if gap > tol:
        raise ValueError(
            f"{label}: the loop is not closed: {out[-1].name!r} ends at {out[-1].end.tolist()}, "
            f"{out[0].name!r} starts at {out[0].start.tolist()} (gap {gap:.3g})"
        )
    return out


def _reorder(curves: list[BoundedCurve], tol: float) -> list[BoundedCurve] | None:
    """The curves in chain order (greedy walk from the first curve matching end points), or
    None when they do not form one closed chain."""
    rest = list(curves[1:])
    out = [curves[0]]
    here = curves[0].end
    while rest:
        for i, c in enumerate(rest):
            if np.linalg.norm(c.start - here) <= tol:
                out.append(c)
                here = c.end
                break
            if np.linalg.norm(c.end - here) <= tol:
                out.append(c.reversed())
                here = c.start
                break
        else:
            return None
        rest.pop(i)
    return out


def _edge_names(raw: list[list[BoundedCurve]]) -> list[str]:
    """Edge names in the order given (unnamed curves get e<k>, k their position); curves
    renamed in place in ``raw``. Names must be unique."""
    names = [c.name for lp in raw for c in lp]
    used = {n for n in names if n}
    for k, nm in enumerate(names):
        if not nm:
            j = k
            while f"e{j}" in used:
                j += 1
            names[k] = f"e{j}"
            used.add(names[k])
    dup = sorted(n for n, count in Counter(names).items() if count > 1)
    if dup:
        raise ValueError(f"profile edge names must be unique; repeated: {', '.join(dup)}")
    k = 0
    for lp in raw:
        for j, c in enumerate(lp):
            if c.name != names[k]:
                lp[j] = c.renamed(names[k])
            k += 1
    return names


def _chained(curves: list[BoundedCurve], tol: float, label: str) -> list[BoundedCurve]:
    """The loop's curves chained end to start, in the order given or, where that does not
    chain, in the order found by walking from the first curve."""
    try:
        return _chain(curves, tol, label)
    except ValueError:
        ordered = _reorder(curves, tol)
        if ordered is None:
            raise
        return _chain(ordered, tol, label)


def _oriented(chained: list[BoundedCurve], ccw: bool, label: str) -> tuple[BoundedCurve, ...]:
    """The chained loop turned counter-clockwise (``ccw``) or clockwise."""
    area = _loop_area(chained)
    if area == 0.0:
        raise ValueError(f"{label} encloses no area")
    if (area > 0.0) != ccw:
        chained = [c.reversed() for c in reversed(chained)]
    return tuple(chained)


def _loop_area(curves: Sequence[BoundedCurve]) -> float:
    return float(sum(c.area_integral() for c in curves))


class Profile:
    """A closed 2D region: ``loops[0]`` is the outer boundary, the others are holes.

    The constructor takes each loop as a sequence of bounded curves listed in order, each in
    either direction; it reverses curves so they chain end to start (gaps up to
    ``tolerance``, default 1e-6 of the profile's size; curves listed out of order are
    put in order when the listed order does not chain), then orients the outer loop
    counter-clockwise and holes clockwise, so every curve's ``normal`` points out of the
    material. Edge names stay with their curves and must be unique. The loops must not
    cross or touch themselves or each other, holes must lie inside the outer loop and not
    inside each other (:func:`geometry.loop_checks.check_loops`; docs/geometry.md).
    """

    def __init__(self, loops: Iterable[Any], tolerance: float | None = None) -> None:
        raw = [_as_loop(lp) for lp in loops]
        if not raw:
            raise ValueError("a profile needs at least one loop")
        samples = np.concatenate([np.vstack([c.start, c.end, c.evaluate(np.linspace(c.t_start, c.t_end, 5))]) for lp in raw for c in lp])
        size = float(np.linalg.norm(np.ptp(samples, axis=0)))
        if not size > 0.0:
            raise ValueError("profile has zero size")
        tol = 1e-6 * size if tolerance is None else float(tolerance)
        self.size = size
        self.tolerance = tol

        names = _edge_names(raw)
        chained = [_chained(lp, tol, "outer loop" if i == 0 else f"hole {i - 1}") for i, lp in enumerate(raw)]
        check_loops(chained, size, tol)
        #: the oriented curves of each loop in chain order (outer CCW first, then holes CW)
        self.loops: tuple[tuple[BoundedCurve, ...], ...] = tuple(
            _oriented(lp, i == 0, "outer loop" if i == 0 else f"hole {i - 1}") for i, lp in enumerate(chained)
        )
        # edges in the order given; topology from the chains
        oriented = {c.name: c for lp in self.loops for c in lp}
        edges = [oriented[nm] for nm in names]
        self.edge_names: tuple[str, ...] = tuple(names)
        self.edges: dict[str, BoundedCurve] = dict(zip(names, edges))
        self._edge_list = edges
        self._set_topology()
        self._set_boxes()

    def _set_topology(self) -> None:
        """Previous / next edge and loop of every edge, parameter ranges, end normals."""
        edges = self._edge_list
        index = {nm: k for k, nm in enumerate(self.edge_names)}
        n_edges = len(edges)
        prev = np.zeros(n_edges, dtype=np.intp)
        nxt = np.zeros(n_edges, dtype=np.intp)
        loop_of = np.zeros(n_edges, dtype=np.intp)
        for li, lp in enumerate(self.loops):
            m = len(lp)
            for j, c in enumerate(lp):
                k = index[c.name]
                prev[k] = index[lp[(j - 1) % m].name]
                nxt[k] = index[lp[(j + 1) % m].name]
                loop_of[k] = li
        self._prev = prev
        self._next = nxt
        #: loop index of every edge (0 = outer)
        self.edge_loop = loop_of
        self._t_start = np.array([c.t_start for c in edges])
        self._t_end = np.array([c.t_end for c in edges])
        # a foot within 1e-9 of an edge's parameter range from its end is at that vertex
        eps = 1e-9 * (self._t_end - self._t_start)
        self._start_to, self._end_from = self._t_start + eps, self._t_end - eps
        self._n_start = np.vstack([c.normal(c.t_start) for c in edges])
        self._n_end = np.vstack([c.normal(c.t_end) for c in edges])
        self._p_start = np.vstack([c.start for c in edges])
        self._p_end = np.vstack([c.end for c in edges])

    def _set_boxes(self) -> None:
        """Tight boxes (ends and axis-extreme points) and culling boxes for ``_nearest``."""
        edges = self._edge_list
        boxes = [_curve_box(c) for c in edges]
        self._box_lo = np.array([b[0] for b in boxes])
        self._box_hi = np.array([b[1] for b in boxes])
        self._bounds = self._box_lo.min(axis=0), self._box_hi.max(axis=0)
        self._centre = tuple(float(c) for c in 0.5 * (self._bounds[0] + self._bounds[1]))
        # points within these (x min, y min, x max, y max) are inside the bounds' margin in _phi
        near = 1e-9 * self.size
        self._fuzz_box = (float(self._bounds[0][0] - near), float(self._bounds[0][1] - near),
                          float(self._bounds[1][0] + near), float(self._bounds[1][1] + near))
        # culling boxes must contain the curve for sure: B-splines use their control points
        # (convex hull property, positive weights); a small margin covers round-off
        cull = [(c.control_points.min(axis=0), c.control_points.max(axis=0)) if isinstance(c, BSplineArc) else b for c, b in zip(edges, boxes)]
        margin = 1e-12 * self.size
        self._cull_lo = np.array([b[0] for b in cull]) - margin
        self._cull_hi = np.array([b[1] for b in cull]) + margin
        self._expensive = np.array([getattr(c, "cost", 1) > 1 for c in edges])
        self._order = sorted(range(len(edges)), key=lambda k: getattr(edges[k], "cost", 1))
        # the straight edges' distances in one pass (two or more: one set of array operations)
        straight = [k for k in self._order if type(edges[k]) is Segment]
        self._segment_batch = SegmentBatch([edges[k] for k in straight]) if len(straight) > 1 else None
        self._segment_row = {k: i for i, k in enumerate(straight)} if self._segment_batch else {}

    def _cheap_distances(self, P: np.ndarray):
        """Edge k -> (signed distance, foot parameter) at the points P of every straight edge
        (:class:`SegmentBatch`), the others' on request: the function of k."""
        if self._segment_batch is None:
            return lambda k: self._edge_list[k]._nearest_signed(P)
        sd, t = self._segment_batch.nearest_signed(P)
        rows = self._segment_row

        def distances(k: int):
            i = rows.get(k)
            return (sd[i], t[i]) if i is not None else self._edge_list[k]._nearest_signed(P)

        return distances

    # -- naming ----------------------------------------------------------------------------

    def edge(self, name: str) -> BoundedCurve:
        try:
            return self.edges[name]
        except KeyError:
            raise UnknownEdgeError(f"no edge named {name!r}; the profile's edges are: {', '.join(self.edge_names)}") from None

    def edge_index(self, name: str) -> int:
        self.edge(name)
        return self.edge_names.index(name)

    # -- size ------------------------------------------------------------------------------

    @property
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """(min (2,), max (2,)) of the exact boundary: ends and axis-extreme points."""
        return self._bounds[0].copy(), self._bounds[1].copy()

    @property
    def area(self) -> float:
        """Area of the material (outer minus holes), by exact-geometry quadrature."""
        return float(sum(_loop_area(lp) for lp in self.loops))

    # -- distance ----------------------------------------------------------------------------

    def _nearest(self, P: np.ndarray):
        """Per point: distance to the boundary, nearest edge, its parameter, and the signed
        (positive outside) distance to that edge. Cheap edges (segments, arcs) go first; an
        expensive edge (elliptic arc, B-spline) is projected only for the points whose
        distance to its bounding box is below the best distance so far."""
        n = len(P)
        first, *rest = self._order
        cheap = self._cheap_distances(P)
        # the first edge is the nearest so far wherever its distance is finite
        sd, tpar = cheap(first)  # new arrays: written in place below
        best = np.abs(sd)
        edge = np.full(n, first, dtype=np.intp)
        lost = ~(best < np.inf)
        if lost.any():
            best[lost], edge[lost], tpar[lost], sd[lost] = np.inf, 0, 0.0, 0.0
        x, y = P[:, 0], P[:, 1]
        for k in rest:
            curve = self._edge_list[k]
            if self._expensive[k]:
                lo, hi = self._cull_lo[k], self._cull_hi[k]
                gx = np.maximum(np.maximum(lo[0] - x, x - hi[0]), 0.0)
                gy = np.maximum(np.maximum(lo[1] - y, y - hi[1]), 0.0)
                idx = np.flatnonzero(np.hypot(gx, gy) < best)
                if idx.size == 0:
                    continue
                dist_k, t_k = curve._nearest_signed(P[idx], best[idx])
                d = np.abs(dist_k)
                better = d < best[idx]
                j = idx[better]
                best[j] = d[better]
                edge[j] = k
                tpar[j] = t_k[better]
                sd[j] = dist_k[better]
            else:
                dist_k, t_k = cheap(k)
                d = np.abs(dist_k)
                better = d < best
                np.copyto(best, d, where=better)
                np.copyto(tpar, t_k, where=better)
                np.copyto(sd, dist_k, where=better)
                np.copyto(edge, k, where=better)
        return best, edge, tpar, sd

    def _neighbour_sign(self, P: np.ndarray, best: np.ndarray, other: np.ndarray, sign: np.ndarray) -> np.ndarray:
        """Signs (positive outside) of points whose nearest foot is a vertex: where the other
        edge at that vertex has its own foot inside it, as near (to round-off), that edge owns
        the point and its sign holds. (An end curving sharply, a very flat ellipse's tip, turns
        its normal within round-off of the vertex, where the pseudo-normal of the end normals
        misjudges points off the tip.)"""
        out = sign.copy()
        for k in np.unique(other):
            sel = np.flatnonzero(other == k)
            d_k, t_k = self._edge_list[k]._nearest_signed(P[sel])
            ts, te = self._t_start[k], self._t_end[k]
            eps = 1e-9 * (te - ts)
            owns = (t_k > ts + eps) & (t_k < te - eps) & (np.abs(d_k) <= best[sel] * (1.0 + 1e-9) + 1e-300)
            out[sel[owns]] = np.where(d_k[owns] < 0.0, -1.0, 1.0)
        return out

    def _evaluate_edges(self, edge: np.ndarray, t: np.ndarray, normals: bool = False):
        """Points (and normals) of the edges ``edge`` at parameters ``t`` (one pass per edge)."""
        c = np.empty((len(t), 2))
        nrm = np.empty((len(t), 2)) if normals else None
        for k, curve in enumerate(self._edge_list):
            m = edge == k
            if np.any(m):
                c[m] = curve.evaluate(t[m])
                if normals:
                    nrm[m] = curve.normal(t[m])
        return c, nrm

    def _phi(self, P: np.ndarray, want_points: bool, box: tuple[float, float, float, float] | None = None):
        """phi (positive inside), nearest edge, its parameter, and (``want_points``) the feet and
        normals at the points P (n, 2); ``box``: P's (x min, y min, x max, y max) when known."""
        best, edge, tpar, sd = self._nearest(P)
        # sign: interior feet keep sign((p - c).n); feet at (or within round-off of) a vertex
        # use the pseudo-normal n_in + n_out of the two edges meeting there
        at_end = tpar >= self._end_from[edge]
        at_start = (tpar <= self._start_to[edge]) & ~at_end
        phi = np.where(sd < 0.0, best, -best)  # positive inside; the vertices' signs below
        c = nrm = None
        if want_points:
            c, nrm = self._evaluate_edges(edge, tpar, normals=True)
        vtx = (at_end | at_start).nonzero()[0]
        if vtx.size:
            e = edge[vtx]
            ae = at_end[vtx]
            pseudo = np.where(
                ae[:, None],
                self._n_end[e] + self._n_start[self._next[e]],
                self._n_start[e] + self._n_end[self._prev[e]],
            )
            cv = c[vtx] if c is not None else self._evaluate_edges(e, tpar[vtx])[0]
            # (p - c), not (p - vertex): where c is interior but within round-off of the
            # vertex, p - c is along that edge's normal n1 and (p - c).(n1 + n2) keeps its sign
            s = np.einsum("ij,ij->i", P[vtx] - cv, pseudo)
            usable = (np.hypot(pseudo[:, 0], pseudo[:, 1]) > 1e-6) & (s != 0.0)
            sign = np.where(sd[vtx] < 0.0, -1.0, 1.0)
            sign = np.where(usable, np.sign(s), sign)
            sign = self._neighbour_sign(P[vtx], best[vtx], np.where(ae, self._next[e], self._prev[e]), sign)
            phi[vtx] = -sign * best[vtx]
        # outside the bounding box is outside whatever the nearest feature's normals say (a loop
        # that folds back on itself within the crossing check's tolerance, e.g. a spike 1e-7 wide,
        # gave far points the inside sign: make fuzz)
        fuzz = self._fuzz_box
        if box is None or box[0] < fuzz[0] or box[1] < fuzz[1] or box[2] > fuzz[2] or box[3] > fuzz[3]:
            beyond = self._beyond(P, box)
            phi = np.where(beyond, -best, phi)
        return phi, edge, tpar, c, nrm

    def _beyond(self, P: np.ndarray, box: tuple[float, float, float, float] | None) -> np.ndarray:
        """(n,) bool: points P (n, 2) outside the bounds by more than 1e-9 of the size, column by
        column and only on the sides ``box`` (P's x min, y min, x max, y max) crosses (a
        reduction along the rows of an (n, 2) array is several times slower)."""
        lo, hi = self._bounds
        margin = 1e-9 * self.size
        sides = [(k, lo[k] - margin, hi[k] + margin) for k in range(2)]
        beyond = np.zeros(len(P), dtype=bool)
        for k, low, high in sides:
            column = P[:, k]
            if box is None or box[k] < low:
                beyond |= column < low
            if box is None or box[k + 2] > high:
                beyond |= column > high
        return beyond

    def project(self, points: Any) -> ProfileProjection:
        """Closest boundary points, outward normals, phi (positive inside), nearest edge.
        ``points`` is an (n, 2) array of finite numbers."""
        P = _query_points(points, infinite=False)
        _, P_near, shift = self._pull_in(P)
        phi, edge, tpar, c, nrm = self._phi(P_near, want_points=True)
        phi = phi - shift
        return ProfileProjection(points=c, normals=nrm, phi=phi, edge_index=edge, parameters=tpar)

    def signed_distance(self, points: Any) -> np.ndarray:
        """phi (n,): distance to the boundary, positive inside, negative outside.

        ``points`` is an (n, 2) array (a single point is ``[[x, y]]``). A point with an
        infinite coordinate is infinitely far outside: phi = -inf; NaN is refused
        (ValueError). Points farther than 1e8 profile sizes are measured along their ray
        from the profile's centre (exact to round-off there), so squares never overflow."""
        P = _query_points(points, infinite=True)
        if len(P):
            x, y = P[:, 0], P[:, 1]  # column by column: P.min(axis=0) takes 20 times longer
            box = float(x.min()), float(y.min()), float(x.max()), float(y.max())
            if self._near_finite(box):  # every point finite and none far: the common case, in one pass
                return self._phi(P, want_points=False, box=box)[0]
        inf = ~np.isfinite(P).all(axis=1)
        phi = np.full(len(P), -np.inf)
        if not inf.all():
            Q = P[~inf]
            _, Q_near, shift = self._pull_in(Q)
            phi[~inf] = self._phi(Q_near, want_points=False)[0] - shift
        return phi

    def contains(self, points: Any, tolerance: float | None = None) -> np.ndarray:
        """Inside test (n,) bool: phi >= -tolerance, the boundary included. The default
        tolerance, 1e-12 of the profile's size, covers the round-off of phi on curved edges,
        so points on any edge or at a corner are inside. Points as for :meth:`signed_distance`."""
        tol = 1e-12 * self.size if tolerance is None else float(tolerance)
        return self.signed_distance(points) >= -tol

    def _near_finite(self, box: tuple[float, float, float, float]) -> bool:
        """Whether points within ``box`` (x min, y min, x max, y max; no NaN among them) are all
        finite and nearer the profile's box centre than :meth:`_pull_in`'s radius R (then it
        moves none)."""
        cx, cy = self._centre
        reach = max(abs(box[0] - cx), abs(box[2] - cx), abs(box[1] - cy), abs(box[3] - cy))
        return 2.0 * reach <= 1e8 * self.size  # hypot(dx, dy) <= sqrt(2) max(|dx|, |dy|)

    def _pull_in(self, P: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Points farther than R = 1e8 sizes from the box centre moved along their ray to
        distance R: (which were moved, the points, how far each was moved). Beyond R the
        distance to the boundary grows with the distance from the centre to round-off
        (the error is about size^2 / R)."""
        lo, hi = self._bounds
        centre = 0.5 * (lo + hi)
        R = 1e8 * self.size
        d = P - centre
        with np.errstate(over="ignore"):  # beyond the largest float: r = inf, phi = -inf
            r = np.hypot(d[:, 0], d[:, 1])
        far = r > R
        shift = np.zeros(len(P))
        if far.any():
            P = P.copy()
            P[far] = centre + d[far] * (R / r[far])[:, None]
            shift[far] = r[far] - R
        return far, P, shift

    # -- tessellation and transforms -----------------------------------------------------------

    def tessellate(self, chord_tolerance: float) -> list[tuple[np.ndarray, np.ndarray]]:
        """Per loop: (points (m, 2), edge_index (m - 1,)); the polyline is closed (the last
        point repeats the first) and segment j lies on edge edge_index[j]."""
        out = []
        index = {nm: k for k, nm in enumerate(self.edge_names)}
        for lp in self.loops:
            pts, idx = [], []
            for cur in lp:
                X, _ = cur.tessellate(chord_tolerance)
                X = X.copy()
                X[0] = cur.start
                pts.append(X[:-1])
                idx.append(np.full(len(X) - 1, index[cur.name]))
            P = np.vstack(pts + [pts[0][:1]])
            out.append((P, np.concatenate(idx)))
        return out

    def transformed(self, rotate_deg: float = 0.0, pivot: Any = (0.0, 0.0), translate: Any = (0.0, 0.0)) -> "Profile":
        """The profile rotated by ``rotate_deg`` about ``pivot`` and then translated."""
        loops = [[c.transformed(rotate_deg, pivot, translate) for c in lp] for lp in self._given_loops()]
        return Profile(loops, tolerance=self.tolerance)

    def _given_loops(self) -> list[list[BoundedCurve]]:
        """Each loop's (oriented) edges in the order of ``edge_names``."""
        return [[self._edge_list[k] for k in np.flatnonzero(self.edge_loop == li)] for li in range(len(self.loops))]

    def to_dict(self) -> dict[str, Any]:
        """The ``profile`` scene shape dict (edges and holes)."""
        given = self._given_loops()
        d: dict[str, Any] = {"type": "profile", "edges": [c.to_dict() for c in given[0]]}
        if len(given) > 1:
            d["holes"] = [[c.to_dict() for c in lp] for lp in given[1:]]
        return d

    def __repr__(self) -> str:
        return f"Profile(edges={list(self.edge_names)}, loops={len(self.loops)})"


def _curve_box(curve: BoundedCurve) -> tuple[np.ndarray, np.ndarray]:
    pts = [curve.start[None, :], curve.end[None, :]]
    for axis in (0, 1):
        # extremes of coordinate `axis`: where the derivative component vanishes
        t = _derivative_roots(curve, axis)
        if t.size:
            pts.append(curve.evaluate(t))
    P = np.vstack(pts)
    return P.min(axis=0), P.max(axis=0)


def _derivative_roots(curve: BoundedCurve, axis: int) -> np.ndarray:
    """Parameters where d(coordinate axis)/dt = 0 (axis-extreme points of the curve)."""
    from ._curve_numerics import _roots_on_grid
    from .segments import Segment

    if isinstance(curve, Segment):
        return np.empty(0)
    grid = curve._sample_grid() if hasattr(curve, "_sample_grid") else np.linspace(curve.t_start, curve.t_end, 65)
    grid = np.unique(np.concatenate([grid, np.linspace(curve.t_start, curve.t_end, 65)]))
    return _roots_on_grid(lambda t: curve.derivative(t)[:, axis], grid)

