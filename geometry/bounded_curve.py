"""Bounded (trimmed) 2D curves: the edges of a :class:`geometry.profile.Profile`.

Every curve is an immutable, oriented piece of curve in the plane with a native parameter
``t`` that increases along the curve from ``t_start`` to ``t_end``:

- :class:`Segment`: ``t`` is the arc length, ``t`` in [0, length];
- :class:`Arc` and :class:`EllipticArc`: ``t`` is the angle swept from the start point,
  ``t`` in [0, |end_angle - start_angle|] (so a clockwise arc still has increasing ``t``);
- :class:`BSplineArc`: ``t`` is the spline parameter on [knots[p], knots[-p-1]].

The normal is the tangent turned by -90 degrees (the right-hand side): the outward normal
when the curve belongs to a counter-clockwise outer loop.

Projection is onto the *trimmed* curve, end points included. ``distances`` in the returned
:class:`BoundedProjection` are signed Euclidean distances ``sign((p - c) . n) * |p - c|``;
they equal ``(p - c) . n`` wherever the closest point ``c`` is interior to the curve.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from ._base import Projection
from .chord_walk import first_crossing, walk_distances
from ._curve_numerics import (
    _axis,
    _bisect,
    _dedupe_sorted,
    _gauss_legendre,
    _params,
    _rot90cw,
    _signed_euclidean,
    _unit,
    _vec2,
)


__all__ = ["BoundedProjection", "BoundedCurve"]


@dataclass(frozen=True, eq=False)
class BoundedProjection(Projection):
    """Closest points on a trimmed curve: ``points`` (n, 2), unit ``normals`` (n, 2),
    signed Euclidean ``distances`` (n,) and the native ``parameters`` t (n,)."""


class BoundedCurve(ABC):
    """An immutable oriented piece of plane curve with parameter t in [t_start, t_end]."""

    name: str
    type: str = ""
    cost: int = 1  # relative projection cost: profiles project cheap edges first

    # -- what every curve provides -------------------------------------------------------

    @property
    @abstractmethod
    def t_start(self) -> float: ...

    @property
    @abstractmethod
    def t_end(self) -> float: ...

    @abstractmethod
    def evaluate(self, t: Any) -> np.ndarray:
        """Points X(t), shape (n, 2)."""

    @abstractmethod
    def derivative(self, t: Any) -> np.ndarray:
        """dX/dt, shape (n, 2)."""

    @abstractmethod
    def second_derivative(self, t: Any) -> np.ndarray:
        """d2X/dt2, shape (n, 2)."""

    @abstractmethod
    def project(self, points: Any) -> BoundedProjection:
        """Closest points on the trimmed curve (end points included), vectorised."""

    @abstractmethod
    def reversed(self) -> "BoundedCurve":
        """The same piece of curve traversed the other way (same name)."""

    @abstractmethod
    def transformed(self, rotate_deg: float = 0.0, pivot: Any = (0.0, 0.0), translate: Any = (0.0, 0.0)) -> "BoundedCurve":
        """Rotated by ``rotate_deg`` about ``pivot``, then translated."""

    @abstractmethod
    def to_dict(self) -> dict[str, Any]:
        """The edge dict of a ``profile`` scene shape."""

    def renamed(self, name: str) -> "BoundedCurve":
        from dataclasses import replace

        return replace(self, name=name)

    # -- derived quantities --------------------------------------------------------------

    @property
    def start(self) -> np.ndarray:
        return self.evaluate(self.t_start)[0]

    @property
    def end(self) -> np.ndarray:
        return self.evaluate(self.t_end)[0]

    @cached_property
    def is_closed(self) -> bool:
        """True when the curve ends where it starts (a full circle or ellipse)."""
        size = float(np.ptp(self._coarse_samples(), axis=0).max())
        return bool(np.linalg.norm(self.end - self.start) <= 1e-12 * max(size, 1e-300))

    def tangent(self, t: Any) -> np.ndarray:
        return _unit(self.derivative(t))

    def normal(self, t: Any) -> np.ndarray:
        """Unit normal: the tangent turned by -90 degrees (right-hand side)."""
        return _rot90cw(self.tangent(t))

    def curvature(self, t: Any) -> np.ndarray:
        """Signed curvature (x'y'' - y'x'')/|X'|^3: positive where the curve turns left."""
        d1 = self.derivative(t)
        d2 = self.second_derivative(t)
        speed = np.hypot(d1[:, 0], d1[:, 1])
        return (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / speed**3

    def _coarse_samples(self) -> np.ndarray:
        return self.evaluate(np.linspace(self.t_start, self.t_end, 9))

    # -- arc length: adaptive composite Gauss-Legendre table, exact closed forms override --

    def _breakpoints(self) -> np.ndarray:
        """Where the curve's smoothness may break (knots); the length table starts here."""
        return np.array([self.t_start, self.t_end])

    def breakpoints(self) -> np.ndarray:
        """Sorted parameters, ends included, between which the curve is analytic (B-spline
        knots; just the ends for segments and arcs): quadrature splits there."""
        return np.array([self.t_start, self.t_end])

    @cached_property
    def _samples(self) -> tuple[np.ndarray, np.ndarray]:
        grid = self._sample_grid()
        return grid, self.evaluate(grid)

    @cached_property
    def _length_table(self) -> tuple[np.ndarray, np.ndarray]:
        """(t_k, s_k): panel ends and the arc length up to them, to ~1e-15 relative.

        Panels are split until a 12-point and a 24-point Gauss rule agree. scipy.integrate.quad
        would do one integral per call; the table lets arc_length work on many t at once.
        """
        x12, w12 = _gauss_legendre(12)
        x24, w24 = _gauss_legendre(24)

        def panel(a: np.ndarray, b: np.ndarray, x, w) -> np.ndarray:
            half = 0.5 * (b - a)
            t = (0.5 * (a + b))[:, None] + half[:, None] * x[None, :]
            d = self.derivative(t.ravel()).reshape(t.shape + (2,))
            return half * (np.hypot(d[..., 0], d[..., 1]) @ w)

        edges = np.unique(self._breakpoints())
        a, b = edges[:-1], edges[1:]
        done_a, done_b, done_s = [], [], []
        total = float(np.sum(panel(a, b, x24, w24)))
        for _ in range(40):
            if a.size == 0:
                break
            s12 = panel(a, b, x12, w12)
            s24 = panel(a, b, x24, w24)
            ok = np.abs(s24 - s12) <= 1e-15 * max(total, 1e-300) + 1e-15 * np.abs(s24)
            done_a.append(a[ok])
            done_b.append(b[ok])
            done_s.append(s24[ok])
            mid = 0.5 * (a[~ok] + b[~ok])
            a, b = np.concatenate([a[~ok], mid]), np.concatenate([mid, b[~ok]])
        if a.size:  # did not settle (should not happen for smooth pieces): keep the best estimate
            done_a.append(a)
            done_b.append(b)
            done_s.append(panel(a, b, x24, w24))
        a = np.concatenate(done_a)
        s = np.concatenate(done_s)
        order = np.argsort(a)
        a, s = a[order], s[order]
        t_k = np.concatenate([a, [self.t_end]])
        s_k = np.concatenate([[0.0], np.cumsum(s)])
        return t_k, s_k

    @property
    def length(self) -> float:
        return float(self._length_table[1][-1])

    def arc_length(self, t: Any) -> np.ndarray:
        """Arc length from t_start to t (vectorised)."""
        t = np.clip(_params(t), self.t_start, self.t_end)
        t_k, s_k = self._length_table
        k = np.clip(np.searchsorted(t_k, t, side="right") - 1, 0, len(t_k) - 2)
        x, w = _gauss_legendre(24)
        half = 0.5 * (t - t_k[k])
        tq = (0.5 * (t + t_k[k]))[:, None] + half[:, None] * x[None, :]
        d = self.derivative(tq.ravel()).reshape(tq.shape + (2,))
        return s_k[k] + half * (np.hypot(d[..., 0], d[..., 1]) @ w)

    def parameter_at_length(self, s: Any) -> np.ndarray:
        """The parameter t where the arc length from the start equals s (clamped to the curve)."""
        s = np.clip(_params(s), 0.0, self.length)
        t_k, s_k = self._length_table
        k = np.clip(np.searchsorted(s_k, s, side="right") - 1, 0, len(t_k) - 2)
        lo, hi = t_k[k].copy(), t_k[k + 1].copy()
        frac = np.where(s_k[k + 1] > s_k[k], (s - s_k[k]) / np.where(s_k[k + 1] > s_k[k], s_k[k + 1] - s_k[k], 1.0), 0.0)
        t = lo + frac * (hi - lo)
        for _ in range(30):  # safeguarded Newton: ds/dt = |X'(t)|
            r = self.arc_length(t) - s
            lo = np.where(r < 0.0, t, lo)
            hi = np.where(r > 0.0, t, hi)
            d = self.derivative(t)
            speed = np.hypot(d[:, 0], d[:, 1])
            t_new = t - r / np.where(speed > 0.0, speed, np.inf)
            bad = ~((t_new >= lo) & (t_new <= hi)) | (speed <= 0.0)
            t_new = np.where(bad, 0.5 * (lo + hi), t_new)
            if np.all(np.abs(t_new - t) <= 1e-15 * (abs(self.t_end) + abs(self.t_start) + 1.0)):
                t = t_new
                break
            t = t_new
        return t

    # -- signed area contribution ---------------------------------------------------------

    def area_integral(self) -> float:
        """(1/2) * integral of (x dy - y dx) along the curve: summed over a closed
        counter-clockwise loop this is the enclosed area (negative for clockwise)."""
        t_k, _ = self._length_table
        x, w = _gauss_legendre(24)
        a, b = t_k[:-1], t_k[1:]
        half = 0.5 * (b - a)
        t = (0.5 * (a + b))[:, None] + half[:, None] * x[None, :]
        X = self.evaluate(t.ravel())
        D = self.derivative(t.ravel())
        f = (X[:, 0] * D[:, 1] - X[:, 1] * D[:, 0]).reshape(t.shape)
        return float(0.5 * np.sum(half * (f @ w)))

    # -- projection by sampling and safeguarded Newton (used by ellipses and B-splines) ----

    def _sample_grid(self) -> np.ndarray:
        return np.linspace(self.t_start, self.t_end, 65)

    @cached_property
    def _pieces(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Sample grid t (M,), points S (M, 2) and, per piece between samples, a bound h
        (M - 1,) on how far the curve strays from the piece's chord: the largest deviation at
        32 points per piece, times 1.5 (the deviation of a smooth piece is close to a
        parabola, so the sampled maximum is within a few per cent of the true one)."""
        grid, S = self._samples
        u = (np.arange(1, 33) / 33.0)[None, :]
        tt = grid[:-1, None] + u * np.diff(grid)[:, None]
        Y = self.evaluate(tt.ravel()).reshape(tt.shape + (2,))
        a, b = S[:-1, None, :], S[1:, None, :]
        ab = b - a
        L2 = np.sum(ab**2, axis=-1)
        s = np.clip(np.sum((Y - a) * ab, axis=-1) / np.where(L2 > 0.0, L2, 1.0), 0.0, 1.0)
        dev = np.sqrt(np.sum((Y - a - s[..., None] * ab) ** 2, axis=-1)).max(axis=1)
        size = float(np.ptp(S, axis=0).max())
        return grid, S, 1.5 * dev + 1e-13 * size

    def _project_sampled(self, P: np.ndarray, upper: np.ndarray | None = None) -> np.ndarray:
        """Parameters of the closest points by branch and bound over the pieces between
        samples: a piece can hold the closest point only if its chord distance minus its
        deviation bound (a lower bound) is below the nearest sample's distance (an upper
        bound); each such piece is refined by safeguarded Newton on g(t) = X'(t).(X(t) - p)
        within the piece, and the nearest result wins (sample points and ends included).
        Pieces whose lower bound is at least ``upper`` (the caller's best) are skipped."""
        grid, S, h = self._pieces
        M = len(grid)
        n = len(P)
        best_t = np.empty(n)
        a = S[:-1]
        ab = S[1:] - S[:-1]
        L2 = np.sum(ab**2, axis=1)
        inv = np.where(L2 > 0.0, 1.0 / np.where(L2 > 0.0, L2, 1.0), 0.0)
        chunk = max(1, 2_000_000 // M)
        for i0 in range(0, n, chunk):  # blocks of points bound the (n, M) work arrays
            p = P[i0 : i0 + chunk]
            m = len(p)
            rows = np.arange(m)
            dx = p[:, 0, None] - a[None, :, 0]
            dy = p[:, 1, None] - a[None, :, 1]
            d2 = dx * dx
            d2 += dy * dy  # squared distances to the samples but the last
            s = dx * ab[None, :, 0]
            s += dy * ab[None, :, 1]
            s *= inv[None, :]
            np.clip(s, 0.0, 1.0, out=s)
            ex = dx - s * ab[None, :, 0]
            ey = dy - s * ab[None, :, 1]
            e2 = ex * ex
            e2 += ey * ey  # squared distances to the chords
            d_last = (p[:, 0] - S[-1, 0]) ** 2 + (p[:, 1] - S[-1, 1]) ** 2
            k = np.argmin(d2, axis=1)
            bd = d2[rows, k]
            use_last = d_last < bd
            k = np.where(use_last, M - 1, k)
            bd = np.where(use_last, d_last, bd)
            ub = np.sqrt(bd)
            if upper is not None:
                ub = np.minimum(ub, upper[i0 : i0 + chunk])
            # lower bound sqrt(e2) - h < ub  <=>  e2 < (ub + h)^2
            reach = ub[:, None] + h[None, :]
            reach *= reach
            pt, piece = np.nonzero(e2 < reach)
            t_pairs = self._newton_closest(
                p[pt],
                grid[piece] + s[pt, piece] * (grid[piece + 1] - grid[piece]),
                grid[piece],
                grid[piece + 1],
            )
            X = self.evaluate(t_pairs)
            dd = (X[:, 0] - p[pt, 0]) ** 2 + (X[:, 1] - p[pt, 1]) ** 2
            # per point: the nearest sample, then any refined piece that beats it
            bt = grid[k]
            order = np.lexsort((dd, pt))
            first = np.unique(pt[order], return_index=True)[1]
            win = order[first]
            better = dd[win] < bd[pt[win]]
            bt[pt[win][better]] = t_pairs[win][better]
            best_t[i0 : i0 + chunk] = bt
        return best_t

    def _newton_closest(self, p: np.ndarray, t: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """Safeguarded Newton for a zero of g(t) = X'(t).(X(t) - p) in [lo, hi]; a Newton step
        leaving the bracket is replaced by bisection. Converged points drop out of the work set."""
        t = t.copy()
        lo = lo.copy()
        hi = hi.copy()
        tol = 1e-15 * (abs(self.t_end - self.t_start) + abs(self.t_start) + abs(self.t_end))
        active = np.arange(len(t))
        for _ in range(60):
            if active.size == 0:
                break
            ta, la, ha, pa = t[active], lo[active], hi[active], p[active]
            X, d1, d2 = self._derivatives2(ta)
            rx = X[:, 0] - pa[:, 0]
            ry = X[:, 1] - pa[:, 1]
            g = d1[:, 0] * rx + d1[:, 1] * ry
            gp = d2[:, 0] * rx + d2[:, 1] * ry + d1[:, 0] ** 2 + d1[:, 1] ** 2
            ha = np.where(g > 0.0, ta, ha)
            la = np.where(g < 0.0, ta, la)
            t_new = ta - g / np.where(gp > 0.0, gp, 1.0)
            bad = (gp <= 0.0) | ~((t_new >= la) & (t_new <= ha))
            t_new = np.where(bad, 0.5 * (la + ha), t_new)
            t_new = np.where(g == 0.0, ta, t_new)
            done = (np.abs(t_new - ta) <= tol) | (ha - la <= tol)
            t[active], lo[active], hi[active] = t_new, la, ha
            active = active[~done]
        return t

    def _derivatives2(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """X, dX/dt and d2X/dt2 at t (one pass where the curve can share the work)."""
        return self.evaluate(t), self.derivative(t), self.second_derivative(t)

    def _nearest_signed(self, P: np.ndarray, upper: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(signed distances, parameters) of the projection, without the points and normals
        (profiles need only these for all points; closed forms override it), as new arrays the
        caller may write to. Where ``upper``
        (n,) is given, a result whose distance is >= upper may be any such value (the caller
        already has something closer)."""
        pr = self.project(P)
        return pr.distances, pr.parameters

    def _projection_at(self, P: np.ndarray, t: np.ndarray) -> BoundedProjection:
        c = self.evaluate(t)
        n = self.normal(t)
        return BoundedProjection(points=c, normals=n, distances=_signed_euclidean(P, c, n), parameters=t)

    # -- axis crossings ---------------------------------------------------------------------

    def axis_crossings(self, axis: int, value: float) -> np.ndarray:
        """Sorted parameters where coordinate ``axis`` (0 = x, 1 = y) equals ``value``.

        Generic version (closed forms override it): sign changes between samples refined by
        bisection, plus pieces that may dip across the line between two samples on the same
        side (within the piece's deviation bound), searched at their coordinate extremum. A
        curve lying along the line returns its two ends."""
        axis = _axis(axis)
        value = float(value)

        def f(t):
            return self.evaluate(t)[:, axis] - value

        def df(t):
            return self.derivative(t)[:, axis]

        grid, S, h = self._pieces
        fs = S[:, axis] - value
        if np.all(fs == 0.0):
            return np.array([self.t_start, self.t_end])
        zeros = [grid[fs == 0.0]]
        change = (fs[:-1] * fs[1:]) < 0.0
        if np.any(change):
            zeros.append(_bisect(f, grid[:-1][change], grid[1:][change], fs[:-1][change]))
        # pieces with both ends on one side that may still reach the line (within their
        # deviation bound): look at the coordinate's extremum inside the piece; if it gets
        # to the other side there are two crossings (a touching line gives one)
        same = ~change & (fs[:-1] != 0.0) & (fs[1:] != 0.0)
        reach = same & (np.minimum(np.abs(fs[:-1]), np.abs(fs[1:])) <= h)
        idx = np.flatnonzero(reach)
        if idx.size:
            lo, hi = grid[idx], grid[idx + 1]
            d_lo, d_hi = df(lo), df(hi)
            turn = d_lo * d_hi < 0.0
            if np.any(turn):
                lo, hi, d_lo = lo[turn], hi[turn], d_lo[turn]
                tm = _bisect(df, lo, hi, d_lo)
                fm = f(tm)
                side = np.sign(fs[idx[turn]])
                touch = fm == 0.0
                zeros.append(tm[touch])
                cross = np.sign(fm) == -side
                if np.any(cross):
                    zeros.append(_bisect(f, lo[cross], tm[cross], f(lo[cross])))
                    zeros.append(_bisect(f, tm[cross], hi[cross], fm[cross]))
        return _dedupe_sorted(np.concatenate(zeros), abs(self.t_end - self.t_start))

    # -- quadrature ------------------------------------------------------------------------

    def quadrature(self, t0: float, t1: float, order: int = 4) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Gauss-Legendre rule in t on [t0, t1] (split at interior knots where the curve has
        them): (points (m, 2), weights ds (m,) = w |dX/dt| |dt|, unit normals (m, 2), t (m,))."""
        order = int(order)
        if order < 1:
            raise ValueError(f"quadrature order must be >= 1, got {order}")
        t0, t1 = float(t0), float(t1)
        lo, hi = min(t0, t1), max(t0, t1)
        bp = self.breakpoints()
        cuts = np.concatenate([[lo], bp[(bp > lo) & (bp < hi)], [hi]])
        if t1 < t0:
            cuts = cuts[::-1]
        x, w = _gauss_legendre(order)
        a, b = cuts[:-1], cuts[1:]
        half = 0.5 * (b - a)
        t = ((0.5 * (a + b))[:, None] + half[:, None] * x[None, :]).ravel()
        d = self.derivative(t)
        speed = np.hypot(d[:, 0], d[:, 1])
        weights = (np.abs(half)[:, None] * w[None, :]).ravel() * speed
        return self.evaluate(t), weights, _rot90cw(_unit(d)), t

    # -- chord matching (thesis section 5.2) ---------------------------------------------------

    def parameter_at_chord(self, origin: Any, chord: Any, t_from: float, direction: int = 1, samples: int = 256) -> np.ndarray:
        """Parameters of the points whose straight-line distance from ``origin`` equals each
        ``chord``, walking along the curve from ``t_from`` in ``direction`` (+1: increasing t).

        The first crossing along the walk is returned (where the chord distance is not
        monotone, later crossings are ignored); NaN where the curve ends before the chord
        distance is reached. On a closed curve (full circle or ellipse) the walk wraps around
        once. The distance is sampled at ``samples`` intervals and each crossing refined to
        round-off by :mod:`geometry.chord_walk` (safeguarded Newton); a crossing that only
        touches (tangency between two samples) can be missed.
        """
        origin = _vec2(origin, "origin")
        chord = _params(chord)
        if direction not in (1, -1):
            raise ValueError(f"direction must be +1 or -1, got {direction!r}")
        t_from = float(np.clip(t_from, self.t_start, self.t_end))
        out = np.full(chord.shape, np.nan)
        segments = self._walk_segments(t_from, direction, int(samples))
        if not segments:  # t_from at the end the walk goes to
            D0 = float(np.linalg.norm(self.evaluate(t_from)[0] - origin))
            out[np.abs(chord - D0) <= 1e-14 * max(D0, 1.0)] = t_from
            return out
        todo = np.arange(len(chord))
        for t in segments:  # the walk's pieces, each continuous in t (a closed curve's seam between)
            found = first_crossing(self, origin, chord[todo], t, walk_distances(self, origin, t))
            out[todo] = found
            todo = todo[np.isnan(found)]
            if not len(todo):
                break
        return out

    def _walk_segments(self, t_from: float, direction: int, samples: int) -> list[np.ndarray]:
        """Parameters of the chord walk from t_from in ``direction`` (to the curve's end; once
        around a closed curve, split at its seam), ``samples`` intervals plus the breakpoints."""
        period = self.t_end - self.t_start
        if self.is_closed:
            W, seam = period, ((self.t_end - t_from) if direction > 0 else (t_from - self.t_start))
        else:
            W = (self.t_end - t_from) if direction > 0 else (t_from - self.t_start)
            seam = W
        if W <= 0.0:
            return []
        bp = self._breakpoints()
        wb = np.mod(direction * (bp - t_from), period) if self.is_closed else direction * (bp - t_from)
        w = np.unique(np.concatenate([np.linspace(0.0, W, samples + 1), wb[(wb > 0.0) & (wb < W)], [seam]]))
        first = w[w <= seam]
        segments = [np.clip(t_from + direction * first, self.t_start, self.t_end)]
        rest = w[w >= seam]
        if self.is_closed and len(rest) > 1:  # past the seam: the parameter restarts at the other end
            segments.append(np.clip(t_from + direction * (rest - period), self.t_start, self.t_end))
        return [t for t in segments if len(t) > 1]

    # -- tessellation ----------------------------------------------------------------------

    def tessellate(self, chord_tolerance: float) -> tuple[np.ndarray, np.ndarray]:
        """Polyline (points (m, 2), t (m,)) with both ends, within ``chord_tolerance`` of the
        curve (the curve's deviation from every chord is checked at 1/4, 1/2 and 3/4 of the
        piece; pieces are halved until it is within the tolerance)."""
        tol = float(chord_tolerance)
        if not tol > 0.0:
            raise ValueError(f"chord_tolerance must be positive, got {chord_tolerance!r}")
        t = np.unique(np.concatenate([np.linspace(self.t_start, self.t_end, 5), self._breakpoints()]))
        for _ in range(60):
            X = self.evaluate(t)
            a, b = X[:-1], X[1:]
            tm = 0.5 * (t[:-1] + t[1:])
            chord = b - a
            L2 = np.where(np.sum(chord**2, axis=1) > 0.0, np.sum(chord**2, axis=1), 1.0)
            dev = np.zeros(len(tm))
            # distance of the curve at 1/4, 1/2, 3/4 of each piece from its chord segment
            # (three points, so an inflection with its midpoint on the chord is caught)
            for frac in (0.25, 0.5, 0.75):
                m = self.evaluate(t[:-1] + frac * (t[1:] - t[:-1]))
                s = np.clip(np.einsum("ij,ij->i", m - a, chord) / L2, 0.0, 1.0)
                dev = np.maximum(dev, np.linalg.norm(m - (a + s[:, None] * chord), axis=1))
            bad = dev > tol
            if not np.any(bad):
                break
            t = np.sort(np.concatenate([t, tm[bad]]))
        return self.evaluate(t), t
