"""Faces named by geometry in a 3D scene: a boundary condition's ``face`` is a face's name (its
id for a CAD part) or a selector table whose keys all have to hold:

- ``normal = [x, y, z]``: a flat face whose outward normal points this way (within 1e-6 in the
  cosine, about 0.08 degrees);
- ``type = "plane" | "cylinder" | "cone" | "sphere" | "torus" | "freeform" | "tessellated"``;
- ``radius = r``: the surface's radius (cylinder, cone at its origin, sphere, torus), to 1e-6 of it;
- ``axis = [x, y, z]``: the surface's axis, either way along it;
- ``nearest = [x, y, z]``: of the faces the other keys leave, the one nearest the point.

A selector must pick exactly one face: none or several is an error that lists the candidates
with their type, area and centroid (``ibfem info PART --faces`` lists every face likewise).
"""

from __future__ import annotations

from typing import Any, Optional

import numpy as np

from ibfem.geometry.solids.face_summary import face_summary

__all__ = ["select_face", "describe"]

_COSINE = 1.0 - 1e-6
_RADIUS = 1e-6


def describe(f: dict[str, Any]) -> str:
    """One face as 'id (type, area A m^2, centroid [x, y, z])'."""
    c = np.asarray(f.get("centroid") or [], dtype=float)
    c = np.where(np.abs(c) > 1e-9 * (1.0 + np.abs(c).max(initial=0.0)), c, 0.0)  # no -5e-18
    centroid = ", ".join(f"{v:.4g}" for v in c)
    extra = f", radius {f['radius']:.6g} m" if isinstance(f.get("radius"), float) else ""
    return f"{f['id']} ({f['type']}{extra}, area {f['area']:.4g} m^2, centroid [{centroid}])"


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    n = float(np.linalg.norm(v))
    if not n > 0.0:
        raise ValueError("a zero vector has no direction")
    return v / n


def _matches(f: dict[str, Any], selector: dict[str, Any]) -> bool:
    if selector.get("type") is not None and f["type"] != selector["type"]:
        return False
    if selector.get("radius") is not None:
        r = f.get("radius")
        if not isinstance(r, float) or abs(r - selector["radius"]) > _RADIUS * max(abs(r), selector["radius"]):
            return False
    if selector.get("axis") is not None:
        axis = f.get("axis")
        if axis is None or abs(float(_unit(axis) @ _unit(selector["axis"]))) < _COSINE:
            return False
    if selector.get("normal") is not None:
        normal = f.get("normal")
        if normal is None or f["type"] != "plane" or float(_unit(normal) @ _unit(selector["normal"])) < _COSINE:
            return False
    return True


def _distance(face, point: np.ndarray) -> float:
    try:
        foot = np.asarray(face.project(point[None]).points, dtype=float).reshape(-1, 3)[0]
        return float(np.linalg.norm(point - foot))
    except (AttributeError, ValueError, NotImplementedError):  # no exact surface: its quadrature points
        points, _, _ = face.quadrature(float(np.linalg.norm(np.ptp(np.asarray(face.triangles).reshape(-1, 3), axis=0))) / 24)
        return float(np.min(np.linalg.norm(np.asarray(points) - point, axis=1)))


def select_face(solid, selector: dict[str, Any], summaries: Optional[list[dict[str, Any]]] = None) -> str:
    """The name of the one face of ``solid`` the selector picks; ValueError (the candidates
    listed) when none or several do."""
    faces = solid.faces
    summaries = summaries if summaries is not None else [face_summary(n, f) for n, f in faces.items()]
    keys = {k: v for k, v in selector.items() if v is not None}
    if not keys:
        raise ValueError("an empty face selector: give normal, nearest, type, radius or axis")
    found = [f for f in summaries if _matches(f, keys)]
    if "nearest" in keys and len(found) > 1:
        point = np.asarray(keys["nearest"], dtype=float)
        d = np.array([_distance(faces[f["id"]], point) for f in found])
        size = max(float(np.sqrt(max(f["area"], 0.0))) for f in found)
        found = [f for f, dk in zip(found, d) if dk <= d.min() + 1e-9 * max(size, 1e-300)]
    if len(found) == 1:
        return found[0]["id"]
    shown = found if found else summaries
    what = "no face matches it" if not found else f"{len(found)} faces match it"
    raise ValueError(f"{what}; {'candidates' if found else 'faces'}: " + "; ".join(describe(f) for f in shown))
