"""The parsed Part on disk, so later runs need not reparse the CAD file (``ibfem import
PART.step --out DIR``).

``DIR/part.json`` holds the source file's path and SHA-256, the mesher's tolerances, the bodies,
and per face / edge its type, exact primitive (its ``to_dict()``, or null), orientation, loops,
notes and (faces) the moments over the face's parameter domain, or null; ``DIR/meshes.npz`` the
arrays: ``<face id>.vertices``, ``<face id>.triangles`` and ``<edge id>.polyline``. ``load_cached(DIR)`` reads it back; when the
source file still exists and its hash changed, the file is parsed again and the cache rewritten.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any, Optional

import numpy as np
from pydantic import BaseModel, ConfigDict, ValidationError

from ibfem.geometry import Body, Coedge, Edge, Face, Loop, Part, primitive_from_dict
from ibfem.geometry.solids.domain_moments import FaceMoments

from .errors import StepFormatError

__all__ = ["write_cache", "read_cache", "is_cache", "file_hash", "CACHE_FILE", "MESH_FILE", "CACHE_FORMAT"]

CACHE_FILE = "part.json"
MESH_FILE = "meshes.npz"
CACHE_FORMAT = "ibfem-step-part"
CACHE_VERSION = 1


def file_hash(path: str | Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def is_cache(directory: str | Path) -> bool:
    p = Path(directory) / CACHE_FILE
    if not p.is_file():
        return False
    try:
        with open(p, "rb") as f:
            head = f.read(200)
    except OSError:
        return False
    return CACHE_FORMAT.encode() in head


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


class _LoopModel(_Strict):
    outer: bool
    coedges: list[tuple[str, bool]]


class _MomentsModel(_Strict):
    reference: tuple[float, float, float]
    area: float
    normal: tuple[float, float, float]
    first: tuple[float, float, float]
    second: tuple[float, float, float]


class _FaceModel(_Strict):
    id: str
    type: str
    surface: Optional[dict[str, Any]]
    orientation: int
    body: str
    loops: list[_LoopModel]
    notes: list[str] = []
    moments: Optional[_MomentsModel] = None


class _EdgeModel(_Strict):
    id: str
    type: str
    curve: Optional[dict[str, Any]]
    start: Optional[tuple[float, float, float]]
    end: Optional[tuple[float, float, float]]
    length: Optional[float]
    body: str
    notes: list[str] = []


class _BodyModel(_Strict):
    id: str
    name: str
    type: str
    faces: list[str]
    edges: list[str]


class _CacheModel(_Strict):
    format: str
    version: int
    source: dict[str, Any]
    tolerance: float
    angular_tolerance: float
    metadata: dict[str, Any] = {}
    warnings: list[str] = []
    bodies: list[_BodyModel]
    faces: list[_FaceModel]
    edges: list[_EdgeModel]


def _vec(v) -> list[float] | None:
    return None if v is None else [float(x) for x in np.asarray(v, float)]


def write_cache(part: Part, directory: str | Path) -> Path:
    """Write ``part`` (built by :func:`importers.step.load_part`) into ``directory``."""
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    meta = dict(part.metadata)
    doc = {
        "format": CACHE_FORMAT, "version": CACHE_VERSION, "source": meta.pop("source", {}),
        "tolerance": meta.pop("tolerance"), "angular_tolerance": meta.pop("angular_tolerance"),
        "metadata": {k: v for k, v in meta.items() if k != "directory"}, "warnings": list(part.warnings),
        "bodies": [{"id": b.id, "name": b.name, "type": b.body_type, "faces": list(b.face_ids),
                    "edges": list(b.edge_ids)} for b in part.bodies.values()],
        "faces": [{"id": f.id, "type": f.surface_type, "surface": None if f.surface is None else f.surface.to_dict(),
                   "orientation": f.orientation, "body": f.body_id, "notes": list(f.notes),
                   "moments": None if f.moments is None else f.moments.to_dict(),
                   "loops": [{"outer": lp.is_outer, "coedges": [[c.edge_id, c.same_sense] for c in lp.coedges]}
                             for lp in f.loops]} for f in part.faces.values()],
        "edges": [{"id": e.id, "type": e.curve_type, "curve": None if e.curve is None else e.curve.to_dict(),
                   "start": _vec(e.start), "end": _vec(e.end), "length": e.length, "body": e.body_id,
                   "notes": list(e.notes)} for e in part.edges.values()],
    }
    arrays = {}
    for f in part.faces.values():
        if f.mesh is not None:
            arrays[f"{f.id}.vertices"] = np.asarray(f.mesh.vertices, float)
            arrays[f"{f.id}.triangles"] = np.asarray(f.mesh.faces, np.int64)
    for e in part.edges.values():
        arrays[f"{e.id}.polyline"] = np.asarray(e.polyline, float)
    np.savez_compressed(out / MESH_FILE, **arrays)
    (out / CACHE_FILE).write_text(json.dumps(doc, indent=1))
    return out


def _primitive(d: dict | None, where: str):
    if d is None:
        return None
    try:
        return primitive_from_dict(d)
    except (ValueError, TypeError, KeyError) as exc:
        raise StepFormatError(f"{where}: {exc}") from None


def read_cache(directory: str | Path) -> Part:
    """The Part stored by :func:`write_cache` (no check of the source file: see load_part)."""
    d = Path(directory)
    try:
        raw = json.loads((d / CACHE_FILE).read_text(encoding="utf-8"))
        doc = _CacheModel.model_validate(raw)
    except OSError as exc:
        raise StepFormatError(f"{d / CACHE_FILE}: cannot read ({exc.strerror or exc})") from None
    except (ValueError, RecursionError) as exc:
        if isinstance(exc, ValidationError):
            e = exc.errors(include_url=False)[0]
            where = ".".join(str(x) for x in e["loc"])
            raise StepFormatError(f"{d / CACHE_FILE}: {where}: {e['msg']}: import the file again") from None
        raise StepFormatError(f"{d / CACHE_FILE}: not a readable cache ({str(exc)[:120]}): import again") from None
    if doc.format != CACHE_FORMAT or doc.version != CACHE_VERSION:
        raise StepFormatError(f"{d / CACHE_FILE}: format {doc.format!r} version {doc.version}, expected "
                              f"{CACHE_FORMAT!r} version {CACHE_VERSION}: import the file again")
    try:
        with np.load(d / MESH_FILE) as npz:
            arrays = {k: npz[k] for k in npz.files}
    except (OSError, ValueError) as exc:
        raise StepFormatError(f"{d / MESH_FILE}: cannot read ({exc}): import the file again") from None
    return _part_from(doc, arrays, d)


def _part_from(doc: _CacheModel, arrays: dict, d: Path) -> Part:
    import trimesh

    part = Part(metadata={**doc.metadata, "source": doc.source, "tolerance": doc.tolerance,
                          "angular_tolerance": doc.angular_tolerance, "directory": str(d)},
                warnings=list(doc.warnings))
    for i, f in enumerate(doc.faces):
        where = f"{d / CACHE_FILE}: faces[{i}]"
        mesh = None
        if f"{f.id}.vertices" in arrays:
            V, T = arrays[f"{f.id}.vertices"], arrays[f"{f.id}.triangles"]
            if V.ndim != 2 or V.shape[1:] != (3,) or T.ndim != 2 or T.shape[1:] != (3,) or \
                    (T.size and (T.min() < 0 or T.max() >= len(V))):
                raise StepFormatError(f"{d / MESH_FILE}: {f.id}: damaged triangles: import the file again")
            mesh = trimesh.Trimesh(vertices=V, faces=T, process=False)
        loops = tuple(Loop(tuple(Coedge(e, s) for e, s in lp.coedges), lp.outer) for lp in f.loops)
        moments = None if f.moments is None else FaceMoments.from_dict(f.moments.model_dump())
        part.faces[f.id] = Face(f.id, f.type, _primitive(f.surface, f"{where}.surface"), f.orientation, mesh,
                                loops, f.body, notes=tuple(f.notes), moments=moments)
    for i, e in enumerate(doc.edges):
        poly = arrays.get(f"{e.id}.polyline", np.zeros((0, 3)))
        part.edges[e.id] = Edge(e.id, e.type, _primitive(e.curve, f"{d / CACHE_FILE}: edges[{i}].curve"),
                                np.asarray(poly, float).reshape(-1, 3), _arr(e.start), _arr(e.end), e.length,
                                e.body, tuple(e.notes))
    for b in doc.bodies:
        part.bodies[b.id] = Body(b.id, b.name, b.type, tuple(b.faces), tuple(b.edges))
    return part


def _arr(v):
    return None if v is None else np.asarray(v, float)
