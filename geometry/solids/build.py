"""``solid_from_dict``: the 3D scene shape dicts into solids, with errors naming the key
path (``where``) and the value."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .ellipsoid import Ellipsoid, HalfEllipsoid
from .shapes import Box, Cylinder, Extrusion, HalfSphere, Revolution, Sphere, Transformed

__all__ = ["solid_from_dict", "SOLID_TYPES", "rotation_matrix"]

_KEYS = {
    "box": ({"min", "max"}, set()),
    "sphere": ({"center", "radius"}, set()),
    "half_sphere": ({"center", "radius"}, {"side"}),
    "ellipsoid": ({"center", "semi_axes"}, set()),
    "half_ellipsoid": ({"center", "semi_axes"}, {"side"}),
    "cylinder": ({"center", "axis", "radius", "length"}, set()),
    "half_cylinder": ({"center", "axis", "radius", "length"}, {"side"}),
    "extrusion": ({"profile", "height"}, {"z0"}),
    "revolution": ({"profile", "axis_origin", "axis"}, {"angle_deg"}),
}
_COMMON = {"type", "rotate", "pivot", "translate"}
SOLID_TYPES = tuple(sorted(_KEYS))
#: shapes read by importers (CAD parts): not built here
IMPORTED = ("onshape", "step")


def _number(value: Any, where: str, positive: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{where} must be a number, got {value!r}")
    x = float(value)
    if not math.isfinite(x) or (positive and not x > 0):
        raise ValueError(f"{where} must be a {'positive' if positive else 'finite'} number, got {value!r}")
    return x


def _vec3(value: Any, where: str) -> np.ndarray:
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise ValueError(f"{where} must be a list of three numbers [x, y, z], got {value!r}")
    return np.array([_number(v, f"{where}[{k}]") for k, v in enumerate(value)])


def rotation_matrix(axis, angle_deg: float) -> np.ndarray:
    """Right-hand rotation by angle_deg about axis (Rodrigues)."""
    a = np.asarray(axis, float)
    a = a / np.linalg.norm(a)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    t = math.radians(angle_deg)
    return np.eye(3) + math.sin(t) * k + (1 - math.cos(t)) * k @ k


def _side(d: dict, where: str) -> str:
    side = d.get("side", "below")
    if side not in ("below", "above"):
        raise ValueError(f"{where}.side must be 'below' or 'above', got {side!r}")
    return side


def _profile(d: dict, where: str):
    from ..shapes import profile_from_shape

    return profile_from_shape(d["profile"], where=f"{where}.profile")


def _half_cylinder(d: dict, where: str):
    from ..shapes import profile_from_shape

    centre, axis = _vec3(d["center"], f"{where}.center"), _vec3(d["axis"], f"{where}.axis")
    radius, length = _number(d["radius"], f"{where}.radius", True), _number(d["length"], f"{where}.length", True)
    a = axis / max(np.linalg.norm(axis), 1e-300)
    up = np.array([0.0, 0.0, 1.0]) - a[2] * a
    if np.linalg.norm(up) < 1e-9:
        raise ValueError(f"{where}.axis = {d['axis']!r}: a half_cylinder's axis must not be along z (the cut plane's "
                         "normal is the part of z perpendicular to the axis)")
    up /= np.linalg.norm(up)
    w = np.cross(up, a)  # (w, up, a) right-handed: the profile's x along w, y along up, extruded along a
    half = profile_from_shape({"type": "half_disk", "center": [0.0, 0.0], "radius": radius,
                               "side": _side(d, where)}, where=where)
    base = Extrusion(half, -0.5 * length, length)
    rename = {"bottom": "end0", "top": "end1"}
    base.faces = {rename.get(k, k): v for k, v in base.faces.items()}
    return Transformed(base, np.column_stack([w, up, a]), np.zeros(3), centre)


def _build(kind: str, d: dict, where: str):
    if kind == "box":
        lo, hi = _vec3(d["min"], f"{where}.min"), _vec3(d["max"], f"{where}.max")
        if not np.all(hi > lo):
            raise ValueError(f"{where}: max {d['max']!r} must exceed min {d['min']!r} on every axis")
        return Box(lo, hi)
    if kind == "sphere":
        return Sphere(_vec3(d["center"], f"{where}.center"), _number(d["radius"], f"{where}.radius", True))
    if kind == "half_sphere":
        return HalfSphere(_vec3(d["center"], f"{where}.center"), _number(d["radius"], f"{where}.radius", True),
                          _side(d, where))
    if kind in ("ellipsoid", "half_ellipsoid"):
        centre, axes = _vec3(d["center"], f"{where}.center"), _vec3(d["semi_axes"], f"{where}.semi_axes")
        for k in range(3):
            _number(d["semi_axes"][k], f"{where}.semi_axes[{k}]", True)
        if kind == "ellipsoid":
            return Ellipsoid(centre, axes)
        return HalfEllipsoid(centre, axes, _side(d, where))
    if kind == "cylinder":
        return Cylinder(_vec3(d["center"], f"{where}.center"), _vec3(d["axis"], f"{where}.axis"),
                        _number(d["radius"], f"{where}.radius", True), _number(d["length"], f"{where}.length", True))
    if kind == "half_cylinder":
        return _half_cylinder(d, where)
    if kind == "extrusion":
        return Extrusion(_profile(d, where), _number(d.get("z0", 0.0), f"{where}.z0"),
                         _number(d["height"], f"{where}.height", True))
    angle = _number(d.get("angle_deg", 360.0), f"{where}.angle_deg")
    if not 0.0 < angle <= 360.0:
        raise ValueError(f"{where}.angle_deg must lie in (0, 360], got {d.get('angle_deg')!r}")
    axis = _vec3(d["axis"], f"{where}.axis")
    if not np.linalg.norm(axis) > 0:
        raise ValueError(f"{where}.axis must be a non-zero vector, got {d['axis']!r}")
    return Revolution(_profile(d, where), _vec3(d["axis_origin"], f"{where}.axis_origin"), axis, angle)


def _cad_solid(d: dict, where: str, load_part):
    from .part_solid import PartSolid

    if load_part is None:
        raise ValueError(f"{where}.type = {d.get('type')!r}: CAD solids need a part loader (the importers read "
                         "the file; pass load_part to solid_from_dict)")
    unknown = set(d) - {"type", "path", "body"} - _COMMON
    if unknown or "path" not in d:
        raise ValueError(f"{where}: a {d['type']!r} solid takes path and body (and rotate, pivot, translate); "
                         f"got keys {', '.join(sorted(d))}")
    part = load_part(d)
    try:
        return PartSolid(part, d.get("body"))
    except ValueError as err:
        raise ValueError(f"{where}.body: {d['path']}: {err}") from None


def solid_from_dict(shape: Any, where: str = "shape", load_part=None):
    """The solid of a 3D scene shape dict (``rotate = {axis, angle_deg}`` about ``pivot``,
    then ``translate``). ``onshape`` / ``step`` shapes need ``load_part(shape dict) ->
    geometry.Part`` (an importer: geometry reads no files of CAD systems itself)."""
    if not isinstance(shape, dict):
        raise ValueError(f"{where} must be a table, got {type(shape).__name__}")
    d = {k: v for k, v in shape.items() if v is not None}
    kind = d.get("type")
    if kind in IMPORTED:
        solid = _cad_solid(d, where, load_part)
        return _placed(solid, d, where)
    if kind not in _KEYS:
        raise ValueError(f"{where}.type must be one of {', '.join(SOLID_TYPES)}, got {kind!r}")
    required, optional = _KEYS[kind]
    unknown = set(d) - required - optional - _COMMON
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {', '.join(sorted(unknown))} for shape type {kind!r} "
                         f"(known: {', '.join(sorted(required | optional | _COMMON - {'type'}))})")
    missing = required - set(d)
    if missing:
        raise ValueError(f"{where}: missing key(s) {', '.join(sorted(missing))} for shape type {kind!r}")
    return _placed(_build(kind, d, where), d, where)


def _placed(solid, d: dict, where: str):
    rotate, translate = d.get("rotate"), d.get("translate")
    if rotate is None and translate is None:
        return solid
    matrix = np.eye(3)
    if rotate is not None:
        if not isinstance(rotate, dict) or set(rotate) - {"axis", "angle_deg"} or not {"axis", "angle_deg"} <= set(rotate):
            raise ValueError(f"{where}.rotate must be a table {{axis = [x, y, z], angle_deg = t}}, got {rotate!r}")
        axis = _vec3(rotate["axis"], f"{where}.rotate.axis")
        if not np.linalg.norm(axis) > 0:
            raise ValueError(f"{where}.rotate.axis must be a non-zero vector, got {rotate['axis']!r}")
        matrix = rotation_matrix(axis, _number(rotate["angle_deg"], f"{where}.rotate.angle_deg"))
    pivot = _vec3(d.get("pivot", [0, 0, 0]), f"{where}.pivot")
    move = _vec3(translate if translate is not None else [0, 0, 0], f"{where}.translate")
    return Transformed(solid, matrix, pivot, move)
