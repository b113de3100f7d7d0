"""Cached Onshape responses -> :class:`geometry.Part`.

``load_part(directory)`` reads ``tessellatedfaces.json``, ``tessellatededges.json`` (optional),
``bodydetails.json`` and ``source.json`` (optional) as written by the client (or shipped in
``fixtures/onshape``), in either wire format, and builds one ``Part``:

* faces: exact surface primitive (PLANE, CYLINDER, CONE, SPHERE, TORUS, SWEEP) or none
  (SPUN, BSURFACE, OFFSET, BLEND, OTHER, UNKNOWN and unknown names: tessellation-only,
  reported in ``Part.warnings``), the facets welded into one indexed ``trimesh.Trimesh``,
  the outward orientation relative to the primitive's own normal, loops of coedges;
* edges: exact curve (LINE, CIRCLE, ELLIPSE, BCURVE) or none (ICURVE, OTHER, ...), the
  tessellated polyline, end points and length from the edge geometry.

Orientation: the body-details ``orientation`` flag is read as the Parasolid face sense (true:
outward normal = surface normal) and checked against the facet normals, area-weighted over
the face; where they disagree the facet normals win and a warning is recorded. SWEEP faces
take their orientation from the facets only (Onshape does not document the sweep normal).

Bad input raises :class:`importers.OnshapeFormatError` naming the file and the JSON path.

B-spline curves (BCURVE, and the profile of a SWEEP) -- accepted ``controlPoints`` layouts:

* flat ``[x0, y0, z0, x1, ...]`` (3n numbers): non-rational, or rational with a separate
  ``weights`` list of n numbers;
* flat ``[x0 w0, y0 w0, z0 w0, w0, ...]`` (4n numbers) when ``isRational`` is true and no
  ``weights`` are given: homogeneous coordinates as Parasolid stores rational vertices. The
  other reading of 4n numbers, Cartesian ``(x, y, z, w)``, is also tried when the weights are
  not all 1, and whichever puts the edge's own points (geometry start/mid/quarter/end points
  and tessellation) or the sweep face's vertices on the curve is used (noted on the edge/face);
* nested ``[[x, y, z], ...]`` or ``[[x, y, z, w], ...]`` (same rules) and ``[{x, y, z}, ...]``.

The count is checked against the degree and knots: n = len(knots) - degree - 1 (periodic
curves included: Onshape/Parasolid send the full knot vector); knots must not decrease.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
from pydantic import TypeAdapter, ValidationError

from ibfem.geometry import Body, Coedge, Edge, Face, Loop, Part, primitive_from_dict

from .. import OnshapeFormatError
from . import models as M

__all__ = ["load_part", "parse_part", "bcurve_control_points", "EXACT_SURFACES", "EXACT_CURVES"]

FACES_FILE = "tessellatedfaces.json"
EDGES_FILE = "tessellatededges.json"
DETAILS_FILE = "bodydetails.json"
SOURCE_FILE = "source.json"

EXACT_SURFACES = ("PLANE", "CYLINDER", "CONE", "SPHERE", "TORUS", "SWEEP")
TESSELLATION_ONLY_SURFACES = ("SPUN", "BSURFACE", "OFFSET", "BLEND", "OTHER", "UNKNOWN")
EXACT_CURVES = ("LINE", "CIRCLE", "ELLIPSE", "BCURVE")
TESSELLATION_ONLY_CURVES = ("ICURVE", "OTHER", "UNKNOWN")
LEGACY_NAMES = {"REVOLVED": "SPUN", "EXTRUDED": "SWEEP"}
# surface types whose Onshape normal is the own normal of the primitive we build
FLAG_CONVENTION_KNOWN = ("PLANE", "CYLINDER", "CONE", "SPHERE", "TORUS")


class _Fail(Exception):
    """Internal: a problem at a JSON path, turned into OnshapeFormatError with the file name."""

    def __init__(self, path: str, message: str):
        super().__init__(f"{path}: {message}")
        self.path, self.message = path, message


# ---------------------------------------------------------------------------------------
# reading files
# ---------------------------------------------------------------------------------------


def _read_json(directory: Path, name: str, required: bool = True) -> Any:
    path = directory / name
    if not path.is_file():
        if required:
            raise OnshapeFormatError(f"{directory}: missing {name} (expected the cached Onshape response)")
        return None
    try:
        text = path.read_bytes().decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise OnshapeFormatError(f"{path}: not a UTF-8 text file (byte at offset {exc.start}); the Onshape "
                                 "cache is damaged: import it again") from None
    except OSError as exc:
        raise OnshapeFormatError(f"{path}: cannot read ({exc.strerror or exc})") from None
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        what = "truncated or invalid JSON" if exc.pos >= len(text.rstrip()) - 1 else "invalid JSON"
        raise OnshapeFormatError(f"{name}: {what} at line {exc.lineno} column {exc.colno}: {exc.msg}") from None
    except RecursionError:
        raise OnshapeFormatError(f"{path}: nested too deeply to read: not an Onshape response") from None
    except ValueError as exc:  # e.g. an integer of more than 4300 digits
        raise OnshapeFormatError(f"{path}: cannot read a value: {str(exc).split(';')[0]}") from None


def _validate(name: str, model: Any, data: Any, prefix: tuple = ()) -> Any:
    try:
        return TypeAdapter(model).validate_python(data)
    except ValidationError as exc:
        raise OnshapeFormatError(M.format_validation_error(name, exc, prefix)) from None


def _top_level(name: str, data: Any, body_model: Any, response_model: Any) -> tuple[Any, str, str]:
    """(response, wire format, JSON path prefix of the bodies list)."""
    if isinstance(data, list):  # format B: bare array of bodies
        bodies = _validate(name, list[body_model], data)
        return response_model(bodies=bodies), "B", ""
    if isinstance(data, dict):
        if "bodies" not in data and isinstance(data.get("parts"), list):  # 2018 docs: {"parts": [...]}
            bodies = _validate(name, list[body_model], data["parts"], ("parts",))
            return response_model(bodies=bodies), "B", "parts"
        fmt = "A" if "btType" in data else "B"
        return _validate(name, response_model, data), fmt, "bodies"
    raise OnshapeFormatError(f"{name}: (top level): expected an object with 'bodies' or an array of bodies, "
                             f"got {M.describe(data)}")


def _check_error_enum(name: str, value: str | None) -> None:
    if value not in (None, "NO_ERROR"):
        raise OnshapeFormatError(f"{name}: errorEnum: the server reported {value!r} instead of NO_ERROR")


def _check_body_type(name: str, path: str, value: str | None) -> str:
    if value is None:
        return "SOLID"
    if value not in M.BODY_TYPES:
        raise OnshapeFormatError(f"{name}: {path}: expected one of {', '.join(M.BODY_TYPES)}, got {value!r}")
    return value


def _bpath(prefix: str, i: int) -> str:
    return f"{prefix}[{i}]" if prefix else f"[{i}]"


# ---------------------------------------------------------------------------------------
# tessellation
# ---------------------------------------------------------------------------------------


def _facet_arrays(face: M.TessFace, body: M.TessBody, top: list, path: str):
    """Corners (m, 3, 3), facet normals (m, 3) or None, vertex normals (m, 3, 3) or None."""
    corners, normals, vnormals = [], [], []
    has_n = all(f.normal is not None for f in face.facets)
    has_vn = all(len(f.vertex_normals) == 3 for f in face.facets)
    for k, f in enumerate(face.facets):
        fp = f"{path}.facets[{k}]"
        if f.vertices:
            if len(f.vertices) != 3:
                raise _Fail(f"{fp}.vertices", f"expected 3 vertices (triangles only), got {len(f.vertices)}")
            corners.append(f.vertices)
        elif f.indices:
            table = body.facetPoints or top
            if len(f.indices) != 3:
                raise _Fail(f"{fp}.indices", f"expected 3 indices (triangles only), got {len(f.indices)}")
            bad = [i for i in f.indices if not 0 <= i < len(table)]
            if bad:
                raise _Fail(f"{fp}.indices", f"index {bad[0]} outside the facetPoints table of {len(table)} points")
            corners.append([table[i] for i in f.indices])
        else:
            raise _Fail(fp, "facet has neither vertices nor indices")
        if has_n:
            normals.append(f.normal)
        if has_vn:
            vnormals.append(f.vertex_normals)
    C = np.asarray(corners, dtype=float).reshape(-1, 3, 3)
    N = np.asarray(normals, dtype=float).reshape(-1, 3) if has_n and corners else None
    VN = np.asarray(vnormals, dtype=float).reshape(-1, 3, 3) if has_vn and corners else None
    return C, N, VN


def weld_facets(corners: np.ndarray, facet_normals: np.ndarray | None, vertex_normals: np.ndarray | None):
    """Weld facet corners shared by coordinate into an indexed mesh.

    Returns (vertices (n, 3), triangles (m, 3), facet normals (m, 3) or None, vertex normals
    (n, 3) or None, notes). Degenerate facets are dropped; facets wound against their given
    normal are re-wound so the mesh winding agrees with the facet normals.
    """
    notes = []
    e1 = corners[:, 1] - corners[:, 0]
    e2 = corners[:, 2] - corners[:, 0]
    cross = np.cross(e1, e2)
    twice_area = np.linalg.norm(cross, axis=1)
    scale = float(np.max(np.abs(corners))) if corners.size else 1.0
    keep = twice_area > 1e-14 * max(scale, 1e-300) ** 2
    if not np.all(keep):
        notes.append(f"{int(np.sum(~keep))} degenerate facets dropped")
    corners, cross = corners[keep], cross[keep]
    if facet_normals is not None:
        facet_normals = facet_normals[keep]
    if vertex_normals is not None:
        vertex_normals = vertex_normals[keep]
    if facet_normals is not None:
        flip = np.einsum("ij,ij->i", cross, facet_normals) < 0
        if np.any(flip):
            notes.append(f"{int(np.sum(flip))} facets wound against their normal: re-wound")
            corners[flip] = corners[flip][:, [0, 2, 1]]
            if vertex_normals is not None:
                vertex_normals[flip] = vertex_normals[flip][:, [0, 2, 1]]
    flat = corners.reshape(-1, 3)
    vertices, inverse = np.unique(flat, axis=0, return_inverse=True)
    triangles = inverse.reshape(-1, 3)
    vn = None
    if vertex_normals is not None:
        acc = np.zeros_like(vertices)
        np.add.at(acc, inverse.ravel(), vertex_normals.reshape(-1, 3))
        norm = np.linalg.norm(acc, axis=1, keepdims=True)
        vn = np.divide(acc, norm, out=np.zeros_like(acc), where=norm > 0)
    return vertices, triangles, facet_normals, vn, notes


def _make_mesh(vertices, triangles):
    import trimesh  # lazy: geometry/importers stay light until a mesh is built

    return trimesh.Trimesh(vertices=vertices, faces=triangles, process=False)


# ---------------------------------------------------------------------------------------
# exact surfaces and curves
# ---------------------------------------------------------------------------------------


def _need(desc: Any, field: str, path: str, kind: str, *alternatives: str) -> Any:
    for name in (field, *alternatives):
        value = getattr(desc, name)
        if value is not None:
            return value
    also = f" (or {', '.join(alternatives)})" if alternatives else ""
    raise _Fail(f"{path}.{field}", f"missing field{also}, needed for {kind}")


def bcurve_control_points(desc: M.CurveDesc, path: str) -> list[tuple[np.ndarray, np.ndarray | None, str]]:
    """Candidate readings (points (n, 3), weights (n,) or None, layout name) of a BCURVE's
    control points, validated against degree and knots. See the module docstring."""
    degree = _need(desc, "degree", path, "BCURVE")
    knots = _need(desc, "knots", path, "BCURVE")
    raw = _need(desc, "controlPoints", path, "BCURVE")
    if degree < 1:
        raise _Fail(f"{path}.degree", f"expected a degree of at least 1, got {degree}")
    k = np.asarray(knots, dtype=float)
    if np.any(np.diff(k) < 0):
        raise _Fail(f"{path}.knots", "knots must not decrease")
    cp = f"{path}.controlPoints"
    if raw and all(isinstance(v, dict) for v in raw):
        pts = np.asarray(_validate_inline(cp, list[M.Vec3], raw), dtype=float)
        rows, width = pts, 3
    elif raw and all(isinstance(v, (list, tuple)) for v in raw):
        widths = {len(v) for v in raw}
        if len(widths) != 1 or widths.pop() not in (3, 4):
            raise _Fail(cp, "nested control points must all have 3 (x, y, z) or 4 (x, y, z, w) numbers")
        rows = np.asarray(_validate_inline(cp, list[list[M.Number]], raw), dtype=float)
        width = rows.shape[1]
    else:
        flat = np.asarray(_validate_inline(cp, list[M.Number], raw), dtype=float)
        width = 4 if (desc.isRational and desc.weights is None) else 3
        if flat.size % width:
            layout = "x w, y w, z w, w (isRational without weights)" if width == 4 else "x, y, z"
            raise _Fail(cp, f"{flat.size} numbers is not a whole number of control points of {width} ({layout})")
        rows = flat.reshape(-1, width)
    n = len(rows)
    expected = len(k) - degree - 1
    if n != expected:
        raise _Fail(cp, f"{n} control points do not match degree {degree} and {len(k)} knots "
                        f"(expected len(knots) - degree - 1 = {expected})")
    if width == 3:
        weights = None
        if desc.weights is not None:
            weights = np.asarray(desc.weights, dtype=float)
            if len(weights) != n:
                raise _Fail(f"{path}.weights", f"expected {n} weights (one per control point), got {len(weights)}")
        elif desc.isRational:
            raise _Fail(f"{path}.weights", "isRational is true but no weights: give weights or 4 numbers per point")
        if weights is not None and not np.all(weights > 0):
            raise _Fail(f"{path}.weights", "weights must be positive")
        return [(rows, weights, "xyz")]
    w = rows[:, 3]
    if not np.all(w > 0):
        raise _Fail(cp, "the 4th coordinate (weight) of every control point must be positive")
    homogeneous = (rows[:, :3] / w[:, None], w, "homogeneous xyzw")
    if np.all(w == 1.0):
        return [homogeneous]
    return [homogeneous, (rows[:, :3].copy(), w, "cartesian xyzw")]


def _validate_inline(path: str, model: Any, data: Any) -> Any:
    try:
        return TypeAdapter(model).validate_python(data)
    except ValidationError as exc:
        e = exc.errors(include_url=False)[0]
        sub = M.json_path(tuple(e["loc"]))
        msg = str(e["ctx"]["error"]) if e["type"] == "value_error" and "ctx" in e else e["msg"]
        raise _Fail(f"{path}{'' if sub.startswith('[') else '.'}{sub}", msg) from None


def _bspline_dict(desc: M.CurveDesc, reading) -> dict:
    pts, w, _ = reading
    d = {"type": "bspline_curve", "degree": int(desc.degree), "knots": [float(x) for x in desc.knots],
         "control_points": pts.tolist(), "periodic": bool(desc.isPeriodic)}
    if w is not None:
        d["weights"] = w.tolist()
    return d


class _Unavailable(Exception):
    """The geometry package has no primitive of this type (yet): keep the entity as
    tessellation-only rather than refuse the whole part."""


def _build(d: dict, path: str):
    from ibfem.geometry._base import _REGISTRY

    if d["type"] not in _REGISTRY or (d["type"] == "sweep" and d["profile"]["type"] not in _REGISTRY):
        raise _Unavailable(d["type"])
    try:
        return primitive_from_dict(d)
    except ValueError as exc:
        raise _Fail(path, str(exc)) from None


def _best_reading(candidates, build, check_points: np.ndarray | None):
    """Build every candidate reading; keep the one whose primitive passes nearest to the
    check points (the first one when there is nothing to check against)."""
    if len(candidates) == 1 or check_points is None or len(check_points) == 0:
        return build(candidates[0]), candidates[0][2]
    best = None
    for cand in candidates:
        prim = build(cand)
        res = float(np.max(np.abs(prim.project(check_points).distances)))
        if best is None or res < best[0]:
            best = (res, prim, cand[2])
    return best[1], best[2]


def curve_primitive(desc: M.CurveDesc, path: str, check_points: np.ndarray | None = None):
    """(primitive or None, canonical type, note or None)."""
    kind = LEGACY_NAMES.get(desc.type, desc.type)
    if kind == "LINE":
        d = {"type": "line", "origin": list(_need(desc, "origin", path, kind)),
             "direction": list(_need(desc, "direction", path, kind))}
    elif kind == "CIRCLE":
        d = {"type": "circle", "origin": list(_need(desc, "origin", path, kind)),
             "normal": list(_need(desc, "normal", path, kind, "direction")), "radius": _need(desc, "radius", path, kind)}
    elif kind == "ELLIPSE":
        d = {"type": "ellipse", "origin": list(_need(desc, "origin", path, kind)),
             "normal": list(_need(desc, "normal", path, kind, "direction")),
             "major_axis": list(_need(desc, "majorAxis", path, kind)),
             "major_radius": _need(desc, "majorRadius", path, kind),
             "minor_radius": _need(desc, "minorRadius", path, kind)}
    elif kind == "BCURVE":
        cands = bcurve_control_points(desc, path)
        prim, layout = _best_reading(cands, lambda c: _build(_bspline_dict(desc, c), path), check_points)
        note = f"control points read as {layout}" if len(cands) > 1 else None
        return prim, kind, note
    else:
        return None, kind, None
    return _build(d, path), kind, None


def surface_primitive(desc: M.SurfaceDesc, path: str, check_points: np.ndarray | None = None):
    """(primitive or None, canonical type, note or None)."""
    kind = LEGACY_NAMES.get(desc.type, desc.type)
    if kind == "PLANE":
        d = {"type": "plane", "origin": list(_need(desc, "origin", path, kind)),
             "normal": list(_need(desc, "normal", path, kind, "direction"))}
    elif kind == "CYLINDER":
        d = {"type": "cylinder", "origin": list(_need(desc, "origin", path, kind)),
             "axis": list(_need(desc, "axis", path, kind, "direction")), "radius": _need(desc, "radius", path, kind)}
    elif kind == "CONE":
        d = {"type": "cone", "origin": list(_need(desc, "origin", path, kind)),
             "axis": list(_need(desc, "axis", path, kind, "direction")), "radius": _need(desc, "radius", path, kind),
             "half_angle": _need(desc, "halfAngle", path, kind)}
    elif kind == "SPHERE":
        d = {"type": "sphere", "origin": list(_need(desc, "origin", path, kind)),
             "radius": _need(desc, "radius", path, kind)}
    elif kind == "TORUS":
        d = {"type": "torus", "origin": list(_need(desc, "origin", path, kind)),
             "axis": list(_need(desc, "axis", path, kind, "direction")),
             "major_radius": _need(desc, "majorRadius", path, kind),
             "minor_radius": _need(desc, "minorRadius", path, kind)}
    elif kind == "SWEEP":
        if desc.profile is None:
            return None, kind, "SWEEP without a profile: kept as tessellation-only"
        direction = list(_need(desc, "direction", path, kind))
        prof = desc.profile
        ppath = f"{path}.profile"
        if LEGACY_NAMES.get(prof.type, prof.type) != "BCURVE":
            pcurve, _, _ = curve_primitive(prof, ppath)
            if pcurve is None:
                return None, kind, f"SWEEP profile of type {prof.type}: kept as tessellation-only"
            return _build({"type": "sweep", "profile": pcurve.to_dict(), "direction": direction}, path), kind, None
        cands = bcurve_control_points(prof, ppath)
        prim, layout = _best_reading(
            cands, lambda c: _build({"type": "sweep", "profile": _bspline_dict(prof, c), "direction": direction}, path),
            check_points)
        note = f"profile control points read as {layout}" if len(cands) > 1 else None
        return prim, kind, note
    else:
        return None, kind, None
    return _build(d, path), kind, None


def _orientation_vote(surface, vertices, triangles, facet_normals) -> float:
    """Area-weighted mean sign of (facet normal . surface normal at the facet centroid):
    +1 all facets agree with the surface's own normal, -1 all opposite."""
    P = vertices[triangles]
    cent = P.mean(axis=1)
    cross = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    area = np.linalg.norm(cross, axis=1)
    n = facet_normals if facet_normals is not None else cross / np.where(area > 0, area, 1.0)[:, None]
    s = np.sign(np.einsum("ij,ij->i", n, surface.project(cent).normals))
    total = float(area.sum())
    return float((area * s).sum() / total) if total > 0 else 0.0


# ---------------------------------------------------------------------------------------
# the Part
# ---------------------------------------------------------------------------------------


def load_part(directory: str | Path) -> Part:
    """Read a cached part studio/part directory into a ``geometry.Part``."""
    directory = Path(directory)
    if not directory.is_dir():
        raise OnshapeFormatError(f"{directory}: not a directory (expected a cached Onshape import)")
    faces = _read_json(directory, FACES_FILE)
    details = _read_json(directory, DETAILS_FILE)
    edges = _read_json(directory, EDGES_FILE, required=False)
    source = _read_json(directory, SOURCE_FILE, required=False)
    part = parse_part(faces, details, edges, source)
    part.metadata["directory"] = str(directory)
    return part


def parse_part(faces_json: Any, details_json: Any, edges_json: Any = None, source: Any = None) -> Part:
    """Build a Part from the decoded JSON responses (see :func:`load_part`)."""
    tess, ffmt, fprefix = _top_level(FACES_FILE, faces_json, M.TessBody, M.TessFacesResponse)
    _check_error_enum(FACES_FILE, tess.errorEnum)
    if not isinstance(details_json, dict):
        raise OnshapeFormatError(f"{DETAILS_FILE}: (top level): expected an object with 'bodies', "
                                 f"got {M.describe(details_json)}")
    details = _validate(DETAILS_FILE, M.BodiesResponse, details_json)
    dfmt = "A" if "btType" in details_json else "B"
    _check_error_enum(DETAILS_FILE, details.errorEnum)
    etess, efmt, eprefix = (None, None, "")
    if edges_json is not None:
        etess, efmt, eprefix = _top_level(EDGES_FILE, edges_json, M.TessEdgeBody, M.TessEdgesResponse)
        _check_error_enum(EDGES_FILE, etess.errorEnum)

    part = Part()
    part.metadata.update({
        "wire_format": {FACES_FILE: ffmt, DETAILS_FILE: dfmt, **({EDGES_FILE: efmt} if efmt else {})},
        "microversion": details.microversionId.theId if details.microversionId else None,
    })
    if isinstance(source, dict):
        part.metadata["source"] = {k: v for k, v in source.items() if "key" not in k.lower()}
    if edges_json is None:
        part.warnings.append(f"{EDGES_FILE} missing: edges have no polylines")

    meshes, tess_body_of, tess_body_info = _face_meshes(tess, fprefix, part)
    if tess.bodies and not details.bodies:
        raise OnshapeFormatError(f"{DETAILS_FILE}: bodies: empty, while {FACES_FILE} has {len(tess.bodies)} bodies: "
                                 "the cached response is damaged; import the part again")
    if not any(m is not None for m in meshes.values()):
        faces = sum(len(tb.faces) for tb in tess.bodies)
        raise OnshapeFormatError(f"{FACES_FILE}: no usable tessellation ({len(tess.bodies)} bodies, {faces} faces, "
                                 "no facets): the cached response is empty or damaged; import the part again")
    polylines: dict[str, np.ndarray] = {}
    if etess is not None:
        for eb in etess.bodies:
            for e in eb.edges:
                polylines[e.id] = np.asarray(e.vertices, dtype=float).reshape(-1, 3)

    unsupported: dict[str, list[str]] = {}
    _detailed_bodies(details, meshes, polylines, tess_body_info, part, unsupported)
    _tessellation_only_faces(meshes, tess_body_of, tess_body_info, part, unsupported)
    for what, ids in sorted(unsupported.items()):
        part.warnings.append(f"{what}: kept as tessellation-only: {', '.join(ids)}")
    for fid, face in part.faces.items():
        if face.mesh is None:
            part.warnings.append(f"face {fid} ({face.surface_type}): no tessellation in {FACES_FILE}")
    return part


def _face_meshes(tess, fprefix: str, part: Part) -> tuple[dict, dict, dict]:
    """Tessellated faces, welded per face: {face id: mesh}, {face id: body id}, {body id: (name, type)}."""
    meshes: dict[str, tuple] = {}
    tess_body_of: dict[str, str] = {}
    tess_body_info: dict[str, tuple[str, str]] = {}
    for bi, tb in enumerate(tess.bodies):
        bpath = _bpath(fprefix, bi)
        tess_body_info[tb.id] = (tb.name or "", _check_body_type(FACES_FILE, f"{bpath}.bodyType", tb.bodyType))
        for fi, tf in enumerate(tb.faces):
            fpath = f"{bpath}.faces[{fi}]"
            try:
                C, N, VN = _facet_arrays(tf, tb, tess.facetPoints, fpath)
            except _Fail as exc:
                raise OnshapeFormatError(f"{FACES_FILE}: {exc.path}: {exc.message}") from None
            if tf.id in meshes:
                raise OnshapeFormatError(f"{FACES_FILE}: {fpath}.id: face id {tf.id!r} appears twice")
            meshes[tf.id] = weld_facets(C, N, VN) if len(C) else None
            tess_body_of[tf.id] = tb.id
            if tf.errorMessage:
                part.warnings.append(f"face {tf.id}: Onshape could not tessellate it: {tf.errorMessage}")
    return meshes, tess_body_of, tess_body_info


def _detailed_bodies(details, meshes, polylines, tess_body_info, part: Part, unsupported) -> None:
    """Bodies, faces and edges from the body details, with their exact surfaces and curves."""
    seen_faces: set[str] = set()
    for bi, mb in enumerate(details.bodies):
        bpath = f"bodies[{bi}]"
        btype = _check_body_type(DETAILS_FILE, f"{bpath}.type", mb.type)
        face_ids, edge_ids = [], []
        for fi, mf in enumerate(mb.faces):
            fpath = f"{bpath}.faces[{fi}]"
            if mf.id in seen_faces:
                raise OnshapeFormatError(f"{DETAILS_FILE}: {fpath}.id: face id {mf.id!r} appears twice")
            seen_faces.add(mf.id)
            face_ids.append(mf.id)
            part.faces[mf.id] = _make_face(mf, mb.id, meshes.get(mf.id), fpath, part, unsupported)
        for ei, me in enumerate(mb.edges):
            epath = f"{bpath}.edges[{ei}]"
            edge_ids.append(me.id)
            part.edges[me.id] = _make_edge(me, mb.id, polylines.get(me.id), epath, part, unsupported)
        name = (mb.properties.name if mb.properties and mb.properties.name else None) or \
            tess_body_info.get(mb.id, ("", ""))[0]
        part.bodies[mb.id] = Body(id=mb.id, name=name or "", body_type=btype, face_ids=tuple(face_ids),
                                  edge_ids=tuple(edge_ids))


def _tessellation_only_faces(meshes, tess_body_of, tess_body_info, part: Part, unsupported) -> None:
    """Faces tessellated but absent from the body details: kept, tessellation-only."""
    for fid, mesh in meshes.items():
        if fid in part.faces:
            continue
        bid = tess_body_of[fid]
        part.faces[fid] = _mesh_face(fid, "UNKNOWN", None, mesh, bid, (), ("not in bodydetails.json",))
        unsupported.setdefault("face UNKNOWN (missing from bodydetails.json)", []).append(fid)
        if bid not in part.bodies:
            name, btype = tess_body_info[bid]
            part.bodies[bid] = Body(id=bid, name=name, body_type=btype)
        b = part.bodies[bid]
        part.bodies[bid] = Body(b.id, b.name, b.body_type, b.face_ids + (fid,), b.edge_ids)


def _mesh_face(fid, kind, surface, mesh_data, body_id, loops, notes, orientation=1):
    if mesh_data is None:
        return Face(id=fid, surface_type=kind, surface=surface, orientation=orientation, mesh=None, loops=loops,
                    body_id=body_id, notes=tuple(notes))
    V, T, _, VN, wnotes = mesh_data
    return Face(id=fid, surface_type=kind, surface=surface, orientation=orientation, mesh=_make_mesh(V, T),
                loops=loops, body_id=body_id, vertex_normals=VN, notes=tuple(wnotes) + tuple(notes))


def _convert(convert, desc, path: str, check, what: str, item_id: str, unsupported):
    """``convert(desc, path, check)`` -> (primitive, kind, note, None). A malformed description
    raises OnshapeFormatError; one whose primitive the geometry package lacks is recorded in
    ``unsupported`` and gives (None, kind, None, name of the missing primitive)."""
    try:
        primitive, kind, note = convert(desc, path, check)
    except _Fail as exc:
        raise OnshapeFormatError(f"{DETAILS_FILE}: {exc.path}: {exc.message}") from None
    except _Unavailable as exc:
        kind = LEGACY_NAMES.get(desc.type, desc.type)
        unsupported.setdefault(f"{what} {kind} (no {exc.args[0]} primitive in geometry)", []).append(item_id)
        return None, kind, None, exc.args[0]
    return primitive, kind, note, None


def _make_face(mf: M.ModelFace, body_id: str, mesh_data, path: str, part: Part, unsupported) -> Face:
    loops = tuple(Loop(coedges=tuple(Coedge(c.edgeId, c.orientation) for c in lp.coedges), is_outer=lp.outer)
                  for lp in mf.loops)
    check = mesh_data[0] if mesh_data is not None else None
    surface, kind, note, missing = _convert(
        surface_primitive, mf.surface, f"{path}.surface", check, "surface", mf.id, unsupported
    )
    if missing is not None:
        note = f"geometry has no {missing!r} primitive: kept as tessellation-only"
        return _mesh_face(mf.id, kind, None, mesh_data, body_id, loops, [note])
    notes = [note] if note else []
    if surface is None:
        label = kind if kind in TESSELLATION_ONLY_SURFACES + ("SWEEP",) else f"{kind} (unknown surface type)"
        unsupported.setdefault(f"surface {label}", []).append(mf.id)
        return _mesh_face(mf.id, kind, None, mesh_data, body_id, loops, notes)
    flag = 1 if mf.orientation else -1
    orientation = flag
    if mesh_data is not None and len(mesh_data[1]):
        V, T, FN, _, _ = mesh_data
        vote = _orientation_vote(surface, V, T, FN)
        from_facets = 1 if vote >= 0 else -1
        source = "facet normals" if FN is not None else "facet winding"
        if abs(vote) < 0.5:
            part.warnings.append(f"face {mf.id} ({kind}): {source} do not decide the orientation "
                                 f"(agreement {vote:+.2f})")
        if kind in FLAG_CONVENTION_KNOWN and from_facets != flag:
            part.warnings.append(f"face {mf.id} ({kind}): orientation flag {mf.orientation} disagrees with the "
                                 f"{source}; using the {source}")
        if kind in FLAG_CONVENTION_KNOWN and FN is None:
            orientation = flag  # winding is not documented: trust the flag when there are no facet normals
        else:
            orientation = from_facets
    return _mesh_face(mf.id, kind, surface, mesh_data, body_id, loops, notes, orientation)


def _make_edge(me: M.ModelEdge, body_id: str, polyline, path: str, part: Part, unsupported) -> Edge:
    g = me.geometry
    start = np.asarray(g.startPoint, float) if g and g.startPoint is not None else None
    end = np.asarray(g.endPoint, float) if g and g.endPoint is not None else None
    if polyline is None:
        polyline = np.zeros((0, 3))
    if me.curve is None:
        unsupported.setdefault("edge without curve", []).append(me.id)
        return Edge(me.id, "UNKNOWN", None, polyline, start, end, g.length if g else None, body_id)
    pts = [p for p in ((g.startPoint, g.midPoint, g.quarterPoint, g.endPoint) if g else ()) if p is not None]
    check = np.vstack([np.asarray(pts, float).reshape(-1, 3), polyline]) if (pts or len(polyline)) else None
    curve, kind, note, missing = _convert(curve_primitive, me.curve, f"{path}.curve", check, "curve", me.id, unsupported)
    if missing is not None:
        return Edge(me.id, kind, None, polyline, start, end, g.length if g else None, body_id,
                    notes=(f"geometry has no {missing!r} primitive",))
    if curve is None:
        label = kind if kind in TESSELLATION_ONLY_CURVES else f"{kind} (unknown curve type)"
        unsupported.setdefault(f"curve {label}", []).append(me.id)
    return Edge(me.id, kind, curve, polyline, start, end, g.length if g else None, body_id,
                notes=(note,) if note else ())
