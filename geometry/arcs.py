"""Circular and elliptic arcs: t is the angle swept from the start (the parametric angle
for ellipses), in [0, |end_angle - start_angle|]; a sweep of 2 pi is a full circle or
ellipse (one closed edge)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from ._base import MAX_COORDINATE
from .bounded_curve import BoundedCurve, BoundedProjection
from ._curve_numerics import (
    _TWO_PI,
    _axis,
    _dedupe_sorted,
    _norm2,
    _number,
    _params,
    _points2,
    _rotation,
    _transform_point,
    _vec2,
)

__all__ = ["Arc", "EllipticArc"]

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
        return _mod_two_pi(self.sense * (theta - self.start_angle))

    def _nearer_end(self, P: np.ndarray) -> np.ndarray:
        """t of the end point nearer to each point (the start on a tie)."""
        (sx, sy), (ex, ey) = self.start, self.end
        x, y = P[:, 0], P[:, 1]  # column by column: a sum along the rows of (n, 2) is much slower
        ds = (x - sx) ** 2 + (y - sy) ** 2
        de = (x - ex) ** 2 + (y - ey) ** 2
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

    @cached_property
    def _nearest_constants(self) -> tuple[float, ...]:
        """(centre x, centre y, sense, start angle, radius, sweep) as floats, and whether the arc
        is closed, for :meth:`_nearest_signed`."""
        return (float(self.center[0]), float(self.center[1]), self.sense, self.start_angle, self.radius,
                self.sweep, self.is_closed)

    def _nearest_signed(self, P: np.ndarray, upper: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(signed distance, positive outside; foot parameter) of points P (n, 2) within 1e120
        of the centre (a profile's query points are: Profile._pull_in), whose squared
        differences cannot overflow: no overflow check (the same numbers as with it)."""
        cx, cy, sense, start, radius, sweep, closed = self._nearest_constants
        dx = P[:, 0] - cx
        dy = P[:, 1] - cy
        theta = np.arctan2(dy, dx)
        theta -= start
        theta *= sense
        t = _mod_two_pi(theta)
        # foot on the arc: p - c = (rho - r) e_r and n = sense e_r
        np.multiply(dx, dx, out=dx)
        np.multiply(dy, dy, out=dy)
        dx += dy
        sd = np.sqrt(dx, out=dx)
        sd -= radius
        sd *= sense
        if not closed:
            out = (t > sweep).nonzero()[0]
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


def _mod_two_pi(a: np.ndarray) -> np.ndarray:
    """np.mod(a, 2 pi), bitwise: where every value lies in [-2 pi, 2 pi) (angle differences of
    arctan2's range) the remainder is a, or a + 2 pi below zero (np.mod's own result there, +0
    for -0), ten times faster than np.mod's general division."""
    a = np.asarray(a, dtype=float)
    if a.size and -_TWO_PI <= a.min() and a.max() < _TWO_PI:
        return np.where(a < 0.0, a + _TWO_PI, a) + 0.0
    return np.mod(a, _TWO_PI)
