"""Shared numerics of the bounded 2D curves (geometry.bounded_curve and the edge types):
query and parameter arrays, the value checks of curve fields, plane rotations, an
overflow-safe norm, signed distances and vectorised bisection / root finding."""

from __future__ import annotations

import math
import numbers
from typing import Any

import numpy as np

from ._base import MAX_COORDINATE, real_array
from .quadrature import gauss_legendre

_TWO_PI = 2.0 * math.pi

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
    """Two finite real numbers within +-MAX_COORDINATE (bools and strings refused)."""
    mixed = isinstance(value, (list, tuple)) and any(isinstance(v, (bool, np.bool_, str)) for v in value)
    try:
        arr = real_array(value, field)
    except ValueError:
        mixed = True
    if mixed:
        raise ValueError(f"{field} must be a list of 2 numbers, got {value!r}")
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
    """A finite real number (bools and strings refused)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Real, np.ndarray)):
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


def _axis(axis: Any) -> int:
    if axis not in (0, 1):
        raise ValueError(f"axis must be 0 (x) or 1 (y), got {axis!r}")
    return int(axis)
