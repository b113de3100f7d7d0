"""An OpenCascade shape (read from STEP / IGES, in metres) -> :class:`geometry.Part`.

Ids are stable for a given file: faces ``F1..Fn`` and edges ``E1..Em`` in the order
OpenCascade's ``TopExp::MapShapes`` meets them (the order of the file's topology), bodies
``B1..`` (solids first, then free shells and free faces as ``SHEET`` bodies).

Orientation (+1 when the solid's outward normal is the primitive's
own normal): OpenCascade's outward normal is ``S_u x S_v`` of the face's surface, negated on a
``REVERSED`` face; it is compared with the primitive's normal at the middle of the face's
parameter range. The triangles (wound outward) vote as a check: a disagreement is a warning.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from ibfem.geometry import Body, Coedge, Edge, Face, Loop, Part, primitive_from_dict

from .curves import edge_curve, edge_polyline
from .surfaces import covering, covering_sweep, surface_dict
from .tessellation import face_triangles

__all__ = ["build_part"]


def _shape_map(shape, kind):
    """OpenCascade's indexed map of the sub-shapes of ``kind`` (1-based, IsSame identity)."""
    from OCP.collections import IndexedMap_TopoDS_Shape_TopTools_ShapeMapHasher as ShapeMap
    from OCP.TopExp import TopExp

    m = ShapeMap()
    TopExp.MapShapes_s(shape, kind, m)
    return m


def _indexed(shape, kind) -> list:
    m = _shape_map(shape, kind)
    return [m.FindKey(i) for i in range(1, m.Extent() + 1)]


def _loops(face, edge_index) -> tuple[Loop, ...]:
    from OCP.BRepTools import BRepTools, BRepTools_WireExplorer
    from OCP.TopAbs import TopAbs_Orientation, TopAbs_ShapeEnum
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    outer = BRepTools.OuterWire_s(face)
    loops = []
    explorer = TopExp_Explorer(face, TopAbs_ShapeEnum.TopAbs_WIRE)
    while explorer.More():
        wire = TopoDS.Wire(explorer.Current())
        coedges = []
        walker = BRepTools_WireExplorer(wire, face)
        while walker.More():
            e = walker.Current()
            coedges.append(Coedge(f"E{edge_index(e)}", e.Orientation() == TopAbs_Orientation.TopAbs_FORWARD))
            walker.Next()
        loops.append(Loop(coedges=tuple(coedges), is_outer=bool(not outer.IsNull() and wire.IsSame(outer))))
        explorer.Next()
    return tuple(sorted(loops, key=lambda lp: not lp.is_outer))


def _occ_outward(face, evaluator) -> tuple[np.ndarray, np.ndarray] | None:
    """(point, OpenCascade's outward unit normal) at the middle of the face's (u, v) range."""
    from OCP.BRepTools import BRepTools
    from OCP.gp import gp_Pnt, gp_Vec
    from OCP.TopAbs import TopAbs_Orientation

    u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
    p, du, dv = gp_Pnt(), gp_Vec(), gp_Vec()
    for fu, fv in ((0.5, 0.5), (0.37, 0.61), (0.23, 0.29)):
        evaluator.D1(u0 + fu * (u1 - u0), v0 + fv * (v1 - v0), p, du, dv)
        n = np.cross([du.X(), du.Y(), du.Z()], [dv.X(), dv.Y(), dv.Z()])
        norm = np.linalg.norm(n)
        if norm > 0:
            sign = -1.0 if face.Orientation() == TopAbs_Orientation.TopAbs_REVERSED else 1.0
            return np.array([p.X(), p.Y(), p.Z()]), sign * n / norm
    return None


def _vote(surface, vertices: np.ndarray, triangles: np.ndarray) -> float:
    """Area-weighted agreement (+1 .. -1) of the outward-wound triangles with the primitive's normal."""
    P = vertices[triangles]
    cross = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    area = np.linalg.norm(cross, axis=1)
    keep = area > 0
    if not keep.any():
        return 0.0
    normals = surface.project(P[keep].mean(axis=1)).normals
    s = np.sign(np.einsum("ij,ij->i", cross[keep], normals))
    return float((area[keep] * s).sum() / area[keep].sum())


def _make_mesh(data):
    if data is None:
        return None
    import trimesh

    return trimesh.Trimesh(vertices=data[0], faces=data[1], process=False)


def _face_parameters(face, triangles) -> np.ndarray:
    """(u, v) of the corners of the face's trimming box and of its mesh nodes."""
    from OCP.BRepTools import BRepTools

    u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
    corners = np.array([[u0, v0], [u1, v1]])
    return corners if triangles is None else np.concatenate([corners, triangles[0]])


def _outward_moments(face, data):
    """The face's moments (from the mesher's data) for its outward normal in the body."""
    from OCP.TopAbs import TopAbs_Orientation

    if data is None or len(data) < 3 or data[2] is None:
        return None
    return data[2].oriented(-1 if face.Orientation() == TopAbs_Orientation.TopAbs_REVERSED else 1)


def _face(face, fid: str, body_id: str, edge_index, part: Part, unsupported: dict, triangles) -> Face:
    from OCP.BRep import BRep_Tool
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAdaptor import GeomAdaptor_Surface
    from OCP.TopoDS import TopoDS

    face = TopoDS.Face(face)
    evaluator = BRepAdaptor_Surface(face, False)
    mesh = face_triangles(face, evaluator, triangles)
    moments = _outward_moments(face, triangles)
    loops = _loops(face, edge_index)
    geom = BRep_Tool.Surface_s(face)
    d, kind, note = surface_dict(GeomAdaptor_Surface(geom), v_range=_face_parameters(face, None)[:, 1])
    notes = [note] if note else []
    if d is not None and d["type"] == "bspline_surface" and kind == "BSURFACE":
        d, grown = covering(d, geom, _face_parameters(face, triangles))
        notes += [grown] if grown else []
    elif d is not None and d["type"] == "sweep":
        d, grown = covering_sweep(d, _face_parameters(face, triangles)[:, 0])
        notes += [grown] if grown else []
    surface = None
    if d is not None:
        try:
            surface = primitive_from_dict(d)
        except ValueError as exc:
            notes.append(f"{kind} not representable: {exc}")
    if surface is None:
        unsupported.setdefault(f"surface {kind}", []).append(fid)
        return Face(fid, kind, None, 1, _make_mesh(mesh), loops, body_id, notes=tuple(notes), moments=moments)
    orientation = 1
    at = _occ_outward(face, evaluator)
    if at is not None:
        orientation = 1 if float(surface.project(at[0][None]).normals[0] @ at[1]) >= 0 else -1
    else:
        notes.append("no regular point to compare normals at: orientation from the triangles")
    if mesh is not None:
        vote = _vote(surface, *mesh)
        if at is None:
            orientation = 1 if vote >= 0 else -1
        elif vote * orientation < 0.5:
            part.warnings.append(f"face {fid} ({kind}): the triangles' normals agree only {vote * orientation:+.2f} "
                                 "with the exact outward normal")
    return Face(fid, kind, surface, orientation, _make_mesh(mesh), loops, body_id, notes=tuple(notes),
                moments=moments)


def _edge(edge, eid: str, body_id: str, deflection: float, unsupported: dict) -> Edge:
    from OCP.TopoDS import TopoDS

    info = edge_curve(TopoDS.Edge(edge))
    kind, d = info["kind"], info["dict"]
    polyline = edge_polyline(info["adaptor"], deflection, info["start"])
    curve, notes = None, ()
    if d is not None:
        try:
            curve = primitive_from_dict(d)
        except ValueError as exc:
            notes = (f"{kind} not representable: {exc}",)
    if curve is None and kind != "DEGENERATE":
        unsupported.setdefault(f"curve {kind}", []).append(eid)
    if kind == "DEGENERATE":
        notes = ("degenerated edge (a pole of its face): a point, no curve",)
    return Edge(eid, kind, curve, polyline, info["start"], info["end"], info["length"], body_id, notes)


def _bodies(shape) -> list[tuple[str, object, list]]:
    """(body type, sub-shape, faces) per body: solids, then free shells, then loose faces."""
    from OCP.collections import IndexedMap_TopoDS_Shape_TopTools_ShapeMapHasher as ShapeMap
    from OCP.TopAbs import TopAbs_ShapeEnum as S

    bodies, taken = [], ShapeMap()
    for kind, enum in (("SOLID", S.TopAbs_SOLID), ("SHEET", S.TopAbs_SHELL)):
        for sub in _indexed(shape, enum):
            faces = _indexed(sub, S.TopAbs_FACE)
            if kind == "SHEET" and any(taken.Contains(f) for f in faces):
                continue  # the shell of a solid
            for f in faces:
                taken.Add(f)
            bodies.append((kind, sub, faces))
    loose = [f for f in _indexed(shape, S.TopAbs_FACE) if not taken.Contains(f)]
    if loose:
        bodies.append(("SHEET", None, loose))
    return bodies


def _solid_volume(solid) -> float:
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(solid, props)
    return float(props.Mass())


def _checked_solid(sub, bid: str, name: str, part: Part):
    """(body type, solid) of a SOLID of the file: reversed (with a warning) when its faces are
    oriented inward (negative volume, as some exporters write); a SHEET, with a warning, when a
    shell is open or the volume is zero. OpenCascade's volume is kept in ``part.metadata["volumes"]``."""
    from OCP.BRep import BRep_Tool
    from OCP.TopAbs import TopAbs_ShapeEnum as S

    label = f"body {bid}" + (f" ({name})" if name else "")
    open_shells = [k for k, shell in enumerate(_indexed(sub, S.TopAbs_SHELL), 1) if not BRep_Tool.IsClosed_s(shell)]
    if open_shells:
        part.warnings.append(f"{label}: shell {', '.join(map(str, open_shells))} is open (an edge bounds only one "
                             "face): imported as a sheet (its faces as surfaces), not as a solid")
        return "SHEET", sub
    volume = _solid_volume(sub)
    scale = _box_diagonal(sub) ** 3
    if not abs(volume) > 1e-12 * scale:
        part.warnings.append(f"{label}: zero volume ({volume:.3g} m^3): imported as a sheet, not as a solid")
        return "SHEET", sub
    if volume < 0:
        part.warnings.append(f"{label}: faces oriented inward in the file (volume {volume:.4g} m^3): reversed")
        sub, volume = sub.Reversed(), -volume
    part.metadata.setdefault("volumes", {})[bid] = volume
    return "SOLID", sub


def _box_diagonal(shape) -> float:
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    box = Bnd_Box()
    BRepBndLib.Add_s(shape, box)
    if box.IsVoid():
        return 0.0
    lo, hi = box.CornerMin(), box.CornerMax()
    return float(np.linalg.norm([hi.X() - lo.X(), hi.Y() - lo.Y(), hi.Z() - lo.Z()]))


def build_part(shape, path: Path, names=None, deflection: float = 1e-4, meshes=None) -> Part:
    """The Part of a shape (see the module docstring); ``meshes``: {face number: (uv, triangles, moments)}
    from :func:`~.tessellation.mesh_shape`; ``names(sub-shape)``: the name the
    file gives a solid, shell or face ('' when none). Face names are kept in
    ``part.metadata["face_names"]`` ({face id: name}) and in the face's notes."""
    names = names or (lambda s: "")
    from OCP.TopAbs import TopAbs_ShapeEnum as S

    face_map, edge_map = _shape_map(shape, S.TopAbs_FACE), _shape_map(shape, S.TopAbs_EDGE)
    face_index, edge_index = face_map.FindIndex, edge_map.FindIndex
    edges = [edge_map.FindKey(i) for i in range(1, edge_map.Extent() + 1)]
    part = Part()
    unsupported: dict[str, list[str]] = {}
    edge_body: dict[int, str] = {}
    for b, (btype, sub, bfaces) in enumerate(_bodies(shape), 1):
        bid = f"B{b}"
        name = names(sub) if sub is not None else ""
        if btype == "SOLID":
            btype, sub = _checked_solid(sub, bid, name, part)
            bfaces = _indexed(sub, S.TopAbs_FACE)
        fids = [f"F{face_index(f)}" for f in bfaces]
        eids = sorted({edge_index(e) for f in bfaces for e in _indexed(f, S.TopAbs_EDGE)})
        for f, fid in zip(bfaces, fids):
            face = _face(f, fid, bid, edge_index, part, unsupported, (meshes or {}).get(face_index(f)))
            label = names(f)
            if label:
                part.metadata.setdefault("face_names", {})[fid] = label
                face = replace(face, notes=face.notes + (f"name in the file: {label}",))
            part.faces[fid] = face
        for e in eids:
            edge_body.setdefault(e, bid)
        part.bodies[bid] = Body(bid, name, btype, tuple(fids), tuple(f"E{e}" for e in eids))
    part.faces = dict(sorted(part.faces.items(), key=lambda kv: int(kv[0][1:])))
    for i, e in enumerate(edges, 1):
        part.edges[f"E{i}"] = _edge(e, f"E{i}", edge_body.get(i, ""), deflection, unsupported)
    for what, ids in sorted(unsupported.items()):
        part.warnings.append(f"{what}: kept as tessellation-only: {', '.join(ids)}")
    for fid, face in part.faces.items():
        if face.mesh is None:
            part.warnings.append(f"face {fid} ({face.surface_type}): the mesher produced no triangles")
    return part
