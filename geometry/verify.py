"""Verification of the projection methods on an imported part (thesis section 4.2.7).

Every vertex of a face's tessellation lies on the exact surface. Offsetting it by a small
distance along the exact outward normal and projecting the offset point back must return
the vertex itself, with the same normal; anything else is projection error (or a
tessellation that is not on the surface it claims).

Scales. The default offset is 1e-3 of the part's size (the diagonal of its tessellation's box),
at most 0.1 mm, and on each face at most a fifth of the smallest radius of curvature its
tessellation shows (the angle between neighbouring vertices' normals over their distance): the
offset point must stay on the side of the centre of curvature where the vertex is its nearest
point. An offset given by the caller is used as it is.

Degenerate points. Where the surface's parameterisation is singular (a cone's apex, a B-spline
patch collapsed to a point along one side: ``|S_u x S_v|`` below 1e-4 of ``max(|S_u|, |S_v|)^2``)
the normal has no single value, so the offset test is skipped at those vertices; they are
counted (``singular_vertices``) and still checked to lie on the surface (``max_vertex_distance``).

Tolerances (:func:`tolerances`), per face, in position: ``1e4 eps L`` for surfaces projected in
closed form (L the larger of the part's size and its largest coordinate, eps the float precision:
the round-off of coordinates of that magnitude), ``1e-9`` of the part's size for B-spline and
swept surfaces projected iteratively; in normal, the angle that position tolerance subtends at
the face's offset. The report carries a ``verdict`` ("pass" or "fail") and a ``reason``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["verify_projection", "angle_between", "tolerances", "part_size", "ITERATIVE_SURFACES"]

EPS = float(np.finfo(float).eps)
ROUND_OFF_FACTOR = 1e4  # closed-form projections: position tolerance = factor x eps x L
ITERATIVE_RELATIVE = 1e-9  # iterative projections: position tolerance = this x part size
DEFAULT_RELATIVE_OFFSET = 1e-3  # of the part's size
MAX_OFFSET = 1e-4  # m
CURVATURE_SHARE = 0.2  # of the smallest radius of curvature seen on the face
SINGULAR = 1e-4  # |S_u x S_v| / max(|S_u|, |S_v|)^2 below this: a singular point
#: surfaces whose projection is iterative (Newton on a parameterisation)
ITERATIVE_SURFACES = ("bspline_surface", "sweep")


def angle_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angles (radians) between rows of a and b, accurate for tiny angles (atan2 form)."""
    cross = np.linalg.norm(np.cross(a, b), axis=1)
    dot = np.einsum("ij,ij->i", a, b)
    return np.arctan2(cross, dot)


def _all_vertices(part: Any) -> np.ndarray:
    pts = [np.asarray(f.mesh.vertices, float) for f in part.faces.values()
           if f.mesh is not None and len(f.mesh.vertices)]
    return np.concatenate(pts) if pts else np.zeros((0, 3))


def part_size(part: Any) -> float:
    """Diagonal (m) of the box around every face's tessellation."""
    V = _all_vertices(part)
    return float(np.linalg.norm(np.ptp(V, axis=0))) if len(V) else 0.0


def tolerances(surface: Any, size: float, extent: float, offset: float) -> tuple[float, float]:
    """(position tolerance m, normal tolerance rad) of one face (see the module docstring)."""
    position = ROUND_OFF_FACTOR * EPS * max(size, extent)
    if getattr(surface, "type", None) in ITERATIVE_SURFACES:
        position = max(position, ITERATIVE_RELATIVE * size)
    return position, position / abs(offset)


def _singular(surface: Any, V: np.ndarray, size: float) -> np.ndarray:
    """Vertices at singular points of the surface's parameterisation (see the module docstring)."""
    kind = getattr(surface, "type", None)
    if kind == "cone":
        d = surface.to_dict()
        axis = np.asarray(d["axis"], float)
        apex = np.asarray(d["origin"], float) - axis / np.linalg.norm(axis) * d["radius"] / np.tan(d["half_angle"])
        return np.linalg.norm(V - apex, axis=1) <= 1e-9 * max(size, 1e-300)
    if kind == "bspline_surface":
        _, D = surface.closest_parameters(V)
        su, sv = np.linalg.norm(D[(1, 0)], axis=1), np.linalg.norm(D[(0, 1)], axis=1)
        cross = np.linalg.norm(np.cross(D[(1, 0)], D[(0, 1)]), axis=1)
        return cross <= SINGULAR * np.maximum(su, sv) ** 2
    return np.zeros(len(V), bool)


def _curvature_offset(offset: float, mesh: Any, V: np.ndarray, normals: np.ndarray, keep: np.ndarray) -> float:
    """``offset``, reduced to CURVATURE_SHARE of the smallest radius of curvature the face's
    tessellation shows between neighbouring regular vertices."""
    edges = np.asarray(mesh.faces)[:, [[0, 1], [1, 2], [2, 0]]].reshape(-1, 2)
    edges = edges[keep[edges].all(axis=1)]
    if not len(edges):
        return offset
    length = np.linalg.norm(V[edges[:, 0]] - V[edges[:, 1]], axis=1)
    turn = angle_between(normals[edges[:, 0]], normals[edges[:, 1]])
    ok = length > 0
    kappa = float(np.max(turn[ok] / length[ok], initial=0.0))
    return offset if kappa * abs(offset) <= CURVATURE_SHARE else float(np.sign(offset) * CURVATURE_SHARE / kappa)


def _face_row(face: Any, offset: float, explicit: bool, size: float, extent: float) -> dict:
    V = np.asarray(face.mesh.vertices, dtype=float)
    at_vertex = face.surface.project(V)
    outward = at_vertex.normals * face.orientation
    regular = ~_singular(face.surface, V, size)
    used = offset if explicit else _curvature_offset(offset, face.mesh, V, outward, regular)
    row: dict[str, Any] = {"max_vertex_distance": float(np.max(np.abs(at_vertex.distances))),
                           "singular_vertices": int((~regular).sum()), "offset": used}
    err = nerr = 0.0
    if regular.any():
        Vr, out_r = V[regular], outward[regular]
        back = face.surface.project(Vr + used * out_r)
        err = float(np.max(np.linalg.norm(back.points - Vr, axis=1)))
        nerr = float(np.max(angle_between(back.normals * face.orientation, out_r)))
    position, normal = tolerances(face.surface, size, extent, used)
    row.update(max_error=err, max_normal_error=nerr, tolerance=position, normal_tolerance=normal,
               passed=bool(err <= position and nerr <= normal and row["max_vertex_distance"] <= position))
    if face.vertex_normals is not None and len(face.vertex_normals) == len(V):
        row["max_vertex_normal_deviation"] = float(np.max(angle_between(face.vertex_normals, outward)))
    return row


def _verdict(faces: list[dict]) -> tuple[str, str]:
    failed = [f for f in faces if f["exact"] and f.get("passed") is False]
    if not failed:
        exact = sum(1 for f in faces if f["exact"] and f["max_error"] is not None)
        return "pass", f"all {exact} exact faces within their tolerances"
    def excess(f):
        return max(f["max_error"] / f["tolerance"], f["max_normal_error"] / f["normal_tolerance"],
                   f["max_vertex_distance"] / f["tolerance"])

    worst = max(failed, key=excess)
    return "fail", (f"{len(failed)} exact faces outside their tolerances; worst {worst['id']} ({worst['type']}): "
                    f"position error {worst['max_error']:.3g} m (tolerance {worst['tolerance']:.3g} m), normal error "
                    f"{worst['max_normal_error']:.3g} rad (tolerance {worst['normal_tolerance']:.3g} rad), vertex "
                    f"off the surface by {worst['max_vertex_distance']:.3g} m")


def verify_projection(part: Any, offset: float | None = None) -> dict:
    """Project every tessellated vertex of every exact face, offset along its exact outward
    normal (negative ``offset``: into the solid; None: the default of the module docstring),
    back onto the surface.

    Returns ``{"faces": [{"id", "type", "vertices", "max_error", "max_normal_error", ...}],
    "max_error": float, ...}``. Per exact face: ``max_error`` is the largest distance (m)
    between a projected point and its vertex, ``max_normal_error`` the largest angle (rad)
    between the normal returned for the offset point and the exact outward normal at the vertex,
    ``tolerance`` / ``normal_tolerance`` and ``passed`` the face's acceptance, ``offset`` the
    offset used there, ``singular_vertices`` those skipped. Extra keys: ``exact`` (false for
    tessellation-only faces, whose errors are null), ``max_vertex_distance`` (largest |signed
    distance| of the vertices themselves), ``max_vertex_normal_deviation`` (angle between the CAD
    system's vertex normals, when sent, and the exact outward normals), and at the top level
    ``max_normal_error``, ``offset``, ``size``, ``exact_faces``, ``tessellation_only_faces``,
    ``by_type`` (worst errors per surface type), ``verdict`` ("pass" / "fail") and ``reason``.
    """
    explicit = offset is not None
    V = _all_vertices(part)
    size = float(np.linalg.norm(np.ptp(V, axis=0))) if len(V) else 0.0
    extent = float(np.abs(V).max()) if len(V) else 0.0
    if explicit:
        offset = float(offset)
        if not np.isfinite(offset) or offset == 0.0:
            raise ValueError(f"verify_projection: offset must be a finite non-zero distance, got {offset!r}")
    else:
        offset = min(MAX_OFFSET, DEFAULT_RELATIVE_OFFSET * size) if size > 0 else MAX_OFFSET
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
            row["note"] = "tessellation-only: no exact surface" if face.surface is None else "no tessellation"
            faces.append(row)
            continue
        row.update(_face_row(face, offset, explicit, size, extent))
        faces.append(row)
        err, nerr = row["max_error"], row["max_normal_error"]
        worst, worst_normal = max(worst, err), max(worst_normal, nerr)
        entry["max_error"] = max(entry["max_error"] or 0.0, err)
        entry["max_normal_error"] = max(entry["max_normal_error"] or 0.0, nerr)
    exact = sum(1 for f in faces if f["exact"])
    verdict, reason = _verdict(faces)
    return {"faces": faces, "max_error": worst, "max_normal_error": worst_normal, "offset": offset, "size": size,
            "exact_faces": exact, "tessellation_only_faces": len(faces) - exact, "by_type": by_type,
            "verdict": verdict, "reason": reason}
