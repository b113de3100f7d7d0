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

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from .quadrature import gauss_legendre
from ._base import MAX_COORDINATE, Projection, real_array

__all__ = [
    "BoundedProjection",
    "BoundedCurve",
    "Segment",
    "Arc",
    "EllipticArc",
    "BSplineArc",
    "bounded_curve_from_dict",
]

_TWO_PI = 2.0 * math.pi



@dataclass(frozen=True, eq=False)
class BoundedProjection(Projection):
    """Closest points on a trimmed curve: ``points`` (n, 2), unit ``normals`` (n, 2),
    signed Euclidean ``distances`` (n,) and the native ``parameters`` t (n,)."""


# ---------------------------------------------------------------------------------------
# small helpers
# ---------------------------------------------------------------------------------------


_gauss_legendre = gauss_legendre


def _points2(points: Any, name: str = "points") -> np.ndarray:
    """Query points as a float (n, 2) array; a single (2,) point is n = 1. Only real numbers
    (int or float arrays) are accepted."""
    arr = real_array(points, name)
    if arr.ndim == 1:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ValueError(f"{name} must have shape (n, 2), got {np.shape(points)}")
    return arr


def _norm2(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """sqrt(x^2 + y^2) elementwise, fast; np.hypot where the squares would overflow."""
    with np.errstate(over="ignore", invalid="ignore"):
        d = np.sqrt(x * x + y * y)
    big = ~(d < 1e150)
    if big.any():
        d[big] = np.hypot(np.broadcast_to(x, d.shape)[big], np.broadcast_to(y, d.shape)[big])
    return d


def _params(t: Any) -> np.ndarray:
    return np.atleast_1d(np.asarray(t, dtype=float))


def _vec2(value: Any, field: str) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{field} must be a list of 2 numbers, got {value!r}") from None
    if arr.shape != (2,):
        raise ValueError(f"{field} must be a list of 2 numbers, got {value!r}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{field} must be finite, got {value!r}")
    if np.any(np.abs(arr) > MAX_COORDINATE):
        raise ValueError(f"{field} must be within +-{MAX_COORDINATE:g} (squared distances would overflow), got {value!r}")
    arr = arr.copy()
    arr.setflags(write=False)
    return arr


def _number(value: Any, field: str) -> float:
    if isinstance(value, bool):
        raise ValueError(f"{field} must be a number, got {value!r}")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{field} must be a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{field} must be finite, got {value!r}")
    return x


def _rotation(rotate_deg: float) -> np.ndarray:
    a = math.radians(rotate_deg)
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s], [s, c]])


def _transform_point(p: np.ndarray, rotate_deg: float, pivot: Any, translate: Any) -> np.ndarray:
    pivot = np.asarray(pivot, dtype=float)
    translate = np.asarray(translate, dtype=float)
    return _rotation(rotate_deg) @ (np.asarray(p, dtype=float) - pivot) + pivot + translate


def _rot90cw(v: np.ndarray) -> np.ndarray:
    """Vectors (n, 2) turned by -90 degrees: (x, y) -> (y, -x)."""
    return np.stack([v[..., 1], -v[..., 0]], axis=-1)


def _unit(v: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return v / np.where(n > 0.0, n, 1.0)


def _signed_euclidean(p: np.ndarray, c: np.ndarray, n: np.ndarray) -> np.ndarray:
    d = p - c
    dist = _norm2(d[:, 0], d[:, 1])
    side = d[:, 0] * n[:, 0] + d[:, 1] * n[:, 1]
    return np.where(side < 0.0, -dist, dist)


def _bisect(func, lo: np.ndarray, hi: np.ndarray, flo: np.ndarray, iterations: int = 64) -> np.ndarray:
    """Vectorised bisection for a sign change of ``func`` in [lo, hi] (flo = func(lo)).

    Hand-written because scipy.optimize's bracketing solvers are scalar (one call per root).
    """
    lo = lo.copy()
    hi = hi.copy()
    flo = flo.copy()
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        fm = func(mid)
        left = np.sign(fm) == np.sign(flo)
        lo = np.where(left, mid, lo)
        flo = np.where(left, fm, flo)
        hi = np.where(left, hi, mid)
        if np.all(np.abs(hi - lo) <= 4e-16 * np.maximum(np.abs(lo), np.abs(hi)) + 1e-300):
            break
    return 0.5 * (lo + hi)


def _roots_on_grid(func, grid: np.ndarray) -> np.ndarray:
    """Sorted roots of a scalar function sampled on ``grid``: exact zeros at grid nodes and
    sign changes between nodes refined by bisection. A double root strictly between two
    nodes (a tangency) is missed unless it is sampled."""
    f = func(grid)
    zeros = grid[f == 0.0]
    change = (f[:-1] * f[1:]) < 0.0
    if np.any(change):
        lo, hi = grid[:-1][change], grid[1:][change]
        roots = _bisect(func, lo, hi, f[:-1][change])
        zeros = np.concatenate([zeros, roots])
    return np.unique(zeros)


def _dedupe_sorted(t: np.ndarray, scale: float) -> np.ndarray:
    t = np.sort(np.asarray(t, dtype=float))
    if t.size < 2:
        return t
    keep = np.concatenate([[True], np.diff(t) > 1e-13 * scale])
    return t[keep]


# ---------------------------------------------------------------------------------------
# the base class: everything that follows from evaluate / derivative / second_derivative
# ---------------------------------------------------------------------------------------


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
        """The SPEC section 4 profile edge dict."""

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
        (profiles need only these for all points; closed forms override it). Where ``upper``
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
        once. The distance is sampled at ``samples`` intervals and each crossing
        refined by bisection to round-off; a crossing that only touches (tangency between two
        samples) can be missed.
        """
        origin = _vec2(origin, "origin")
        chord = _params(chord)
        if direction not in (1, -1):
            raise ValueError(f"direction must be +1 or -1, got {direction!r}")
        t_from = float(np.clip(t_from, self.t_start, self.t_end))
        period = self.t_end - self.t_start
        closed = self.is_closed
        # walk variable w >= 0: t = t_from + direction * w, wrapped once around a closed curve
        if closed:
            W = period
        else:
            W = (self.t_end - t_from) if direction > 0 else (t_from - self.t_start)

        def t_of(w):
            t = t_from + direction * w
            if closed:
                t = self.t_start + np.mod(t - self.t_start, period)
                t = np.where(w >= W, t_from, t) if W > 0 else t
            return np.clip(t, self.t_start, self.t_end)

        out = np.full(chord.shape, np.nan)
        if W <= 0.0:
            D0 = float(np.linalg.norm(self.evaluate(t_from)[0] - origin))
            out[np.abs(chord - D0) <= 1e-14 * max(D0, 1.0)] = t_from
            return out
        w = np.linspace(0.0, W, int(samples) + 1)
        bp = self._breakpoints()
        wb = np.mod(direction * (bp - t_from), period) if closed else direction * (bp - t_from)
        w = np.unique(np.concatenate([w, wb[(wb > 0.0) & (wb < W)]]))
        X = self.evaluate(t_of(w))
        D = np.sqrt((X[:, 0] - origin[0]) ** 2 + (X[:, 1] - origin[1]) ** 2)
        f = D[None, :] - chord[:, None]
        # distances within round-off of the chord count as hits (origin on the curve, chord 0)
        f = np.where(np.abs(f) <= 1e-14 * (D.max() + np.abs(chord[:, None])), 0.0, f)
        hit = (f[:, :-1] == 0.0) | (f[:, :-1] * f[:, 1:] < 0.0)
        last = f[:, -1] == 0.0
        found = hit.any(axis=1)
        j = np.argmax(hit, axis=1)
        exact = found & (f[np.arange(len(chord)), j] == 0.0)
        out[exact] = t_of(w[j[exact]])
        todo = found & ~exact
        if np.any(todo):
            c = chord[todo]

            def g(ww):
                Y = self.evaluate(t_of(ww))
                return np.sqrt((Y[:, 0] - origin[0]) ** 2 + (Y[:, 1] - origin[1]) ** 2) - c

            jj = j[todo]
            out[todo] = t_of(_bisect(g, w[jj], w[jj + 1], f[todo, jj]))
        tail = ~found & last
        out[tail] = t_of(np.array([W]))[0]
        return out

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


def _axis(axis: Any) -> int:
    if axis not in (0, 1):
        raise ValueError(f"axis must be 0 (x) or 1 (y), got {axis!r}")
    return int(axis)


# ---------------------------------------------------------------------------------------
# segment
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class Segment(BoundedCurve):
    """Straight segment from ``p0`` to ``p1``; t is the arc length."""

    p0: np.ndarray
    p1: np.ndarray
    name: str = ""
    type = "line"
    cost = 1

    def __post_init__(self) -> None:
        object.__setattr__(self, "p0", _vec2(self.p0, f"segment {self.name!r}: start"))
        object.__setattr__(self, "p1", _vec2(self.p1, f"segment {self.name!r}: end"))
        d = self.p1 - self.p0
        L = float(np.hypot(d[0], d[1]))
        if not L > 1e-300:
            raise ValueError(f"segment {self.name!r}: start and end coincide ({list(self.p0)})")

    @cached_property
    def _frame(self) -> tuple[float, np.ndarray]:
        d = self.p1 - self.p0
        L = float(np.hypot(d[0], d[1]))
        return L, d / L

    @property
    def t_start(self) -> float:
        return 0.0

    @property
    def t_end(self) -> float:
        return self._frame[0]

    @property
    def length(self) -> float:
        return self._frame[0]

    @property
    def start(self) -> np.ndarray:
        return self.p0

    @property
    def end(self) -> np.ndarray:
        return self.p1

    @property
    def is_closed(self) -> bool:
        return False

    def evaluate(self, t: Any) -> np.ndarray:
        t = _params(t)
        L, u = self._frame
        # interpolate so that t = L gives p1 exactly
        return self.p0[None, :] + (t / L)[:, None] * (self.p1 - self.p0)[None, :]

    def derivative(self, t: Any) -> np.ndarray:
        t = _params(t)
        return np.broadcast_to(self._frame[1], (t.size, 2)).copy()

    def second_derivative(self, t: Any) -> np.ndarray:
        return np.zeros((_params(t).size, 2))

    def curvature(self, t: Any) -> np.ndarray:
        return np.zeros(_params(t).size)

    def arc_length(self, t: Any) -> np.ndarray:
        return np.clip(_params(t), 0.0, self.length)

    def parameter_at_length(self, s: Any) -> np.ndarray:
        return np.clip(_params(s), 0.0, self.length)

    def area_integral(self) -> float:
        return 0.5 * float(self.p0[0] * self.p1[1] - self.p0[1] * self.p1[0])

    def _breakpoints(self) -> np.ndarray:
        return np.array([0.0, self.length])

    def project(self, points: Any) -> BoundedProjection:
        P = _points2(points)
        L, u = self._frame
        (x0, y0), (x1, y1) = self.p0, self.p1
        ux, uy = float(u[0]), float(u[1])
        dx = P[:, 0] - x0
        dy = P[:, 1] - y0
        t = dx * ux
        t += dy * uy
        np.clip(t, 0.0, L, out=t)
        f = t / L
        cx = x0 + f * (x1 - x0)
        cy = y0 + f * (y1 - y0)
        rx = P[:, 0] - cx
        ry = P[:, 1] - cy
        dist = _norm2(rx, ry)
        side = rx * uy - ry * ux
        dist = np.where(side < 0.0, -dist, dist)
        n = np.empty((len(P), 2))
        n[:, 0] = uy
        n[:, 1] = -ux
        return BoundedProjection(points=np.stack([cx, cy], axis=1), normals=n, distances=dist, parameters=t)

    def _nearest_signed(self, P: np.ndarray, upper: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        L, u = self._frame
        (x0, y0), (x1, y1) = self.p0, self.p1
        ux, uy = float(u[0]), float(u[1])
        dx = P[:, 0] - x0
        dy = P[:, 1] - y0
        t = dx * ux
        t += dy * uy
        np.clip(t, 0.0, L, out=t)
        f = t / L
        rx = dx - f * (x1 - x0)
        ry = dy - f * (y1 - y0)
        dist = _norm2(rx, ry)
        side = rx * uy - ry * ux
        return np.where(side < 0.0, -dist, dist), t

    def axis_crossings(self, axis: int, value: float) -> np.ndarray:
        axis = _axis(axis)
        a, b = self.p0[axis], self.p1[axis]
        value = float(value)
        if a == b:
            return np.array([0.0, self.length]) if a == value else np.empty(0)
        if not (min(a, b) <= value <= max(a, b)):
            return np.empty(0)
        if value == a:
            return np.array([0.0])
        if value == b:
            return np.array([self.length])
        return np.array([min(max((value - a) / (b - a) * self.length, 0.0), self.length)])

    def parameter_at_chord(self, origin: Any, chord: Any, t_from: float, direction: int = 1, samples: int = 256) -> np.ndarray:
        """Closed form: the first root along the walk of |a + t u - origin| = chord."""
        origin = _vec2(origin, "origin")
        chord = _params(chord)
        if direction not in (1, -1):
            raise ValueError(f"direction must be +1 or -1, got {direction!r}")
        L, u = self._frame
        t_from = float(np.clip(t_from, 0.0, L))
        # walk variable w >= 0: t = t_from + direction * w; |q + direction*w*u|^2 = chord^2
        q = self.evaluate(t_from)[0] - origin
        bq = direction * float(q @ u)
        cq = float(q @ q)
        disc = bq * bq - (cq - chord**2)
        out = np.full(chord.shape, np.nan)
        ok = disc >= 0.0
        sq = np.sqrt(np.where(ok, disc, 0.0))
        w1 = -bq - sq
        w2 = -bq + sq
        w = np.where(w1 >= 0.0, w1, w2)
        w_max = (L - t_from) if direction > 0 else t_from
        ok &= (w >= 0.0) & (w <= w_max * (1 + 1e-15))
        out[ok] = np.clip(t_from + direction * w[ok], 0.0, L)
        return out

    def tessellate(self, chord_tolerance: float) -> tuple[np.ndarray, np.ndarray]:
        if not float(chord_tolerance) > 0.0:
            raise ValueError(f"chord_tolerance must be positive, got {chord_tolerance!r}")
        return np.array([self.p0, self.p1]), np.array([0.0, self.length])

    def reversed(self) -> "Segment":
        return Segment(self.p1, self.p0, self.name)

    def transformed(self, rotate_deg: float = 0.0, pivot: Any = (0.0, 0.0), translate: Any = (0.0, 0.0)) -> "Segment":
        return Segment(
            _transform_point(self.p0, rotate_deg, pivot, translate),
            _transform_point(self.p1, rotate_deg, pivot, translate),
            self.name,
        )

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "type": "line", "start": self.p0.tolist(), "end": self.p1.tolist()}


# ---------------------------------------------------------------------------------------
# circular arc
# ---------------------------------------------------------------------------------------


def _sweep_checks(start_angle: float, end_angle: float, owner: str) -> None:
    sweep = end_angle - start_angle
    if sweep == 0.0:
        raise ValueError(f"{owner}: start_angle and end_angle are equal ({math.degrees(start_angle)} degrees)")
    if abs(sweep) > _TWO_PI * (1.0 + 1e-12):
        raise ValueError(
            f"{owner}: the arc sweeps more than 360 degrees "
            f"(start_angle {math.degrees(start_angle)}, end_angle {math.degrees(end_angle)})"
        )


class _AngleSweptArc(BoundedCurve):
    """Shared part of the circular and elliptic arcs: t is the angle swept from
    ``start_angle`` towards ``end_angle`` (radians), in [0, |end - start|]."""

    start_angle: float
    end_angle: float

    def _set_angles(self, owner: str) -> None:
        """Check the two angles and store them as floats; a sweep a hair over 2 pi is cut to 2 pi."""
        a0 = _number(self.start_angle, f"{owner}: start_angle")
        a1 = _number(self.end_angle, f"{owner}: end_angle")
        _sweep_checks(a0, a1, owner)
        if abs(a1 - a0) > _TWO_PI:
            a1 = a0 + math.copysign(_TWO_PI, a1 - a0)
        object.__setattr__(self, "start_angle", a0)
        object.__setattr__(self, "end_angle", a1)

    @property
    def sense(self) -> float:
        """+1 counter-clockwise, -1 clockwise."""
        return 1.0 if self.end_angle > self.start_angle else -1.0

    @property
    def sweep(self) -> float:
        return abs(self.end_angle - self.start_angle)

    @property
    def t_start(self) -> float:
        return 0.0

    @property
    def t_end(self) -> float:
        return self.sweep

    @property
    def is_closed(self) -> bool:
        return self.sweep >= _TWO_PI

    @property
    def end(self) -> np.ndarray:
        if self.is_closed:
            return self.start
        return self.evaluate(self.sweep)[0]

    def _theta(self, t: Any) -> np.ndarray:
        return self.start_angle + self.sense * _params(t)

    def _t_of_angle(self, theta: np.ndarray) -> np.ndarray:
        """Angle -> t in [0, 2 pi)."""
        return np.mod(self.sense * (theta - self.start_angle), _TWO_PI)

    def _nearer_end(self, P: np.ndarray) -> np.ndarray:
        """t of the end point nearer to each point (the start on a tie)."""
        ds = np.sum((P - self.start) ** 2, axis=1)
        de = np.sum((P - self.end) ** 2, axis=1)
        return np.where(ds <= de, 0.0, self.sweep)

    def _crossings_at_angles(self, theta: np.ndarray) -> np.ndarray:
        """Sorted t of the angles ``theta`` that lie on the arc (the axis crossings)."""
        t = self._t_of_angle(theta)
        # a crossing at the start angle may come back as ~2 pi
        t = np.where(t > _TWO_PI - 1e-14, 0.0, t)
        out = list(t[t <= self.sweep * (1 + 1e-15)])
        if self.is_closed and 0.0 in out:
            out.append(self.sweep)
        return _dedupe_sorted(np.clip(np.array(out), 0.0, self.sweep), self.sweep)


@dataclass(frozen=True, eq=False)
class Arc(_AngleSweptArc):
    """Circular arc from ``start_angle`` to ``end_angle`` (radians; counter-clockwise when
    end > start). t is the angle swept from the start, in [0, |end - start|]. A sweep of
    2 pi is a full circle (one closed edge)."""

    center: np.ndarray
    radius: float
    start_angle: float
    end_angle: float
    name: str = ""
    type = "arc"
    cost = 1

    def __post_init__(self) -> None:
        owner = f"arc {self.name!r}"
        object.__setattr__(self, "center", _vec2(self.center, f"{owner}: center"))
        r = _number(self.radius, f"{owner}: radius")
        if not r > 0.0:
            raise ValueError(f"{owner}: radius must be positive, got {self.radius!r}")
        if r > MAX_COORDINATE:
            raise ValueError(f"{owner}: radius must be at most {MAX_COORDINATE:g} (squared distances would overflow), got {self.radius!r}")
        object.__setattr__(self, "radius", r)
        self._set_angles(owner)

    @property
    def length(self) -> float:
        return self.radius * self.sweep

    def evaluate(self, t: Any) -> np.ndarray:
        th = self._theta(t)
        return self.center[None, :] + self.radius * np.stack([np.cos(th), np.sin(th)], axis=1)

    @property
    def start(self) -> np.ndarray:
        return self.evaluate(0.0)[0]

    def derivative(self, t: Any) -> np.ndarray:
        th = self._theta(t)
        return self.sense * self.radius * np.stack([-np.sin(th), np.cos(th)], axis=1)

    def second_derivative(self, t: Any) -> np.ndarray:
        th = self._theta(t)
        return -self.radius * np.stack([np.cos(th), np.sin(th)], axis=1)

    def normal(self, t: Any) -> np.ndarray:
        th = self._theta(t)
        return self.sense * np.stack([np.cos(th), np.sin(th)], axis=1)

    def curvature(self, t: Any) -> np.ndarray:
        return np.full(_params(t).size, self.sense / self.radius)

    def arc_length(self, t: Any) -> np.ndarray:
        return self.radius * np.clip(_params(t), 0.0, self.sweep)

    def parameter_at_length(self, s: Any) -> np.ndarray:
        return np.clip(_params(s) / self.radius, 0.0, self.sweep)

    def _breakpoints(self) -> np.ndarray:
        k = max(1, int(math.ceil(self.sweep / (0.5 * math.pi))))
        return np.linspace(0.0, self.sweep, k + 1)

    def project(self, points: Any) -> BoundedProjection:
        P = _points2(points)
        d = P - self.center
        theta = np.arctan2(d[:, 1], d[:, 0])  # the centre itself gives 0: deterministic
        t = self._t_of_angle(theta)
        if not self.is_closed:
            outside = t > self.sweep
            if np.any(outside):
                t = np.where(outside, self._nearer_end(P), t)
        return self._projection_at(P, t)

    def _nearest_signed(self, P: np.ndarray, upper: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        dx = P[:, 0] - self.center[0]
        dy = P[:, 1] - self.center[1]
        t = self._t_of_angle(np.arctan2(dy, dx))
        # foot on the arc: p - c = (rho - r) e_r and n = sense e_r
        sd = self.sense * (_norm2(dx, dy) - self.radius)
        if not self.is_closed:
            out = np.flatnonzero(t > self.sweep)
            if out.size:
                pr = self.project(P[out])
                sd[out] = pr.distances
                t[out] = pr.parameters
        return sd, t

    def axis_crossings(self, axis: int, value: float) -> np.ndarray:
        axis = _axis(axis)
        k = (float(value) - self.center[axis]) / self.radius
        if abs(k) > 1.0 + 1e-14:
            return np.empty(0)
        k = min(max(k, -1.0), 1.0)
        if axis == 0:
            base = math.acos(k)
            theta = np.array([base, -base])
        else:
            base = math.asin(k)
            theta = np.array([base, math.pi - base])
        return self._crossings_at_angles(theta)

    def tessellate(self, chord_tolerance: float) -> tuple[np.ndarray, np.ndarray]:
        tol = float(chord_tolerance)
        if not tol > 0.0:
            raise ValueError(f"chord_tolerance must be positive, got {chord_tolerance!r}")
        # sagitta r (1 - cos(dt/2)) <= tol
        if tol >= self.radius:
            dt = math.pi / 2
        else:
            dt = 2.0 * math.acos(1.0 - tol / self.radius)
        n = max(2, int(math.ceil(self.sweep / dt)))
        t = np.linspace(0.0, self.sweep, n + 1)
        X = self.evaluate(t)
        if self.is_closed:
            X[-1] = X[0]
        return X, t

    def reversed(self) -> "Arc":
        return Arc(self.center, self.radius, self.end_angle, self.start_angle, self.name)

    def transformed(self, rotate_deg: float = 0.0, pivot: Any = (0.0, 0.0), translate: Any = (0.0, 0.0)) -> "Arc":
        rot = math.radians(float(rotate_deg))
        return Arc(
            _transform_point(self.center, rotate_deg, pivot, translate),
            self.radius,
            self.start_angle + rot,
            self.end_angle + rot,
            self.name,
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "type": "arc",
            "center": self.center.tolist(),
            "radius": self.radius,
            "start_angle": math.degrees(self.start_angle),
            "end_angle": math.degrees(self.end_angle),
        }


# ---------------------------------------------------------------------------------------
# elliptic arc
# ---------------------------------------------------------------------------------------


def _ellipse_kernel():
    """The robust closest-point kernel of geometry.ellipse, if it is available."""
    try:
        from .ellipse import ellipse_closest_point_2d  # type: ignore[attr-defined]
    except ImportError:
        return None
    return ellipse_closest_point_2d


@dataclass(frozen=True, eq=False)
class EllipticArc(_AngleSweptArc):
    """Arc of the ellipse X = center + R(rotate_deg) (a cos th, b sin th) from parametric
    angle ``start_angle`` to ``end_angle`` (radians, counter-clockwise when end > start);
    ``semi_axes`` = (a, b) along the rotated x and y axes. t is the parametric angle swept
    from the start, in [0, |end - start|]."""

    center: np.ndarray
    semi_axes: np.ndarray
    rotate_deg: float
    start_angle: float
    end_angle: float
    name: str = ""
    type = "elliptic_arc"
    cost = 4

    def __post_init__(self) -> None:
        owner = f"elliptic_arc {self.name!r}"
        object.__setattr__(self, "center", _vec2(self.center, f"{owner}: center"))
        ax = _vec2(self.semi_axes, f"{owner}: semi_axes")
        if not (ax[0] > 0.0 and ax[1] > 0.0):
            raise ValueError(f"{owner}: semi_axes must be positive, got {list(ax)}")
        object.__setattr__(self, "semi_axes", ax)
        object.__setattr__(self, "rotate_deg", _number(self.rotate_deg, f"{owner}: rotate_deg"))
        self._set_angles(owner)

    @cached_property
    def _R(self) -> np.ndarray:
        return _rotation(self.rotate_deg)

    def _local(self, v: np.ndarray) -> np.ndarray:
        # elementwise (not a matmul) so one point and many points round identically
        R = self._R
        return np.stack([R[0, 0] * v[:, 0] + R[0, 1] * v[:, 1], R[1, 0] * v[:, 0] + R[1, 1] * v[:, 1]], axis=1)

    def evaluate(self, t: Any) -> np.ndarray:
        th = self._theta(t)
        a, b = self.semi_axes
        return self.center[None, :] + self._local(np.stack([a * np.cos(th), b * np.sin(th)], axis=1))

    def derivative(self, t: Any) -> np.ndarray:
        th = self._theta(t)
        a, b = self.semi_axes
        return self.sense * self._local(np.stack([-a * np.sin(th), b * np.cos(th)], axis=1))

    def second_derivative(self, t: Any) -> np.ndarray:
        th = self._theta(t)
        a, b = self.semi_axes
        return -self._local(np.stack([a * np.cos(th), b * np.sin(th)], axis=1))

    def _breakpoints(self) -> np.ndarray:
        # quarter-ellipse pieces starting at the axis ends help the length table with very
        # elongated ellipses (the speed varies fastest there)
        k = np.arange(-8, 9) * (0.5 * math.pi)
        t = self._t_of_angle(k)
        t = t[(t > 1e-9 * self.sweep) & (t < self.sweep * (1.0 - 1e-9))]
        # the same axis end reached from different k differs in the last bits: merge them
        return _dedupe_sorted(np.concatenate([[0.0, self.sweep], t]), 1e5 * self.sweep)

    def _sample_grid(self) -> np.ndarray:
        bp = self._breakpoints()
        pieces = [np.linspace(a, b, 33)[:-1] for a, b in zip(bp[:-1], bp[1:])]
        return np.concatenate(pieces + [[self.sweep]])

    def project(self, points: Any) -> BoundedProjection:
        """Exact foot on the full ellipse (geometry.ellipse's kernel) where it lies on the arc.
        Elsewhere the nearest point is an end point, except for points inside the evolute
        (four normals to the ellipse), which may have an interior local minimum on the arc:
        those go through sampling and safeguarded Newton."""
        P = _points2(points)
        return self._projection_at(P, self._parameters(P))

    def _nearest_signed(self, P: np.ndarray, upper: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        pr = self._projection_at(P, self._parameters(P, upper))
        return pr.distances, pr.parameters

    def _parameters(self, P: np.ndarray, upper: np.ndarray | None = None) -> np.ndarray:
        kernel = _ellipse_kernel()
        if kernel is None:
            return self._project_sampled(P)
        a, b = self.semi_axes
        R = self._R
        dx = P[:, 0] - self.center[0]
        dy = P[:, 1] - self.center[1]
        qx = R[0, 0] * dx + R[1, 0] * dy  # local coordinates R^T (p - c)
        qy = R[0, 1] * dx + R[1, 1] * dy
        cx, cy = kernel(a, b, qx, qy)
        t = self._t_of_angle(np.arctan2(np.asarray(cy) / b, np.asarray(cx) / a))
        if not self.is_closed:
            off = np.flatnonzero(t > self.sweep)
            if off.size:
                Po = P[off]
                t_off = self._nearer_end(Po)
                # inside the evolute: (a x)^(2/3) + (b y)^(2/3) < |a^2 - b^2|^(2/3) (with margin)
                ev = np.cbrt((a * qx[off]) ** 2) + np.cbrt((b * qy[off]) ** 2)
                inside_evolute = ev <= np.cbrt((a * a - b * b) ** 2) * (1.0 + 1e-6)
                if upper is not None:
                    # the full ellipse is nearer than the arc: where even it is beyond the
                    # caller's best distance, the arc cannot win and the end point will do
                    foot = np.sqrt((qx[off] - cx[off]) ** 2 + (qy[off] - cy[off]) ** 2)
                    inside_evolute &= foot < upper[off]
                inner = np.flatnonzero(inside_evolute)
                if inner.size:
                    t_off[inner] = self._project_sampled(Po[inner])
                t[off] = t_off
        return t

    def axis_crossings(self, axis: int, value: float) -> np.ndarray:
        axis = _axis(axis)
        a, b = self.semi_axes
        A = self._R[axis, 0] * a
        B = self._R[axis, 1] * b
        rho = math.hypot(A, B)
        k = (float(value) - self.center[axis]) / rho
        if abs(k) > 1.0 + 1e-14:
            return np.empty(0)
        k = min(max(k, -1.0), 1.0)
        delta = math.atan2(B, A)
        base = math.acos(k)
        theta = np.array([delta + base, delta - base])
        return self._crossings_at_angles(theta)

    def reversed(self) -> "EllipticArc":
        return EllipticArc(self.center, self.semi_axes, self.rotate_deg, self.end_angle, self.start_angle, self.name)

    def transformed(self, rotate_deg: float = 0.0, pivot: Any = (0.0, 0.0), translate: Any = (0.0, 0.0)) -> "EllipticArc":
        return EllipticArc(
            _transform_point(self.center, rotate_deg, pivot, translate),
            self.semi_axes,
            self.rotate_deg + float(rotate_deg),
            self.start_angle,
            self.end_angle,
            self.name,
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "type": "elliptic_arc",
            "center": self.center.tolist(),
            "semi_axes": self.semi_axes.tolist(),
            "rotate_deg": self.rotate_deg,
            "start_angle": math.degrees(self.start_angle),
            "end_angle": math.degrees(self.end_angle),
        }


# ---------------------------------------------------------------------------------------
# B-spline piece
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class BSplineArc(BoundedCurve):
    """Clamped-or-not B-spline (NURBS when ``weights`` are given) plane curve on its full
    parameter domain [knots[degree], knots[-degree-1]]; evaluation by scipy's BSpline."""

    degree: int
    control_points: np.ndarray
    knots: np.ndarray
    weights: np.ndarray | None = None
    name: str = ""
    type = "bspline"
    cost = 8

    def __post_init__(self) -> None:
        owner = f"bspline {self.name!r}"
        p = self.degree
        if isinstance(p, bool) or not isinstance(p, (int, np.integer)) and not (isinstance(p, float) and p.is_integer()):
            raise ValueError(f"{owner}: degree must be a positive integer, got {p!r}")
        p = int(p)
        if p < 1:
            raise ValueError(f"{owner}: degree must be a positive integer, got {p!r}")
        try:
            cp = np.array(self.control_points, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"{owner}: control_points must be a list of [x, y] points") from None
        if cp.ndim != 2 or cp.shape[1] != 2 or not np.all(np.isfinite(cp)):
            raise ValueError(f"{owner}: control_points must be a list of finite [x, y] points, got shape {cp.shape}")
        if np.any(np.abs(cp) > MAX_COORDINATE):
            raise ValueError(f"{owner}: control_points must be within +-{MAX_COORDINATE:g}")
        n = cp.shape[0]
        if n < p + 1:
            raise ValueError(f"{owner}: needs at least degree + 1 = {p + 1} control_points, got {n}")
        try:
            kn = np.array(self.knots, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"{owner}: knots must be a list of numbers") from None
        if kn.ndim != 1 or kn.size != n + p + 1:
            raise ValueError(f"{owner}: knots must have len(control_points) + degree + 1 = {n + p + 1} entries, got {kn.size}")
        if not np.all(np.isfinite(kn)) or np.any(np.diff(kn) < 0.0):
            raise ValueError(f"{owner}: knots must be finite and non-decreasing, got {kn.tolist()}")
        if not kn[-p - 1] > kn[p]:
            raise ValueError(f"{owner}: knots give an empty parameter domain [{kn[p]}, {kn[-p - 1]}]")
        w = None
        if self.weights is not None:
            try:
                w = np.array(self.weights, dtype=float)
            except (TypeError, ValueError):
                raise ValueError(f"{owner}: weights must be a list of numbers") from None
            if w.shape != (n,):
                raise ValueError(f"{owner}: weights must have one entry per control point ({n}), got shape {w.shape}")
            if not np.all(np.isfinite(w)) or np.any(w <= 0.0):
                raise ValueError(f"{owner}: weights must be positive, got {w.tolist()}")
            w.setflags(write=False)
        for arr in (cp, kn):
            arr.setflags(write=False)
        object.__setattr__(self, "degree", p)
        object.__setattr__(self, "control_points", cp)
        object.__setattr__(self, "knots", kn)
        object.__setattr__(self, "weights", w)

    @cached_property
    def _splines(self):
        from scipy.interpolate import BSpline  # lazy: keeps `import geometry` light

        if self.weights is None:
            c = self.control_points
        else:
            c = np.column_stack([self.control_points * self.weights[:, None], self.weights])
        # derivatives by evaluating with nu (piecewise, so repeated interior knots are fine;
        # BSpline.derivative refuses those)
        return BSpline(self.knots, c, self.degree, extrapolate=False)

    @property
    def t_start(self) -> float:
        return float(self.knots[self.degree])

    @property
    def t_end(self) -> float:
        return float(self.knots[-self.degree - 1])

    def _clip(self, t: Any) -> np.ndarray:
        return np.clip(_params(t), self.t_start, self.t_end)

    def _eval_all(self, t: np.ndarray, nu: int):
        s = self._splines
        H = s(t)
        H1 = s(t, nu=1) if nu >= 1 else None
        if nu >= 2:
            H2 = s(t, nu=2) if self.degree >= 2 else np.zeros_like(H)
        else:
            H2 = None
        return H, H1, H2

    def evaluate(self, t: Any) -> np.ndarray:
        t = self._clip(t)
        H, _, _ = self._eval_all(t, 0)
        if self.weights is None:
            return H
        return H[:, :2] / H[:, 2:3]

    def derivative(self, t: Any) -> np.ndarray:
        t = self._clip(t)
        H, H1, _ = self._eval_all(t, 1)
        if self.weights is None:
            return H1
        w = H[:, 2:3]
        X = H[:, :2] / w
        return (H1[:, :2] - X * H1[:, 2:3]) / w

    def second_derivative(self, t: Any) -> np.ndarray:
        t = self._clip(t)
        H, H1, H2 = self._eval_all(t, 2)
        if self.weights is None:
            return H2
        w = H[:, 2:3]
        X = H[:, :2] / w
        X1 = (H1[:, :2] - X * H1[:, 2:3]) / w
        return (H2[:, :2] - 2.0 * X1 * H1[:, 2:3] - X * H2[:, 2:3]) / w

    def _derivatives2(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        t = self._clip(t)
        H, H1, H2 = self._eval_all(t, 2)
        if self.weights is None:
            return H, H1, H2
        w = H[:, 2:3]
        X = H[:, :2] / w
        X1 = (H1[:, :2] - X * H1[:, 2:3]) / w
        X2 = (H2[:, :2] - 2.0 * X1 * H1[:, 2:3] - X * H2[:, 2:3]) / w
        return X, X1, X2

    def _breakpoints(self) -> np.ndarray:
        k = self.knots
        return np.unique(k[(k >= self.t_start) & (k <= self.t_end)])

    def breakpoints(self) -> np.ndarray:
        return self._breakpoints()

    def _sample_grid(self) -> np.ndarray:
        bp = self._breakpoints()
        per = max(6, 2 * (self.degree + 1))
        pieces = [np.linspace(a, b, per + 1)[:-1] for a, b in zip(bp[:-1], bp[1:])]
        return np.concatenate(pieces + [[self.t_end]])

    @cached_property
    def kinks(self) -> np.ndarray:
        """Interior knots of multiplicity >= degree, where the curve may have a corner."""
        k = self.knots
        inner, counts = np.unique(k[(k > self.t_start) & (k < self.t_end)], return_counts=True)
        return inner[counts >= self.degree]


    def _nearest_signed(self, P: np.ndarray, upper: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        pr = self._project(P, upper)
        return pr.distances, pr.parameters

    def project(self, points: Any) -> BoundedProjection:
        """Sampling and safeguarded Newton; where the closest point is a corner (a kink at a
        knot of multiplicity >= degree) the sign of the distance comes from the pseudo-normal
        n_left + n_right there, as at the vertices of a profile."""
        return self._project(_points2(points))

    def _project(self, P: np.ndarray, upper: np.ndarray | None = None) -> BoundedProjection:
        t = self._project_sampled(P, upper)
        pr = self._projection_at(P, t)
        if self.kinks.size and len(P):
            span = self.t_end - self.t_start
            j = np.clip(np.searchsorted(self.kinks, t), 0, self.kinks.size - 1)
            jl = np.clip(j - 1, 0, self.kinks.size - 1)
            near_r = np.abs(t - self.kinks[j]) <= 1e-9 * span
            near_l = np.abs(t - self.kinks[jl]) <= 1e-9 * span
            kk = np.where(near_r, self.kinks[j], self.kinks[jl])
            at = np.flatnonzero(near_r | near_l)
            if at.size:
                h = 1e-9 * span
                pseudo = self.normal(kk[at] - h) + self.normal(kk[at] + h)
                d = P[at] - pr.points[at]
                s = d[:, 0] * pseudo[:, 0] + d[:, 1] * pseudo[:, 1]
                dist = np.abs(pr.distances[at])
                pr.distances[at] = np.where(s < 0.0, -dist, dist)
        return pr

    def trimmed(self, t0: float, t1: float) -> "BSplineArc":
        """The piece on [t0, t1] (inside the domain) as a clamped B-spline of its own: knots
        inserted up to multiplicity ``degree`` at t0 and t1 (exact, scipy's FITPACK insertion,
        in homogeneous coordinates for NURBS), then the control points between them. The
        parameter keeps its values (the piece's domain is [t0, t1]); the name is kept."""
        from scipy.interpolate import insert  # lazy: keeps `import geometry` light

        t0, t1 = float(t0), float(t1)
        if not (self.t_start <= t0 < t1 <= self.t_end):
            raise ValueError(
                f"bspline {self.name!r}: trim range [{t0}, {t1}] must be increasing and inside the domain "
                f"[{self.t_start}, {self.t_end}]"
            )
        p = self.degree
        if self.weights is None:
            coef = self.control_points
        else:
            coef = np.column_stack([self.control_points * self.weights[:, None], self.weights])
        T = self.knots
        C = [coef[:, j].copy() for j in range(coef.shape[1])]
        for x in (t0, t1):
            mult = int(np.count_nonzero(T == x))
            if mult < p:
                T, C, _ = insert(x, (T, C, p), m=p - mult)
                C = [np.asarray(c[: len(T) - p - 1]) for c in C]
        C = np.column_stack(C)
        i_last = int(np.flatnonzero(T == t0)[-1])
        j_first = int(np.flatnonzero(T == t1)[0])
        cp = C[i_last - p : j_first]
        knots = np.concatenate([[t0] * (p + 1), T[(T > t0) & (T < t1)], [t1] * (p + 1)])
        if self.weights is None:
            return BSplineArc(p, cp, knots, None, self.name)
        return BSplineArc(p, cp[:, :2] / cp[:, 2:3], knots, cp[:, 2], self.name)

    def reversed(self) -> "BSplineArc":
        a, b = self.knots[0], self.knots[-1]
        return BSplineArc(
            self.degree,
            self.control_points[::-1],
            (a + b) - self.knots[::-1],
            None if self.weights is None else self.weights[::-1],
            self.name,
        )

    def transformed(self, rotate_deg: float = 0.0, pivot: Any = (0.0, 0.0), translate: Any = (0.0, 0.0)) -> "BSplineArc":
        R = _rotation(float(rotate_deg))
        pivot = np.asarray(pivot, dtype=float)
        cp = (self.control_points - pivot) @ R.T + pivot + np.asarray(translate, dtype=float)
        return BSplineArc(self.degree, cp, self.knots, self.weights, self.name)

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {
            "name": self.name,
            "type": "bspline",
            "degree": self.degree,
            "control_points": self.control_points.tolist(),
            "knots": self.knots.tolist(),
        }
        if self.weights is not None:
            d["weights"] = self.weights.tolist()
        return d


# ---------------------------------------------------------------------------------------
# from the SPEC section 4 edge dict
# ---------------------------------------------------------------------------------------

_EDGE_KEYS = {
    "line": {"name", "type", "start", "end"},
    "arc": {"name", "type", "center", "radius", "start_angle", "end_angle"},
    "elliptic_arc": {"name", "type", "center", "semi_axes", "rotate_deg", "start_angle", "end_angle"},
    "bspline": {"name", "type", "degree", "control_points", "knots", "weights"},
}
_EDGE_REQUIRED = {
    "line": {"start", "end"},
    "arc": {"center", "radius", "start_angle", "end_angle"},
    "elliptic_arc": {"center", "semi_axes", "start_angle", "end_angle"},
    "bspline": {"degree", "control_points", "knots"},
}


def bounded_curve_from_dict(d: Any, where: str = "edge") -> BoundedCurve:
    """Build a bounded curve from a SPEC section 4 profile edge dict (angles in degrees).

    Errors are ``ValueError`` messages starting with ``where`` (e.g. "shape.edges[2]") and
    naming the key."""
    if not isinstance(d, dict):
        raise ValueError(f"{where} must be a table/dict, got {type(d).__name__}")
    d = {k: v for k, v in d.items() if v is not None}
    kind = d.get("type")
    if not isinstance(kind, str) or kind not in _EDGE_KEYS:
        raise ValueError(f"{where}.type must be one of {', '.join(sorted(_EDGE_KEYS))}, got {kind!r}")
    unknown = set(d) - _EDGE_KEYS[kind]
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {', '.join(sorted(unknown))} for type {kind!r}")
    missing = _EDGE_REQUIRED[kind] - set(d)
    if missing:
        raise ValueError(f"{where}: missing key(s) {', '.join(sorted(missing))} for type {kind!r}")
    name = d.get("name", "")
    if not isinstance(name, str):
        raise ValueError(f"{where}.name must be a string, got {name!r}")
    try:
        if kind == "line":
            return Segment(_vec2(d["start"], f"{where}.start"), _vec2(d["end"], f"{where}.end"), name)
        if kind == "arc":
            radius = _number(d["radius"], f"{where}.radius")
            if not radius > 0.0:
                raise ValueError(f"{where}.radius must be positive, got {d['radius']!r}")
            return Arc(
                _vec2(d["center"], f"{where}.center"),
                radius,
                math.radians(_number(d["start_angle"], f"{where}.start_angle")),
                math.radians(_number(d["end_angle"], f"{where}.end_angle")),
                name,
            )
        if kind == "elliptic_arc":
            ax = _vec2(d["semi_axes"], f"{where}.semi_axes")
            if not (ax[0] > 0.0 and ax[1] > 0.0):
                raise ValueError(f"{where}.semi_axes must be positive, got {d['semi_axes']!r}")
            return EllipticArc(
                _vec2(d["center"], f"{where}.center"),
                ax,
                _number(d.get("rotate_deg", 0.0), f"{where}.rotate_deg"),
                math.radians(_number(d["start_angle"], f"{where}.start_angle")),
                math.radians(_number(d["end_angle"], f"{where}.end_angle")),
                name,
            )
        return BSplineArc(d["degree"], d["control_points"], d["knots"], d.get("weights"), name)
    except ValueError as exc:
        msg = str(exc)
        if msg.startswith(where):
            raise
        raise ValueError(f"{where}: {msg}") from None
