"""The 2D profile shapes of a scene file built from their plain dicts.

``profile_from_shape(d)`` turns ``{"type": "rectangle", "min": [...], "max": [...]}`` (and
half_disk, disk, half_ellipse, polygon, profile) into a :class:`geometry.profile.Profile`
with their documented edge names. Every shape also takes ``rotate_deg`` (about ``pivot``, default
[0, 0]) and then ``translate``. Bad input raises ``ValueError`` whose message names the key
as ``shape.<key>`` (the scene loader prefixes the file name). Keys set to ``None`` count as
absent (pydantic models dumped with defaults).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ._base import MAX_COORDINATE
from ._curve_numerics import _number, _vec2
from .arcs import Arc, EllipticArc
from .bounded_curve import BoundedCurve
from .edge_dicts import bounded_curve_from_dict
from .segments import Segment
from .profile import Profile

__all__ = ["profile_from_shape", "SHAPE_TYPES"]

_COMMON = {"type", "rotate_deg", "pivot", "translate"}
_KEYS = {
    "rectangle": {"min", "max"},
    "disk": {"center", "radius"},
    "half_disk": {"center", "radius", "side"},
    "half_ellipse": {"center", "semi_axes", "side"},
    "polygon": {"points", "edge_names"},
    "profile": {"edges", "holes"},
}
_OPTIONAL = {"edge_names", "holes"}
SHAPE_TYPES = tuple(sorted(_KEYS))

# direction (angle) of the half that is kept
_SIDES = {"below": -0.5 * math.pi, "above": 0.5 * math.pi, "left": math.pi, "right": 0.0}


def _positive(d: dict, key: str, where: str) -> float:
    x = _number(d[key], f"{where}.{key}")
    if not x > 0.0:
        raise ValueError(f"{where}.{key} must be positive, got {d[key]!r}")
    if x > MAX_COORDINATE:
        raise ValueError(f"{where}.{key} must be at most {MAX_COORDINATE:g} (squared distances would overflow), got {d[key]!r}")
    return x


def _side(d: dict, where: str) -> float:
    side = d["side"]
    if not isinstance(side, str) or side not in _SIDES:
        raise ValueError(f"{where}.side must be one of below, above, left, right, got {side!r}")
    return _SIDES[side]


def _rectangle(d: dict, w: str) -> list[list[BoundedCurve]]:
    lo = _vec2(d["min"], f"{w}.min")
    hi = _vec2(d["max"], f"{w}.max")
    if not (hi[0] > lo[0] and hi[1] > lo[1]):
        raise ValueError(f"{w}.max must exceed {w}.min in both coordinates, got min {lo.tolist()}, max {hi.tolist()}")
    (x0, y0), (x1, y1) = lo, hi
    return [
        [
            Segment((x0, y0), (x1, y0), "bottom"),
            Segment((x1, y0), (x1, y1), "right"),
            Segment((x1, y1), (x0, y1), "top"),
            Segment((x0, y1), (x0, y0), "left"),
        ]
    ]


def _disk(d: dict, w: str) -> list[list[BoundedCurve]]:
    c = _vec2(d["center"], f"{w}.center")
    r = _positive(d, "radius", w)
    return [[Arc(c, r, 0.0, 2.0 * math.pi, "boundary")]]


def _half_disk(d: dict, w: str) -> list[list[BoundedCurve]]:
    c = _vec2(d["center"], f"{w}.center")
    r = _positive(d, "radius", w)
    psi = _side(d, w)
    arc = Arc(c, r, psi - 0.5 * math.pi, psi + 0.5 * math.pi, "arc")
    # the flat closes the arc: from its end back to its start (exact shared end points)
    flat = Segment(arc.end, arc.start, "flat")
    return [[arc, flat]]


def _half_ellipse(d: dict, w: str) -> list[list[BoundedCurve]]:
    c = _vec2(d["center"], f"{w}.center")
    ax = _vec2(d["semi_axes"], f"{w}.semi_axes")
    if not (ax[0] > 0.0 and ax[1] > 0.0):
        raise ValueError(f"{w}.semi_axes must be positive, got {d['semi_axes']!r}")
    psi = _side(d, w)
    # parametric angle of the kept side's pole equals its polar angle on the axes
    arc = EllipticArc(c, ax, 0.0, psi - 0.5 * math.pi, psi + 0.5 * math.pi, "arc")
    flat = Segment(arc.end, arc.start, "flat")
    return [[arc, flat]]


def _polygon(d: dict, w: str) -> list[list[BoundedCurve]]:
    try:
        pts = np.array(d["points"], dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{w}.points must be a list of [x, y] points, got {d['points']!r}") from None
    if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 3:
        raise ValueError(f"{w}.points must be a list of at least 3 [x, y] points, got {d['points']!r}")
    if not np.all(np.isfinite(pts)):
        raise ValueError(f"{w}.points must be finite, got {d['points']!r}")
    if np.allclose(pts[0], pts[-1]) and len(pts) > 3:
        pts = pts[:-1]  # an explicitly closed list
    n = len(pts)
    names = d.get("edge_names")
    if names is None:
        names = [f"e{i}" for i in range(n)]
    else:
        if not isinstance(names, (list, tuple)) or len(names) != n or not all(isinstance(s, str) and s for s in names):
            raise ValueError(f"{w}.edge_names must be a list of {n} non-empty strings (one per edge), got {names!r}")
        if len(set(names)) != n:
            raise ValueError(f"{w}.edge_names must be unique, got {names!r}")
    edges = []
    # consecutive points within the round-off of their coordinates are one vertex typed twice: the
    # edge between them has no direction (make fuzz: [1, 1], [1 + 1e-15, 1] gave far points the
    # inside sign); a real tiny edge (a chamfer of 1e-13 at a unit corner) is kept
    near = 64.0 * np.finfo(float).eps * max(float(np.abs(pts).max()), float(np.max(np.ptp(pts, axis=0))))
    for i in range(n):
        a, b = pts[i], pts[(i + 1) % n]
        if np.array_equal(a, b):
            raise ValueError(f"{w}.points[{i}] and {w}.points[{(i + 1) % n}] coincide ({a.tolist()})")
        if float(np.hypot(*(b - a))) <= near:
            raise ValueError(f"{w}.points[{i}] and {w}.points[{(i + 1) % n}] are {float(np.hypot(*(b - a))):.3g} apart "
                             f"({a.tolist()}, {b.tolist()}), within the round-off of their coordinates: merge them")
        edges.append(Segment(a, b, names[i]))
    return [edges]


def _edge_loop(value: Any, w: str) -> list[BoundedCurve]:
    if not isinstance(value, (list, tuple)) or not value:
        raise ValueError(f"{w} must be a non-empty list of edges")
    out = []
    for i, e in enumerate(value):
        curve = bounded_curve_from_dict(e, f"{w}[{i}]")
        if not curve.name:
            raise ValueError(f"{w}[{i}].name is required")
        out.append(curve)
    return out


def _profile(d: dict, w: str) -> list[list[BoundedCurve]]:
    loops = [_edge_loop(d["edges"], f"{w}.edges")]
    holes = d.get("holes")
    if holes is not None:
        if not isinstance(holes, (list, tuple)):
            raise ValueError(f"{w}.holes must be a list of edge loops")
        for i, h in enumerate(holes):
            loops.append(_edge_loop(h, f"{w}.holes[{i}]"))
    return loops


_BUILDERS = {
    "rectangle": _rectangle,
    "disk": _disk,
    "half_disk": _half_disk,
    "half_ellipse": _half_ellipse,
    "polygon": _polygon,
    "profile": _profile,
}


def profile_from_shape(d: Any, where: str = "shape") -> Profile:
    """Build the :class:`Profile` of a 2D scene shape dict (``onshape`` shapes are
    built by the importers, not here)."""
    if not isinstance(d, dict):
        raise ValueError(f"{where} must be a table/dict, got {type(d).__name__}")
    d = {k: v for k, v in d.items() if v is not None}
    kind = d.get("type")
    if not isinstance(kind, str):
        raise ValueError(f"{where}.type must be a string (one of {', '.join(SHAPE_TYPES)}), got {kind!r}")
    if kind == "onshape":
        raise ValueError(f"{where}.type 'onshape' is built by importers.onshape, not geometry.profile_from_shape")
    if kind not in _KEYS:
        raise ValueError(f"{where}.type must be one of {', '.join(SHAPE_TYPES)}, got {kind!r}")
    unknown = set(d) - _KEYS[kind] - _COMMON
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {', '.join(sorted(unknown))} for shape type {kind!r}")
    missing = _KEYS[kind] - _OPTIONAL - set(d)
    if missing:
        raise ValueError(f"{where}: missing key(s) {', '.join(sorted(missing))} for shape type {kind!r}")
    rotate = _number(d.get("rotate_deg", 0.0), f"{where}.rotate_deg")
    pivot = _vec2(d.get("pivot", (0.0, 0.0)), f"{where}.pivot")
    translate = _vec2(d.get("translate", (0.0, 0.0)), f"{where}.translate")
    loops = _BUILDERS[kind](d, where)
    if rotate != 0.0 or np.any(translate != 0.0):
        loops = [[c.transformed(rotate, pivot, translate) for c in lp] for lp in loops]
    try:
        return Profile(loops)
    except ValueError as exc:
        raise ValueError(f"{where}: {exc}") from None
