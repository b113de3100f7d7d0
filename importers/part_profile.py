"""2D profiles from any imported ``geometry.Part`` (the ``onshape`` and ``step`` shapes of a
scene file): the builders both importers share.

Two ways to get a closed 2D region with exact edges:

* ``face``: a planar face; its loops become the profile, each edge (line, circle, ellipse,
  B-spline) trimmed by its own end points, named by its edge id;
* ``section``: the section of a prismatic body (every face either a cap perpendicular to the
  extrusion direction or a side face parallel to it: plane, cylinder with its axis along the
  direction, sweep along it) by a plane perpendicular to the extrusion direction, between the
  caps. The section of a prism is its cap translated, so the cap's exact loops are used; each
  section edge is named by the id of the side face it cuts.

2D frame of the plane: the normal ``n`` is the face's outward normal (or the section
``normal``); ``e1`` is ``x_axis`` (default: global x, or global y when x is along n) made
perpendicular to n; ``e2 = n x e1``; the 2D origin is the point of the plane nearest the
global origin. So a face at z = c with outward normal +z gives 2D coordinates (x, y).

Arcs run from the edge's start point to its end point through its mid point (or the middle
of its polyline), so no clockwise flag of the source format is needed.

:func:`profile_from_part_shape` reads the scene shape's keys (``face`` | ``section`` with
``body``, ``x_axis``, ``rotate_deg``, ``pivot``, ``translate``) for an importer that supplies the
loaded part.
"""

from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np

from ibfem.geometry import Part
from ibfem.geometry.bounded import Arc, BSplineArc, EllipticArc, Segment
from ibfem.geometry.profile import Profile

__all__ = ["profile_from_part_shape", "face_profile", "section_profile", "plane_frame", "edge_curve_2d", "vector",
           "SHAPE_KEYS"]

SHAPE_KEYS = ("type", "path", "face", "section", "body", "x_axis", "rotate_deg", "pivot", "translate")
_TWO_PI = 2.0 * math.pi


def vector(value: Any, where: str, n: int = 3) -> np.ndarray:
    """A finite vector of n numbers from scene data, or a ValueError naming ``where``."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{where}: expected a list of {n} numbers, got {value!r}") from None
    if arr.shape != (n,) or not np.all(np.isfinite(arr)):
        raise ValueError(f"{where}: expected a list of {n} finite numbers, got {value!r}")
    return arr


def plane_frame(normal: Any, origin: Any, x_axis: Any = None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(origin2d (3,), e1, e2, n) of the plane through ``origin`` with unit normal n."""
    n = np.asarray(normal, float)
    norm = np.linalg.norm(n)
    if not norm > 0:
        raise ValueError(f"plane normal must be non-zero, got {list(normal)}")
    n = n / norm
    ref = np.array([1.0, 0.0, 0.0]) if x_axis is None else np.asarray(x_axis, float)
    e1 = ref - np.dot(ref, n) * n
    if np.linalg.norm(e1) < 1e-9 * max(np.linalg.norm(ref), 1e-300):
        if x_axis is not None:
            raise ValueError(f"x_axis {np.asarray(x_axis, float).tolist()} is along the plane normal {n.tolist()}")
        ref = np.array([0.0, 1.0, 0.0])
        e1 = ref - np.dot(ref, n) * n
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(n, e1)
    o = np.dot(np.asarray(origin, float), n) * n
    return o, e1, e2, n


class _Frame:
    def __init__(self, o, e1, e2, n):
        self.o, self.e1, self.e2, self.n = o, e1, e2, n

    def to2d(self, p) -> np.ndarray:
        d = np.asarray(p, float) - self.o
        return np.stack([d @ self.e1, d @ self.e2], axis=-1)

    def off_plane(self, p) -> float:
        return float(np.max(np.abs((np.asarray(p, float).reshape(-1, 3) - self.o) @ self.n)))


def _mid_point(edge) -> np.ndarray | None:
    mid = getattr(edge, "mid_point", None)
    if mid is not None:
        return np.asarray(mid)
    pl = edge.polyline
    if len(pl) >= 3:
        return pl[len(pl) // 2]
    return None


def _angles(start, end, mid, center, sense_ccw: bool, closed: bool, to_angle) -> tuple[float, float]:
    a0 = to_angle(start)
    if closed:
        return a0, a0 + (_TWO_PI if sense_ccw else -_TWO_PI)
    a1 = to_angle(end)
    ccw = (a1 - a0) % _TWO_PI
    if mid is not None:
        if (to_angle(mid) - a0) % _TWO_PI < ccw:
            return a0, a0 + ccw
        return a0, a0 - (_TWO_PI - ccw)
    return (a0, a0 + ccw) if sense_ccw else (a0, a0 - (_TWO_PI - ccw))


def edge_curve_2d(part: Part, edge_id: str, frame: _Frame, name: str | None = None):
    """The exact bounded 2D curve of an edge lying in the frame's plane."""
    edge = part.edges[edge_id]
    name = edge_id if name is None else name
    curve = edge.curve
    if curve is None:
        raise ValueError(f"edge {edge_id} is tessellation-only ({edge.curve_type}): no exact 2D profile")
    if edge.start is None or edge.end is None:
        raise ValueError(f"edge {edge_id}: no start/end points in the part's data (geometry missing)")
    scale = max(1.0, float(np.max(np.abs(edge.polyline)))) if len(edge.polyline) else 1.0
    tol = 1e-9 * scale
    pts = np.vstack([edge.start, edge.end] + ([edge.polyline] if len(edge.polyline) else []))
    if frame.off_plane(pts) > tol:
        raise ValueError(f"edge {edge_id} does not lie in the profile plane (off by {frame.off_plane(pts):.3g} m)")
    s2, e2 = frame.to2d(edge.start), frame.to2d(edge.end)
    closed = bool(np.linalg.norm(edge.end - edge.start) <= tol)
    mid = _mid_point(edge)
    m2 = None if mid is None else frame.to2d(mid)
    d = curve.to_dict()
    kind = d["type"]
    if kind == "line":
        return Segment(s2, e2, name)
    if kind == "circle":
        c2 = frame.to2d(np.asarray(d["origin"], float))
        ccw = float(np.dot(np.asarray(d["normal"], float), frame.n)) > 0
        a0, a1 = _angles(s2, e2, m2, c2, ccw, closed, lambda p: math.atan2(p[1] - c2[1], p[0] - c2[0]))
        return Arc(c2, float(d["radius"]), a0, a1, name)
    if kind == "ellipse":
        c2 = frame.to2d(np.asarray(d["origin"], float))
        major = np.asarray(d["major_axis"], float)
        phi = math.atan2(float(major @ frame.e2), float(major @ frame.e1))
        a, b = float(d["major_radius"]), float(d["minor_radius"])
        cph, sph = math.cos(phi), math.sin(phi)

        def param(p):
            u = (p[0] - c2[0]) * cph + (p[1] - c2[1]) * sph
            v = -(p[0] - c2[0]) * sph + (p[1] - c2[1]) * cph
            return math.atan2(v / b, u / a)

        ccw = float(np.dot(np.asarray(d["normal"], float), frame.n)) > 0
        a0, a1 = _angles(s2, e2, m2, c2, ccw, closed, param)
        return EllipticArc(c2, (a, b), math.degrees(phi), a0, a1, name)
    if kind == "bspline_curve":
        cp = np.asarray(d["control_points"], float)
        if frame.off_plane(cp) > tol:
            raise ValueError(f"edge {edge_id}: B-spline control points leave the profile plane")
        arc = BSplineArc(int(d["degree"]), frame.to2d(cp), np.asarray(d["knots"], float), d.get("weights"), name)
        if closed or (np.linalg.norm(arc.start - s2) <= tol and np.linalg.norm(arc.end - e2) <= tol):
            return arc
        if np.linalg.norm(arc.start - e2) <= tol and np.linalg.norm(arc.end - s2) <= tol:
            return arc.reversed()
        raise ValueError(f"edge {edge_id}: trimmed B-spline edges (ends inside the curve's domain) are not supported")
    raise ValueError(f"edge {edge_id}: curve type {edge.curve_type} cannot be placed in a 2D profile")


def _outward_plane(part: Part, face_id: str):
    face = part.faces[face_id]
    if face.surface_type != "PLANE" or face.surface is None:
        raise ValueError(f"face {face_id} is not planar ({face.surface_type})")
    d = face.surface.to_dict()
    return np.asarray(d["origin"], float), np.asarray(d["normal"], float) * face.orientation


def face_profile(part: Part, face_id: str, x_axis: Any = None) -> Profile:
    """Profile of a planar face: its loops, edges named by their Onshape ids."""
    if face_id not in part.faces:
        planar = sorted(f.id for f in part.faces.values() if f.surface_type == "PLANE")
        raise ValueError(f"no face {face_id!r}; planar faces: {', '.join(planar)}")
    origin, normal = _outward_plane(part, face_id)
    frame = _Frame(*plane_frame(normal, origin, x_axis))
    face = part.faces[face_id]
    if not face.loops:
        raise ValueError(f"face {face_id} has no loops in the part's data")
    loops = sorted(face.loops, key=lambda lp: not lp.is_outer)
    curves = [[edge_curve_2d(part, co.edge_id, frame) for co in lp.coedges] for lp in loops]
    return Profile(curves)


def _body(part: Part, body: Any):
    if body is None:
        if len(part.bodies) != 1:
            listing = ", ".join(f"{b.id} ({b.name})" for b in part.bodies.values())
            raise ValueError(f"the part has {len(part.bodies)} bodies: say which with 'body' ({listing})")
        return next(iter(part.bodies.values()))
    for b in part.bodies.values():
        if body in (b.id, b.name):
            return b
    listing = ", ".join(f"{b.id} ({b.name})" for b in part.bodies.values())
    raise ValueError(f"no body {body!r}; bodies: {listing}")


def section_profile(part: Part, origin: Any, normal: Any, body: Any = None, x_axis: Any = None) -> Profile:
    """Section of a prismatic body by the plane (origin, normal); the plane must be
    perpendicular to the extrusion direction and strictly between the caps."""
    b = _body(part, body)
    n = np.asarray(normal, float)
    length = float(np.linalg.norm(n))
    if not (length > 1e-300 and math.isfinite(length)):
        raise ValueError(f"the section normal must be a non-zero finite vector, got {np.asarray(normal).tolist()}")
    n = n / length
    origin = np.asarray(origin, float)
    caps, sides = [], []
    for fid in b.face_ids:
        f = part.faces[fid]
        if f.surface is None:
            raise ValueError(f"body {b.id}: face {fid} is tessellation-only ({f.surface_type}): not a prism")
        d = f.surface.to_dict()
        kind = d["type"]
        if kind == "plane":
            pn = np.asarray(d["normal"], float)
            if abs(abs(float(pn @ n)) - 1.0) < 1e-9:
                caps.append(fid)
                continue
            ok = abs(float(pn @ n)) < 1e-9
        elif kind == "cylinder":
            ok = abs(abs(float(np.asarray(d["axis"], float) @ n)) - 1.0) < 1e-9
        elif kind == "sweep":
            ok = abs(abs(float(np.asarray(d["direction"], float) @ n) / np.linalg.norm(d["direction"])) - 1.0) < 1e-9
        else:
            ok = False
        if not ok:
            raise ValueError(f"body {b.id}: face {fid} ({f.surface_type}) is not parallel to the section normal "
                             f"{n.tolist()}: the body is not a prism along it")
        sides.append(fid)
    if len(caps) != 2:
        raise ValueError(f"body {b.id}: a prism along {n.tolist()} has two caps, found {len(caps)}")
    # the caps' levels from their exact planes (the tessellation may be missing)
    levels = sorted(float(np.asarray(part.faces[c].surface.to_dict()["origin"], float) @ n) for c in caps)
    at = float(origin @ n)
    if not levels[0] < at < levels[1]:
        raise ValueError(f"section plane at {at:.6g} along {n.tolist()} is not between the caps "
                         f"({levels[0]:.6g} and {levels[1]:.6g})")
    cap = caps[0]
    # each cap edge belongs to exactly one side face: name the section edge after it
    side_of = {}
    for fid in sides:
        for lp in part.faces[fid].loops:
            for co in lp.coedges:
                side_of.setdefault(co.edge_id, []).append(fid)
    cap_origin, _ = _outward_plane(part, cap)
    shift = (at - float(cap_origin @ n)) * n
    frame = _Frame(*plane_frame(n, origin, x_axis))
    # the same 2D coordinates measured in the cap's plane (e1, e2 are perpendicular to n):
    # the cap's curves are the section's, translated along n
    frame.o = frame.o - shift
    face = part.faces[cap]
    loops = sorted(face.loops, key=lambda lp: not lp.is_outer)
    curves = []
    for lp in loops:
        loop = []
        for co in lp.coedges:
            owners = side_of.get(co.edge_id, [])
            if len(owners) != 1:
                raise ValueError(f"body {b.id}: cap edge {co.edge_id} borders {len(owners)} side faces (expected 1)")
            loop.append(edge_curve_2d(part, co.edge_id, frame, name=owners[0]))
        curves.append(loop)
    return Profile(curves)


def profile_from_part_shape(shape: dict, where: str, kind: str, load: Callable[[str], Part], path_hint: str,
                            face_id: Callable[[Part, str], str] = lambda part, face: face) -> Profile:
    """The profile of a ``kind`` scene shape (``onshape``, ``step``) on the part ``load(path)``
    gives; ``path_hint`` says what ``path`` names, ``face_id`` resolves a face given by name."""
    if not isinstance(shape, dict):
        raise ValueError(f"{where}: expected a table, got {shape!r}")
    shape = {k: v for k, v in shape.items() if v is not None}
    unknown = sorted(set(shape) - set(SHAPE_KEYS))
    if unknown:
        article = "an" if kind[0] in "aeiou" else "a"
        raise ValueError(f"{where}.{unknown[0]}: unknown key for {article} {kind} shape (known: {', '.join(SHAPE_KEYS)})")
    if "path" not in shape:
        raise ValueError(f"{where}.path: missing ({path_hint})")
    if not isinstance(shape["path"], str) or not shape["path"]:
        raise ValueError(f"{where}.path: expected a file or directory name (a string), got {shape['path']!r}")
    if ("face" in shape) == ("section" in shape):
        raise ValueError(f"{where}: give exactly one of 'face' (a planar face id) or 'section' "
                         f"({{origin, normal}})")
    try:
        part = load(str(shape["path"]))
    except ValueError as exc:  # the importers' format errors included
        raise ValueError(f"{where}.path: {exc}") from None
    except OSError as exc:  # a name too long, a directory without permission, ...
        raise ValueError(f"{where}.path: cannot read {shape['path']!r}: {exc.strerror or exc}") from None
    x_axis = vector(shape["x_axis"], f"{where}.x_axis") if "x_axis" in shape else None
    try:
        if "face" in shape:
            if not isinstance(shape["face"], str):
                raise ValueError(f"expected a face id string, got {shape['face']!r}")
            prof = face_profile(part, face_id(part, shape["face"]), x_axis)
        else:
            prof = _section(shape, where, part, x_axis)
    except ValueError as exc:
        key = "face" if "face" in shape else "section"
        msg = str(exc)
        raise ValueError(msg if msg.startswith(where) else f"{where}.{key}: {msg}") from None
    return _placed(prof, shape, where)


def _section(shape: dict, where: str, part: Part, x_axis) -> Profile:
    sec = shape["section"]
    if not isinstance(sec, dict) or set(sec) - {"origin", "normal"} or "normal" not in sec:
        raise ValueError(f"expected {{origin = [x, y, z], normal = [x, y, z]}}, got {sec!r}")
    o = vector(sec.get("origin", [0.0, 0.0, 0.0]), f"{where}.section.origin")
    n = vector(sec["normal"], f"{where}.section.normal")
    return section_profile(part, o, n, shape.get("body"), x_axis)


def _placed(prof: Profile, shape: dict, where: str) -> Profile:
    rot = shape.get("rotate_deg", 0.0)
    pivot = vector(shape.get("pivot", [0.0, 0.0]), f"{where}.pivot", 2)
    translate = vector(shape.get("translate", [0.0, 0.0]), f"{where}.translate", 2)
    if not isinstance(rot, (int, float)) or isinstance(rot, bool) or not math.isfinite(rot):
        raise ValueError(f"{where}.rotate_deg: expected a number, got {rot!r}")
    if rot or np.any(translate):
        prof = prof.transformed(rot, pivot, translate)
    return prof
