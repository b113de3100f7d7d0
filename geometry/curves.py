"""Closed-form curves: the infinite line and the circle.

Both accept (n, 3) query points and, when they lie in the z = 0 plane, (n, 2) points.

Normals:

- ``Line``, 2D query: the direction turned by -90 degrees, ``(d_y, -d_x)``; distances are signed.
  3D query: the unit vector from the closest point toward the query point, so distances are
  the (non-negative) Euclidean distances; on the line itself a fixed unit vector perpendicular
  to the direction is used (distance 0).
- ``Circle``: the in-plane radial direction away from the centre, for 2D and 3D queries alike.
  Distances are signed Euclidean distances: ``hypot(rho - radius, height)``
  with the sign of ``rho - radius``, where ``rho`` is the distance of the query point from the
  circle's axis and ``height`` its distance from the circle's plane (0 for 2D queries, where
  the distance is ``rho - radius``). On the axis a fixed in-plane direction is used.

The private helpers at the bottom (block loop, local frames) are shared with ``ellipse.py``
and ``surfaces.py``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from . import _jit
from ._base import (
    Curve,
    Projection,
    as_points,
    orthonormal_frame,
    positive,
    register_primitive,
    restore_dim,
    signed_hypot,
    unit_vector,
    vector,
)

__all__ = ["Line", "Circle"]


# ---------------------------------------------------------------------------------------
# shared private helpers
# ---------------------------------------------------------------------------------------

# Points are processed in blocks of this many: every temporary of a block stays in the L2
# cache, which makes the long chains of elementwise numpy operations about twice as fast as
# on whole 10^6-point arrays. The loop runs over blocks, never over points.
BLOCK = 1 << 15


def blocks(n: int):
    """Slices covering range(n) in blocks of BLOCK."""
    for start in range(0, n, BLOCK):
        yield slice(start, min(n, start + BLOCK))


def set_fields(obj: Any, **values: Any) -> None:
    """Assign attributes on a frozen dataclass (validated values in __post_init__)."""
    for key, value in values.items():
        object.__setattr__(obj, key, value)


def check_fields(d: Any, owner: str, required: tuple[str, ...], optional: tuple[str, ...] = ()) -> dict:
    """The definition dict minus ``type``; missing or unknown fields raise ValueError."""
    if not isinstance(d, dict):
        raise ValueError(f"{owner}: definition must be a dict, got {type(d).__name__}")
    missing = [k for k in required if k not in d]
    if missing:
        raise ValueError(f"{owner}: missing field {missing[0]!r} (required: {', '.join(required)})")
    allowed = set(required) | set(optional) | {"type"}
    unknown = sorted(k for k in d if k not in allowed)
    if unknown:
        known = ", ".join(required + optional)
        raise ValueError(f"{owner}: unknown field {unknown[0]!r} (fields: {known})")
    kind = d.get("type", owner)
    if str(kind).lower() != owner:
        raise ValueError(f"{owner}: field 'type' must be {owner!r}, got {kind!r}")
    return {k: v for k, v in d.items() if k != "type"}


def result_arrays(n: int, npar: int, out: Projection | None) -> tuple[np.ndarray, ...]:
    """(closest (n, 3), normals (n, 3), distances (n,), parameters (n * npar,)) to write a
    projection into: new arrays, or those of ``out`` (a Projection of n 3D points from an
    earlier call, reused to spare the allocation and the page faults of fresh memory)."""
    if out is None:
        return np.empty((n, 3)), np.empty((n, 3)), np.empty(n), np.empty(n * npar)
    arrays = (out.points, out.normals, out.distances, out.parameters)
    shapes = ((n, 3), (n, 3), (n,), (n,) if npar == 1 else (n, 2))
    for a, shape, name in zip(arrays, shapes, ("points", "normals", "distances", "parameters")):
        if not (isinstance(a, np.ndarray) and a.shape == shape and a.dtype == np.float64 and a.flags.c_contiguous
                and a.flags.writeable):
            raise ValueError(f"out.{name} must be a writeable C-contiguous float64 array of shape {shape}")
    return arrays[0], arrays[1], arrays[2], arrays[3].reshape(-1)


def compiled_projection(kind: str, pts: np.ndarray, prm: np.ndarray, npar: int, out: Projection | None) -> Projection | None:
    """The projection by the compiled kernel (:mod:`geometry._closed_kernels`) on every
    core, or None where the compiled kernels are off (the caller then runs numpy)."""
    mod = _jit.closed_kernel()
    if mod is None:
        return None
    n = len(pts)
    closest, normals, dist, par = result_arrays(n, npar, out)
    code, fn = mod.KINDS[kind], mod.project_range
    _jit.run_ranges(lambda lo, hi: fn(code, pts, lo, hi, prm, closest, normals, dist, par), n)
    return Projection(points=closest, normals=normals, distances=dist, parameters=par if npar == 1 else par.reshape(n, 2))


def kernel_parameters(origin: np.ndarray, frame: np.ndarray, *scalars: float) -> np.ndarray:
    """The compiled kernel's parameter vector: origin, frame rows, the primitive's scalars."""
    return frozen(np.concatenate([origin, np.asarray(frame).ravel(), np.asarray(scalars, dtype=float)]))


def frozen(arr: np.ndarray) -> np.ndarray:
    arr = np.array(arr, dtype=float)
    arr.setflags(write=False)
    return arr


def frame_matrix(e1: np.ndarray, e2: np.ndarray, e3: np.ndarray) -> np.ndarray:
    """Rows e1, e2, e3: ``frame @ v`` gives the local components of v."""
    return frozen(np.array([e1, e2, e3], dtype=float))


def to_local(pts: np.ndarray, frame: np.ndarray, origin: np.ndarray) -> np.ndarray:
    """(3, m) local coordinates ``frame @ (p - origin)`` of an (m, 3) block (rows contiguous).

    The difference is formed first, so the rounding error is relative to |p - origin|, not |p|.
    """
    return frame @ (pts - origin).T


def to_global(local: np.ndarray, frame: np.ndarray, out: np.ndarray) -> None:
    """``out = local^T frame``: (3, m) local components to an (m, 3) output block.

    One BLAS call on the transposed view: much faster than writing the strided output columns
    one by one with elementwise numpy operations.
    """
    np.matmul(local.T, frame, out=out)


def to_global3(c1: Any, c2: Any, c3: Any, frame: np.ndarray, offset: np.ndarray | None, out: np.ndarray) -> None:
    """``out = c1 e1 + c2 e2 + c3 e3 (+ offset)`` for an (m, 3) block; the c's may be scalars.

    The offset rides along as a fourth row of ones times a fourth frame row: a broadcast add
    on the (m, 3) output would cost as much as the whole product.
    """
    m = out.shape[0]
    c = np.empty((3 if offset is None else 4, m))
    c[0] = c1
    c[1] = c2
    c[2] = c3
    if offset is not None:
        c[3] = 1.0
        frame = np.vstack((frame, offset))
    np.matmul(c.T, frame, out=out)


def unit_radial(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """rho = |(x, y)| and the unit direction (x, y)/rho; (1, 0) where rho == 0."""
    with np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore"):
        rho = x * x
        rho += y * y
        np.sqrt(rho, out=rho)  # ten times faster than np.hypot, which is used below where needed
        cx = x / rho
        cy = y / rho
    bad = (rho < 1e-150) | (rho > 1e150)
    if bad.any():
        # the squares under- or overflowed: hypot, after an exact power-of-two rescaling of tiny
        # values (hypot alone keeps too few bits for denormal inputs)
        scale = np.where(rho[bad] < 1e-150, _BIG, 1.0)
        xt = x[bad] * scale
        yt = y[bad] * scale
        rt = np.hypot(xt, yt)
        zero = rt == 0.0
        rt[zero] = 1.0
        xt[zero] = 1.0  # exactly on the axis: the fixed direction (1, 0)
        cx[bad] = xt / rt
        cy[bad] = yt / rt
        rho[bad] = np.where(zero, 0.0, rt / scale)
    return rho, cx, cy


_BIG = 2.0**600


def require_planar_z0(origin: np.ndarray, normal: np.ndarray, owner: str) -> None:
    """2D queries need the curve in the z = 0 plane."""
    if origin[2] != 0.0 or abs(normal[0]) > 1e-14 or abs(normal[1]) > 1e-14:
        raise ValueError(f"{owner}: 2D points need a curve in the z = 0 plane (origin z = 0, normal along z)")


# ---------------------------------------------------------------------------------------
# line
# ---------------------------------------------------------------------------------------


@register_primitive
@dataclass(frozen=True)
class Line(Curve):
    """Infinite line through ``origin`` along the unit ``direction``; parameter = signed
    length along the direction from the origin."""

    origin: tuple[float, ...]
    direction: tuple[float, ...]
    type: ClassVar[str] = "line"

    def __post_init__(self) -> None:
        o = vector(self.origin, "origin", "line", dims=(2, 3))
        d = unit_vector(self.direction, "direction", "line", dims=(2, 3))
        e1, e2 = orthonormal_frame(d)
        frame = frame_matrix(e1, e2, d)
        set_fields(self, origin=tuple(map(float, o)), direction=tuple(map(float, d)))
        set_fields(self, _o=o, _d=d, _frame=frame, _prm=kernel_parameters(o, frame))

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "Line":
        f = check_fields(d, "line", ("origin", "direction"))
        return cls(origin=f["origin"], direction=f["direction"])

    def to_dict(self) -> dict[str, Any]:
        return {"type": "line", "origin": list(self.origin), "direction": list(self.direction)}

    def project(self, points: ArrayLike, out: Projection | None = None) -> Projection:
        """See the module doc; ``out``: a Projection of as many 3D points from an earlier
        call to write the results into (3D queries)."""
        pts, dim = as_points(points, dims=(2, 3))
        o, d = self._o, self._d
        n = len(pts)
        if dim == 2:
            if o[2] != 0.0 or d[2] != 0.0:
                raise ValueError("line: 2D points need a line in the z = 0 plane (origin z = 0, direction z = 0)")
            x = pts[:, 0] - o[0]
            y = pts[:, 1] - o[1]
            t = x * d[0] + y * d[1]
            dist = x * d[1] - y * d[0]  # (p - o) . (d_y, -d_x)
            closest = np.empty((n, 2))
            np.multiply(t, d[0], out=closest[:, 0])
            closest[:, 0] += o[0]
            np.multiply(t, d[1], out=closest[:, 1])
            closest[:, 1] += o[1]
            normals = np.empty((n, 2))
            normals[:, 0] = d[1]
            normals[:, 1] = -d[0]
            return Projection(points=closest, normals=normals, distances=dist, parameters=t)

        fast = compiled_projection("line", pts, self._prm, 1, out)
        if fast is not None:
            return fast
        closest, normals, dist, t = result_arrays(n, 1, out)
        frame = self._frame
        for s in blocks(n):
            x, y, ts = to_local(pts[s], frame, self._o)
            rho, cx, cy = unit_radial(x, y)  # on the line: e1, a fixed perpendicular
            to_global3(cx, cy, 0.0, frame, None, normals[s])
            to_global3(0.0, 0.0, ts, frame, self._o, closest[s])
            t[s] = ts
            dist[s] = rho
        return Projection(points=closest, normals=normals, distances=dist, parameters=t)


# ---------------------------------------------------------------------------------------
# circle
# ---------------------------------------------------------------------------------------


@register_primitive
@dataclass(frozen=True)
class Circle(Curve):
    """Circle of ``radius`` about ``origin`` in the plane normal to ``normal`` (optional in
    the dict, default +z). Parameter: the angle from the frame's first axis
    (``geometry._base.orthonormal_frame(normal)``; the x axis for normal +z) about the normal."""

    origin: tuple[float, ...]
    normal: tuple[float, ...]
    radius: float
    type: ClassVar[str] = "circle"

    def __post_init__(self) -> None:
        o = vector(self.origin, "origin", "circle", dims=(2, 3))
        nrm = unit_vector(self.normal, "normal", "circle")
        r = positive(self.radius, "radius", "circle")
        e1, e2 = orthonormal_frame(nrm)
        frame = frame_matrix(e1, e2, nrm)
        set_fields(self, origin=tuple(map(float, o)), normal=tuple(map(float, nrm)), radius=r)
        set_fields(self, _o=o, _n=nrm, _frame=frame, _prm=kernel_parameters(o, frame, r))

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "Circle":
        f = check_fields(d, "circle", ("origin", "radius"), ("normal",))
        return cls(origin=f["origin"], normal=f.get("normal", [0.0, 0.0, 1.0]), radius=f["radius"])

    def to_dict(self) -> dict[str, Any]:
        return {"type": "circle", "origin": list(self.origin), "normal": list(self.normal), "radius": self.radius}

    def project(self, points: ArrayLike, out: Projection | None = None) -> Projection:
        """See the module doc; ``out``: a Projection of as many 3D points from an earlier
        call to write the results into (3D queries)."""
        pts, dim = as_points(points, dims=(2, 3))
        if dim == 2:
            require_planar_z0(self._o, self._n, "circle")
            out = None
        n = len(pts)
        fast = compiled_projection("circle", pts, self._prm, 1, out)
        if fast is not None:
            return restore_dim(fast, dim)
        R = self.radius
        frame = self._frame
        closest, normals, dist, theta = result_arrays(n, 1, out)
        for s in blocks(n):
            c = to_local(pts[s], frame, self._o)
            rho, cx, cy = unit_radial(c[0], c[1])
            theta[s] = np.arctan2(cy, cx)
            dist[s] = signed_hypot(rho - R, c[2])
            to_global3(cx, cy, 0.0, frame, None, normals[s])
            to_global3(R * cx, R * cy, 0.0, frame, self._o, closest[s])
        return restore_dim(Projection(points=closest, normals=normals, distances=dist, parameters=theta), dim)

