"""What a face of a solid is, in numbers a user can recognise: its surface type, area, centroid,
outward normal (a flat face) or axis and radius (a cylinder, cone, torus), centre and radius (a
sphere). Computed from the face's own quadrature (exact surfaces, trimmed), so it works alike for
the shapes of a scene and for the faces of a CAD part.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["face_summary", "face_summaries"]

#: quadrature panels across the largest extent of the face
PANELS = 24


def _surface_fields(face) -> dict[str, Any]:
    surface = getattr(face, "surface", None)
    to_dict = getattr(surface, "to_dict", None)
    if surface is None:
        return {"type": "tessellated"}
    if to_dict is None or surface is face:
        return {"type": "freeform"}
    d = dict(to_dict())
    out: dict[str, Any] = {"type": str(d.get("type", type(surface).__name__.lower()))}
    for key in ("axis", "radius", "origin"):
        if key in d:
            out[key] = [float(v) for v in d[key]] if isinstance(d[key], (list, tuple)) else float(d[key])
    return out


def _extent(face) -> float:
    triangles = getattr(face, "triangles", None)
    if triangles is not None:
        pts = np.asarray(triangles, float).reshape(-1, 3)
        return float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)))
    lengths = getattr(face, "lengths", None)
    if lengths is not None:
        return float(max(lengths))
    profile = getattr(face, "profile", None)
    if profile is not None:
        lo, hi = (np.asarray(v, float) for v in profile.bounds)
        return float(np.linalg.norm(hi - lo))
    return 1.0


def face_summary(name: str, face) -> dict[str, Any]:
    """``{"id", "type", "area", "centroid", "normal"}`` plus ``axis`` / ``radius`` / ``origin``
    where the surface has them. ``normal`` is the area-weighted mean outward normal: the normal of a
    flat face, shorter than 1 on a curved one (null when it vanishes, e.g. a closed sphere)."""
    points, weights, normals = face.quadrature(_extent(face) / PANELS)
    points, weights, normals = (np.asarray(v, dtype=float) for v in (points, weights, normals))
    area = float(weights.sum())
    out = {"id": name, **_surface_fields(face), "area": area}
    if area > 0.0:
        out["centroid"] = (weights @ points / area).tolist()
        mean = weights @ normals / area
        out["normal"] = mean.tolist() if np.linalg.norm(mean) > 1e-9 else None
    else:
        out["centroid"], out["normal"] = None, None
    if out["type"] == "freeform" and out["normal"] is not None and np.linalg.norm(out["normal"]) > 1.0 - 1e-9:
        out["type"] = "plane"  # a flat face given by a map (e.g. a revolved line)
    if out["type"] == "plane" and out["normal"] is not None:
        out["normal"] = (np.asarray(out["normal"]) / np.linalg.norm(out["normal"])).tolist()
    return out


def face_summaries(solid) -> list[dict[str, Any]]:
    """:func:`face_summary` of every face of a solid (``solid.faces``: name -> face)."""
    return [face_summary(name, face) for name, face in solid.faces.items()]
