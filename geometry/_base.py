"""Shared pieces of every exact primitive: the projection result, the primitive base
class with its ``type`` registry, and validation of the plain values a definition is
built from (so a bad definition fails with the field's name, not deep inside numpy).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

__all__ = [
    "Projection",
    "Primitive",
    "Curve",
    "Surface",
    "register_primitive",
    "primitive_from_dict",
    "as_points",
    "restore_dim",
    "vector",
    "unit_vector",
    "positive",
    "finite",
    "orthonormal_frame",
    "signed_lengths",
    "signed_hypot",
]

_REGISTRY: dict[str, type["Primitive"]] = {}

#: largest coordinate or length a curve or control point may take: squares of differences of
#: such numbers stay far from overflow (values beyond are refused with a ValueError)
MAX_COORDINATE = 1e100


@dataclass(frozen=True)
class Projection:
    """Closest points on a primitive, the unit normals there, and signed distances.

    ``distances`` are signed Euclidean distances:
    ``|distances[i]| == |p_i - points[i]|``, with the sign of ``(p_i - points[i]) . normals[i]``
    (the two agree where the foot is interior to a surface; they differ for a curve in 3D off
    its plane and where the foot lies on the boundary of a bounded patch). Arrays have the
    dimension of the query points: (n, 3) for 3D queries, (n, 2) for 2D queries of curves.
    ``parameters`` optionally carries the primitive's parameter(s) at the closest point
    ((n,) for curves, (n, 2) for surfaces) where the primitive has one.
    """

    points: np.ndarray
    normals: np.ndarray
    distances: np.ndarray
    parameters: np.ndarray | None = None


class Primitive(ABC):
    """An exact, immutable CAD primitive.

    Subclasses are frozen dataclasses registered under their ``type`` name with
    :func:`register_primitive`; they build themselves from a plain dict with
    :meth:`from_dict` (validating every field) and write it back with :meth:`to_dict`.
    """

    type: ClassVar[str]
    kind: ClassVar[str]  # "curve" or "surface"

    @classmethod
    @abstractmethod
    def from_dict(cls, d: dict[str, Any]) -> "Primitive":
        """Build from the plain dict; raise ``ValueError`` naming the field on bad input."""

    @abstractmethod
    def to_dict(self) -> dict[str, Any]:
        """The plain dict (``type`` included), JSON-serialisable, round-trips through from_dict."""

    @abstractmethod
    def project(self, points: ArrayLike) -> Projection:
        """Closest points, unit normals and signed distances for an (n, 3) array of points
        (curves also accept (n, 2), meaning the z = 0 plane). Vectorised over n.

        :raises ValueError: ``points`` is not an array of that shape; or, for B-spline curves
            and surfaces (and sweeps of B-splines), a row holds NaN or an infinite coordinate
            (the message names the row)."""

    def signed_distance(self, points: Any) -> np.ndarray:
        return self.project(points).distances


class Curve(Primitive):
    kind: ClassVar[str] = "curve"


class Surface(Primitive):
    kind: ClassVar[str] = "surface"


def register_primitive(cls: type[Primitive]) -> type[Primitive]:
    """Class decorator: make ``cls`` buildable by :func:`primitive_from_dict`."""
    name = cls.type
    if name in _REGISTRY and _REGISTRY[name] is not cls:
        raise RuntimeError(f"primitive type {name!r} registered twice")
    _REGISTRY[name] = cls
    return cls


def primitive_from_dict(d: Any) -> Primitive:
    """Build any primitive from its plain dict; ``d["type"]`` selects it.

    :raises ValueError: ``d`` is not a dict, its ``type`` is unknown (the message lists the
        known types), or a field is missing or invalid (a zero vector, a negative radius, a
        minor radius above the major one, ...): the message names the field."""
    if not isinstance(d, dict):
        raise ValueError(f"primitive definition must be a dict, got {type(d).__name__}")
    kind = d.get("type")
    if kind is None:
        raise ValueError("primitive definition: missing field 'type'")
    cls = _REGISTRY.get(str(kind).lower())
    if cls is None:
        known = ", ".join(sorted(_REGISTRY))
        raise ValueError(f"primitive definition: field 'type' = {kind!r} is not one of: {known}")
    return cls.from_dict(d)


# ---------------------------------------------------------------------------------------
# validation of plain values
# ---------------------------------------------------------------------------------------


def _where(field: str, owner: str | None) -> str:
    return f"{owner}: field {field!r}" if owner else f"field {field!r}"


def vector(value: Any, field: str, owner: str | None = None, dims: tuple[int, ...] = (3,),
           position: bool = True) -> np.ndarray:
    """A finite vector as float64; 2-vectors are padded with z = 0 when 3 is wanted and 2 allowed.
    A ``position`` (an origin) must lie within +-MAX_COORDINATE: query points minus it are
    squared (a direction of any length is normalised by :func:`unit_vector`)."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{_where(field, owner)} must be a list of numbers, got {value!r}") from None
    if arr.ndim != 1 or arr.shape[0] not in dims:
        want = " or ".join(str(k) for k in dims)
        raise ValueError(f"{_where(field, owner)} must have {want} components, got {value!r}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{_where(field, owner)} must be finite, got {value!r}")
    if position and np.any(np.abs(arr) > MAX_COORDINATE):
        raise ValueError(f"{_where(field, owner)} must be within +-{MAX_COORDINATE:g} (squared distances would "
                         f"overflow), got {value!r}")
    if arr.shape[0] == 2 and 3 in dims:
        arr = np.array([arr[0], arr[1], 0.0])
    arr = arr.copy()
    arr.setflags(write=False)
    return arr


def unit_vector(value: Any, field: str, owner: str | None = None, dims: tuple[int, ...] = (3,)) -> np.ndarray:
    """A vector normalised to unit length; a zero (or denormal) vector is rejected."""
    arr = np.array(vector(value, field, owner, dims, position=False))
    big = float(np.max(np.abs(arr)))
    if big > 1e150:  # the squares would overflow: scale first (exact, a power of two)
        arr = arr * 2.0 ** -math.frexp(big)[1]
    norm = float(np.linalg.norm(arr))
    if not norm > 1e-300 or not math.isfinite(norm):
        raise ValueError(f"{_where(field, owner)} must be a non-zero vector, got {value!r}")
    arr = arr / norm
    arr.setflags(write=False)
    return arr


def finite(value: Any, field: str, owner: str | None = None) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{_where(field, owner)} must be a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{_where(field, owner)} must be finite, got {value!r}")
    return x


def positive(value: Any, field: str, owner: str | None = None) -> float:
    x = finite(value, field, owner)
    if not x > 0.0:
        raise ValueError(f"{_where(field, owner)} must be positive, got {value!r}")
    if x > MAX_COORDINATE:
        raise ValueError(
            f"{_where(field, owner)} must be at most {MAX_COORDINATE:g} (squared distances would overflow), got {value!r}"
        )
    return x


def as_points(points: Any, dims: tuple[int, ...] = (3,), name: str = "points", finite: bool = False) -> tuple[np.ndarray, int]:
    """Query points as a C-contiguous float64 (n, 3) array, and the dimension they came in.

    A single point (shape (d,)) is accepted and treated as n = 1. 2D points (allowed for
    curves) are lifted to z = 0; :func:`restore_dim` drops z again on the way out. With
    ``finite`` a NaN or infinite coordinate is an error (where a search would otherwise
    return an arbitrary point for it; closed forms just propagate NaN).
    """
    arr = real_array(points, name)
    if arr.ndim == 1:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] not in dims:
        want = " or ".join(f"(n, {k})" for k in dims)
        raise ValueError(f"{name} must have shape {want}, got {np.shape(points)}")
    dim = arr.shape[1]
    if finite and not np.isfinite(arr).all():
        row = int(np.flatnonzero(~np.isfinite(arr).all(axis=1))[0])
        raise ValueError(f"{name} must be finite: row {row} is {arr[row].tolist()}")
    if dim == 2:
        arr = np.column_stack([arr, np.zeros(len(arr))])
    return np.ascontiguousarray(arr), dim


def real_array(values: Any, name: str = "points") -> np.ndarray:
    """``values`` as a float64 array; only real numbers are accepted: integer and float arrays
    (and lists of them) convert, while bool, complex, string and object arrays (and ragged
    lists) raise a ValueError naming ``name`` and what was given, instead of being converted
    silently (``np.asarray(["1"], float)`` and ``np.asarray([True], float)`` would succeed)."""
    if isinstance(values, np.ndarray) and values.dtype == np.float64:
        return values
    try:
        raw = np.asarray(values)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be an array of real numbers, got a ragged or unreadable value") from None
    kind = raw.dtype.kind
    if kind not in "iuf":
        what = {"b": "booleans", "c": "complex numbers", "U": "strings", "S": "bytes", "O": "Python objects"}
        got = what.get(kind, f"dtype {raw.dtype}")
        raise ValueError(f"{name} must be an array of real numbers (int or float), got {got}")
    return np.asarray(raw, dtype=float)


def signed_hypot(s: np.ndarray, h: Any) -> np.ndarray:
    """``sign(s) hypot(s, h)`` (plus where s >= 0): the signed Euclidean distance of a point
    whose offset from its foot is ``s`` along the normal and ``h`` across it (a curve's
    in-plane signed distance and the height above its plane). A square root of the sum of
    squares, with ``np.hypot`` (after an exact power-of-two rescaling of tiny values) where
    the squares under- or overflow."""
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        d = s * s
        d += h * h
        np.sqrt(d, out=d)
    bad = (d < 1e-150) | (d > 1e150)
    if bad.any():
        sb = np.broadcast_to(s, d.shape)[bad]
        hb = np.broadcast_to(h, d.shape)[bad]
        scale = np.where(d[bad] < 1e-150, 2.0**600, 1.0)
        d[bad] = np.hypot(sb * scale, hb * scale) / scale
    np.negative(d, out=d, where=s < 0)
    return d


def signed_lengths(r: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Signed Euclidean distances from the offsets ``r = p - closest`` and
    the normals (both (n, d)): ``|r|`` with the sign of ``r . normal`` (plus where that is 0).
    The length is overflow- and underflow-safe (rows rescaled by their largest component)."""
    d = np.sqrt(np.einsum("ij,ij->i", r, r))
    bad = (d < 1e-150) | (d > 1e150)
    if bad.any():
        rb = r[bad]
        big = np.max(np.abs(rb), axis=1)
        scaled = rb / np.where(big > 0, big, 1.0)[:, None]
        d[bad] = np.where(big > 0, big * np.sqrt(np.einsum("ij,ij->i", scaled, scaled)), 0.0)
    np.negative(d, out=d, where=np.einsum("ij,ij->i", r, normals) < 0)
    return d


def restore_dim(projection: Projection, dim: int) -> Projection:
    """Drop the z column again for 2D queries."""
    if dim == 3:
        return projection
    return Projection(
        points=projection.points[:, :dim],
        normals=projection.normals[:, :dim],
        distances=projection.distances,
        parameters=projection.parameters,
    )


def orthonormal_frame(axis: np.ndarray, reference: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors (e1, e2) completing the unit ``axis`` to a right-handed frame.

    ``reference`` (projected onto the plane normal to axis) fixes e1 when given; otherwise a
    deterministic choice based on the smallest component of the axis.
    """
    axis = np.asarray(axis, dtype=float)
    if reference is not None:
        e1 = reference - np.dot(reference, axis) * axis
        if np.linalg.norm(e1) < 1e-12:
            reference = None
    if reference is None:
        helper = np.zeros(3)
        helper[int(np.argmin(np.abs(axis)))] = 1.0
        e1 = helper - np.dot(helper, axis) * axis
    e1 = e1 / np.linalg.norm(e1)
    e2 = np.cross(axis, e1)
    return e1, e2
