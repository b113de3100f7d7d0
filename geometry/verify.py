"""Verification of the projection methods on an imported part (thesis section 4.2.7).

Every vertex of a face's tessellation lies on the exact surface. Offsetting it by a small
distance along the exact outward normal and projecting the offset point back must return
the vertex itself, with the same normal; anything else is projection error (or a
tessellation that is not on the surface it claims). ``ibfem verify --json`` prints this report.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["verify_projection", "angle_between"]


def angle_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angles (radians) between rows of a and b, accurate for tiny angles (atan2 form)."""
    cross = np.linalg.norm(np.cross(a, b), axis=1)
    dot = np.einsum("ij,ij->i", a, b)
    return np.arctan2(cross, dot)


def verify_projection(part: Any, offset: float = 1e-4) -> dict:
    """Project every tessellated vertex of every exact face, offset by ``offset`` metres
    along its exact outward normal (negative: into the solid), back onto the surface.

    Returns ``{"faces": [{"id", "type", "vertices", "max_error", "max_normal_error", ...}],
    "max_error": float, ...}``. Per exact face: ``max_error`` is the largest
    distance (m) between a projected point and its vertex, ``max_normal_error`` the largest
    angle (rad) between the normal returned for the offset point and the exact outward
    normal at the vertex. Extra keys: ``exact`` (false for tessellation-only faces, whose
    errors are null), ``max_vertex_distance`` (largest |signed distance| of the vertices
    themselves), ``max_vertex_normal_deviation`` (angle between the CAD system's vertex
    normals, when sent, and the exact outward normals), and at the top level
    ``max_normal_error``, ``offset``, ``exact_faces``, ``tessellation_only_faces`` and
    ``by_type`` (worst errors per surface type).
    """
    offset = float(offset)
    if not np.isfinite(offset) or offset == 0.0:
        raise ValueError(f"verify_projection: offset must be a finite non-zero distance, got {offset!r}")
    faces = []
    worst, worst_normal = 0.0, 0.0
    by_type: dict[str, dict] = {}
    for face in part.faces.values():
        mesh = face.mesh
        n_vertices = 0 if mesh is None else int(len(mesh.vertices))
        row: dict[str, Any] = {"id": face.id, "type": face.surface_type, "vertices": n_vertices,
                               "max_error": None, "max_normal_error": None, "exact": face.surface is not None}
        entry = by_type.setdefault(face.surface_type, {"faces": 0, "vertices": 0, "exact": face.surface is not None,
                                                       "max_error": None, "max_normal_error": None})
        entry["faces"] += 1
        entry["vertices"] += n_vertices
        if face.surface is None or n_vertices == 0:
            if face.surface is None:
                row["note"] = "tessellation-only: no exact surface"
            else:
                row["note"] = "no tessellation"
            faces.append(row)
            continue
        V = np.asarray(mesh.vertices, dtype=float)
        at_vertex = face.surface.project(V)
        outward = at_vertex.normals * face.orientation
        moved = V + offset * outward
        back = face.surface.project(moved)
        err = float(np.max(np.linalg.norm(back.points - V, axis=1)))
        nerr = float(np.max(angle_between(back.normals * face.orientation, outward)))
        row.update(max_error=err, max_normal_error=nerr,
                   max_vertex_distance=float(np.max(np.abs(at_vertex.distances))))
        if face.vertex_normals is not None and len(face.vertex_normals) == n_vertices:
            row["max_vertex_normal_deviation"] = float(np.max(angle_between(face.vertex_normals, outward)))
        faces.append(row)
        worst, worst_normal = max(worst, err), max(worst_normal, nerr)
        entry["max_error"] = max(entry["max_error"] or 0.0, err)
        entry["max_normal_error"] = max(entry["max_normal_error"] or 0.0, nerr)
    exact = sum(1 for f in faces if f["exact"])
    return {"faces": faces, "max_error": worst, "max_normal_error": worst_normal, "offset": offset,
            "exact_faces": exact, "tessellation_only_faces": len(faces) - exact, "by_type": by_type}
