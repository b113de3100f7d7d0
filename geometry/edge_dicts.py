"""Bounded curves from the edge dicts of a ``profile`` scene shape (angles in degrees)."""

from __future__ import annotations

import math
from typing import Any

from .arcs import Arc, EllipticArc
from .bounded_curve import BoundedCurve
from .bspline_arc import BSplineArc
from .segments import Segment
from ._curve_numerics import (
    _number,
    _vec2,
)

__all__ = ["bounded_curve_from_dict"]

# ---------------------------------------------------------------------------------------
# from the edge dict of a profile
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
    """Build a bounded curve from a profile edge dict (angles in degrees).

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
