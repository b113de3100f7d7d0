"""Straight segments: the closed-form bounded curve (t is the arc length)."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from .bounded_curve import BoundedCurve, BoundedProjection
from ._curve_numerics import (
    _axis,
    _norm2,
    _params,
    _points2,
    _transform_point,
    _vec2,
)

__all__ = ["Segment", "SegmentBatch"]



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

    @cached_property
    def _nearest_constants(self) -> tuple[float, ...]:
        """(x0, y0, ux, uy, L, x1 - x0, y1 - y0) as floats, for :meth:`_nearest_signed`."""
        L, u = self._frame
        (x0, y0), (x1, y1) = self.p0, self.p1
        return float(x0), float(y0), float(u[0]), float(u[1]), L, float(x1 - x0), float(y1 - y0)

    def _nearest_signed(self, P: np.ndarray, upper: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(signed distance, positive outside; foot parameter) of points P (n, 2) within 1e120
        of the segment (a profile's query points are: Profile._pull_in), whose squared
        differences cannot overflow: no overflow check (the same numbers as with it)."""
        return _nearest_signed(P, *self._nearest_constants)

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


def _nearest_signed(P: np.ndarray, x0, y0, ux, uy, L, ex, ey) -> tuple[np.ndarray, np.ndarray]:
    """Segment._nearest_signed of the segments whose constants (x0, y0, ux, uy, L, x1 - x0,
    y1 - y0) are given: floats (one segment: (n,) answers) or (m, 1) columns (m segments:
    (m, n) answers, row by row the same numbers as each segment's alone)."""
    dx = P[:, 0] - x0
    dy = P[:, 1] - y0
    t = dx * ux
    t += dy * uy
    np.maximum(t, 0.0, out=t)  # np.clip(t, 0, L), without its wrapper's overhead on short arrays
    np.minimum(t, L, out=t)
    f = t / L
    rx = dx - f * ex
    ry = dy - f * ey
    side = rx * uy
    side -= ry * ux
    np.multiply(rx, rx, out=rx)
    np.multiply(ry, ry, out=ry)
    rx += ry
    dist = np.sqrt(rx, out=rx)
    np.negative(dist, out=dist, where=side < 0.0)
    return dist, t


class SegmentBatch:
    """Several segments' :meth:`Segment._nearest_signed` in one pass of (m, n) arrays (a
    profile's straight edges: one set of array operations for all of them, whatever their
    number; the same numbers as each segment's own)."""

    def __init__(self, segments: list[Segment]) -> None:
        self.columns = [np.array([s._nearest_constants[j] for s in segments])[:, None] for j in range(7)]

    def nearest_signed(self, P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(signed distances (m, n), foot parameters (m, n)) of points P (n, 2), as
        :meth:`Segment._nearest_signed` of each segment."""
        return _nearest_signed(P, *self.columns)
