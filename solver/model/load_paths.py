"""Load paths: how each boundary condition's value varies with the load parameter t >= 0.

A :class:`LoadPath` is a piecewise-linear factor f(t) through given points (held at its last value
after the last point). A boundary condition or load follows a path (its value times f(t)), one
path per component, or, without a path, a ramp from 0 at t = 0 to 1 at the end of the run. The
run solves the load steps :meth:`LoadHistory.times`: ``steps_per_unit`` per unit of t, plus every
corner of every path (the turning points of a cycle are always solved).

:func:`cycle_points` generates the points of a cyclic path (a sampled sine about a mean: with 4
points per cycle, the triangle wave mean -> mean + amplitude -> mean -> mean - amplitude -> mean).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["LoadPath", "LoadHistory", "cycle_points", "RAMP"]

#: the factor name of a condition without a path: 0 at t = 0, 1 at the end of the run
RAMP = ""


@dataclass(frozen=True)
class LoadPath:
    """Piecewise-linear factor through ``points`` (k, 2) of (t, factor), t increasing from >= 0."""

    name: str
    points: np.ndarray

    def __post_init__(self):
        p = np.array(self.points, dtype=float).reshape(-1, 2)
        if len(p) < 1 or not np.isfinite(p).all():
            raise ValueError(f"load path {self.name!r}: points must be finite [t, factor] pairs")
        if p[0, 0] < 0.0 or np.any(np.diff(p[:, 0]) <= 0.0):
            raise ValueError(f"load path {self.name!r}: t must start at 0 or later and increase strictly")
        p.setflags(write=False)
        object.__setattr__(self, "points", p)

    @property
    def end(self) -> float:
        return float(self.points[-1, 0])

    def factor(self, t) -> np.ndarray:
        """f(t) (same shape as t): linear between points, the first value before the first point,
        the last after the last."""
        return np.interp(t, self.points[:, 0], self.points[:, 1])


def cycle_points(amplitude: float, cycles: float, points_per_cycle: int = 4, mean: float = 0.0,
                 start: float = 0.0, period: float = 1.0) -> np.ndarray:
    """Points (k, 2) of a cyclic path: 0 at t = 0, a ramp to ``mean`` at ``start`` (when start > 0),
    then mean + amplitude sin(2 pi (t - start) / period) sampled at ``points_per_cycle`` points per
    cycle for ``cycles`` cycles (a whole number of samples: rounded to the nearest)."""
    if not points_per_cycle >= 2:
        raise ValueError("points_per_cycle must be at least 2")
    if not (period > 0.0 and cycles > 0.0 and start >= 0.0):
        raise ValueError("period and cycles must be positive and start non-negative")
    n = max(int(round(cycles * points_per_cycle)), 1)
    k = np.arange(n + 1)
    t = start + k * period / points_per_cycle
    f = mean + amplitude * np.sin(2.0 * math.pi * k / points_per_cycle)
    f = np.where(np.abs(f - mean) < 1e-12 * max(abs(amplitude), 1e-300), mean, f)  # exact zeros of the sine
    pts = np.column_stack([t, f])
    if start > 0.0:
        pts = np.vstack([[0.0, 0.0], pts])
    return pts


@dataclass(frozen=True)
class LoadHistory:
    """The paths of a scene and which path each condition follows.

    ``assignments[j]`` for boundary condition j: ``None`` (a ramp to the end of the run), or a
    tuple of path names: one (every component follows it) or one per component."""

    paths: dict = field(default_factory=dict)  # name -> LoadPath
    assignments: tuple = ()
    steps_per_unit: int = 10
    #: why the run keeps a history where the scene gives no path (empty: the scene's paths)
    reason: str = ""

    @property
    def end(self) -> float:
        """The end of the run: the largest t of any path."""
        ends = [p.end for p in self.paths.values()]
        return max(ends) if ends and max(ends) > 0.0 else 1.0

    def times(self) -> np.ndarray:
        """The t of every load step: k / steps_per_unit up to the end, with every path's corners."""
        end = self.end
        n = max(int(math.ceil(end * self.steps_per_unit - 1e-9)), 1)
        t = np.concatenate([np.arange(1, n + 1) / self.steps_per_unit] + [p.points[:, 0] for p in self.paths.values()])
        t = np.sort(t[(t > 0.0) & (t <= end * (1.0 + 1e-12))])
        keep = np.concatenate([[True], np.diff(t) > 1e-9 * end])
        t = t[keep]
        t[-1] = end
        return t

    def factor(self, name: str, t) -> np.ndarray:
        """The factor named ``name`` at t (RAMP: t / end)."""
        if name == RAMP:
            return np.clip(np.asarray(t, dtype=float) / self.end, 0.0, 1.0)
        return self.paths[name].factor(t)

    def names_of(self, j: int, components: int) -> tuple[str, ...]:
        """The factor name of each of the ``components`` components of condition j."""
        names = self.assignments[j] if j < len(self.assignments) else None
        if not names:
            return (RAMP,) * components
        if len(names) == 1:
            return (names[0],) * components
        return tuple(names)
