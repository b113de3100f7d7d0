"""Triangles of the faces: OpenCascade's incremental mesher (``BRepMesh_IncrementalMesh``) at a
chord tolerance (linear deflection, m) and an angular tolerance (rad) the user can set.

Faces are meshed one at a time, in the order of the file's topology. Meshing the whole shape at
once lets one face's edge discretisation make another face's boundary polygon unmeshable
(OpenCascade's Delaunay step can then loop without end, as on a helical spring exported from
Inventor); a face meshed on its own does not depend on its neighbours' choices.

A guard keeps the mesher from hanging an import: on systems with ``fork`` the faces are meshed
in a child process that sends each face's triangles back as it finishes. A face that takes more
than ``time_limit`` seconds, crashes the mesher or gets no triangles (or triangles over part of
it only: their area off the face's by more than ``COVERED``) is meshed again on its own,
then with a coarser angle, then with a chord tolerance ``COARSER`` times larger (with a warning
saying which); when a face stalled and none of these gives it triangles the import stops with an
error naming the face (a face the mesher finishes without triangles is reported by the part
builder and kept without a tessellation). Without ``fork`` (or with ``time_limit=None``) the faces are meshed in this
process, unguarded.

Each face's moments for the volume (``geometry.solids.domain_moments``) are integrated as soon as
it is meshed, over the triangles in (u, v) and the strips to its edges' curves
(:mod:`.face_moments`), while the face still carries the mesher's polygons of its edges.

Each face's triangulation is read with its nodes' (u, v) parameters; the vertices are the face's
surface evaluated there, ``S(u, v)``. For nodes inside the face this is what the mesher computed
anyway; for nodes on the face's edges it puts them on this face's surface (the edge's 3D curve
may stray from it by up to the edge's tolerance, 1e-7 m typically), so every vertex lies on the
exact surface the face carries, as the projection check expects. Triangles of reversed faces are
re-wound, so every face's triangles are wound with the solid's outward normal; triangles of zero
area (two nodes at a pole) are dropped.
"""

from __future__ import annotations

import os
import pickle
import select
import signal
import struct
import time
import warnings

import numpy as np

from .errors import StepFormatError

__all__ = ["mesh_shape", "face_triangles", "default_tolerance", "DEFAULT_ANGULAR_TOLERANCE",
           "FACE_TIME_LIMIT", "COARSER", "fallbacks"]

DEFAULT_ANGULAR_TOLERANCE = 0.25  # rad
DEFAULT_RELATIVE_TOLERANCE = 1e-3  # of the bounding box diagonal
FACE_TIME_LIMIT = 20.0  # s, for one face
COARSER = 10.0  # chord tolerance factor of the second attempt at a face
COVERED = 0.1  # largest relative difference between the triangles' area and the face's
_HEADER = struct.Struct("<Q")


def default_tolerance(shape) -> float:
    """Chord tolerance of 1e-3 of the shape's bounding-box diagonal (m)."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    box = Bnd_Box()
    BRepBndLib.Add_s(shape, box)
    lo, hi = box.CornerMin(), box.CornerMax()
    diag = float(np.linalg.norm([hi.X() - lo.X(), hi.Y() - lo.Y(), hi.Z() - lo.Z()]))
    return DEFAULT_RELATIVE_TOLERANCE * diag if diag > 0 else 1e-6


def _faces(shape) -> list:
    from OCP.collections import IndexedMap_TopoDS_Shape_TopTools_ShapeMapHasher as ShapeMap
    from OCP.TopAbs import TopAbs_ShapeEnum
    from OCP.TopExp import TopExp
    from OCP.TopoDS import TopoDS

    m = ShapeMap()
    TopExp.MapShapes_s(shape, TopAbs_ShapeEnum.TopAbs_FACE, m)
    return [TopoDS.Face(m.FindKey(i)) for i in range(1, m.Extent() + 1)]


def _triangles(face) -> tuple[np.ndarray, np.ndarray] | None:
    """(uv, triangles) of a face's stored triangulation, None without one."""
    from OCP.BRep import BRep_Tool
    from OCP.TopLoc import TopLoc_Location

    tri = BRep_Tool.Triangulation_s(face, TopLoc_Location())
    if tri is None or tri.NbTriangles() == 0 or not tri.HasUVNodes():
        return None
    uv = np.array([(p.X(), p.Y()) for p in (tri.UVNode(i) for i in range(1, tri.NbNodes() + 1))], float)
    triangles = np.array([tri.Triangle(i).Get() for i in range(1, tri.NbTriangles() + 1)], dtype=np.int64) - 1
    return uv, triangles


def _covers(face, data, share: float = COVERED) -> bool:
    """Whether the triangles' area is within ``share`` of the face's area (OpenCascade's integral,
    to 1e-3): the mesher sometimes returns a triangulation of part of a face."""
    from OCP.BRep import BRep_Tool
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps
    from OCP.TopLoc import TopLoc_Location

    tri = BRep_Tool.Triangulation_s(face, TopLoc_Location())
    nodes = np.array([(p.X(), p.Y(), p.Z()) for p in (tri.Node(i) for i in range(1, tri.NbNodes() + 1))])
    P = nodes[data[1]]
    meshed = 0.5 * float(np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), axis=1).sum())
    props = GProp_GProps()
    BRepGProp.SurfaceProperties_s(face, props, 1e-3)
    exact = abs(props.Mass())
    return exact == 0.0 or abs(meshed - exact) <= share * exact


def mesh_face(face, tolerance: float, angular_tolerance: float) -> tuple | None:
    """(uv (n, 2), triangles (m, 3), 0-based, covered, moments) of one face meshed by OpenCascade
    on its own; ``covered`` is false when the triangles' area differs from the face's by more than
    ``COVERED`` of it; ``moments``: the face's ``FaceMoments`` over the triangles' (u, v) domain
    (:mod:`.face_moments`), or None; None when the mesher makes no triangles."""
    from OCP.BRepMesh import BRepMesh_IncrementalMesh

    BRepMesh_IncrementalMesh(face, float(tolerance), False, float(angular_tolerance), False)
    data = _triangles(face)
    return None if data is None else (*data, _covers(face, data), _moments(face, data))


def _moments(face, data):
    """The face's moments over its (u, v) domain (``face_moments``); None when OpenCascade fails
    to evaluate its surface or curves."""
    from .face_moments import meshed_face_moments

    try:
        return meshed_face_moments(face, *data)
    except Exception:  # OpenCascade's Standard_Failure: the solid's volume falls back to the triangles
        return None


def _good(data) -> bool:
    return data is not None and bool(data[2])


def _child(work, indices, fd) -> None:
    """In the forked child: ``work(i)`` for each face in order, writing (index, data) records to
    ``fd``."""
    with os.fdopen(fd, "wb") as out:
        for i in indices:
            try:
                data = work(i)
            except Exception:  # OpenCascade's Standard_Failure: the face gets no triangles
                data = None
            blob = pickle.dumps((i, data), protocol=pickle.HIGHEST_PROTOCOL)
            out.write(_HEADER.pack(len(blob)) + blob)
            out.flush()


def _read_exactly(fd, n: int, deadline: float) -> bytes | None:
    chunks, got = [], 0
    while got < n:
        wait = deadline - time.monotonic()
        if wait <= 0 or not select.select([fd], [], [], wait)[0]:
            return None
        chunk = os.read(fd, min(n - got, 1 << 20))
        if not chunk:  # the child ended (or crashed)
            return None
        chunks.append(chunk)
        got += len(chunk)
    return b"".join(chunks)


def _guarded_pass(work, indices, limit, results) -> int | None:
    """``work(i)`` for the faces ``indices`` in a forked child; finished faces go to ``results``.
    Returns the index of the face that took longer than ``limit`` seconds or crashed the mesher,
    None when all finished."""
    r, w = os.pipe()
    with warnings.catch_warnings():  # Python >= 3.12 warns about fork with threads: the child
        warnings.simplefilter("ignore", DeprecationWarning)  # only meshes and writes to the pipe
        pid = os.fork()
    if pid == 0:  # pragma: no cover - the child (coverage does not follow it)
        os.close(r)
        code = 0
        try:
            _child(work, indices, w)
        except BaseException:
            code = 1
        os._exit(code)
    os.close(w)
    stuck = None
    try:
        for i in indices:
            deadline = time.monotonic() + limit
            head = _read_exactly(r, _HEADER.size, deadline)
            blob = _read_exactly(r, _HEADER.unpack(head)[0], deadline) if head else None
            if blob is None:
                stuck = i
                break
            j, data = pickle.loads(blob)
            results[j] = data
    finally:
        os.close(r)
        if stuck is not None:
            os.kill(pid, signal.SIGKILL)
        os.waitpid(pid, 0)
    return stuck


def _is_bspline(face) -> bool:
    from OCP.BRep import BRep_Tool
    from OCP.GeomAdaptor import GeomAdaptor_Surface
    from OCP.GeomAbs import GeomAbs_SurfaceType

    return GeomAdaptor_Surface(BRep_Tool.Surface_s(face)).GetType() == GeomAbs_SurfaceType.GeomAbs_BSplineSurface


def _face_label(faces, i: int) -> str:
    from OCP.BRep import BRep_Tool
    from OCP.GeomAdaptor import GeomAdaptor_Surface

    kind = GeomAdaptor_Surface(BRep_Tool.Surface_s(faces[i])).GetType().name.removeprefix("GeomAbs_")
    return f"face F{i + 1} ({kind})"


def fallbacks(tolerance: float, angular: float) -> list[tuple[float, float]]:
    """The (chord, angle) tolerances a face is meshed with in turn: the user's, a coarser angle
    (OpenCascade's mesher fails on some B-spline faces at small angles), then a chord tolerance
    ``COARSER`` times larger."""
    coarse_angle = max(2.0 * angular, 0.5)
    ladder = [(tolerance, angular), (tolerance, coarse_angle), (COARSER * tolerance, coarse_angle)]
    return [step for k, step in enumerate(ladder) if step not in ladder[:k]]


def _retry_alone(faces, i, tolerance, angular, limit, results) -> tuple[str | None, bool]:
    """Mesh face ``i`` on its own in a fresh child (none of its neighbours meshed) with the
    settings of :func:`fallbacks` in turn. Returns (a note when other settings than the user's
    were needed, whether an attempt stalled)."""
    stalled, partial = False, results.get(i)
    for k, (chord, angle) in enumerate(fallbacks(tolerance, angular)):
        stuck = _guarded_pass(lambda j, c=chord, a=angle: mesh_face(faces[j], c, a), [i], limit, results)
        stalled |= stuck is not None
        if stuck is None and _good(results.get(i)):
            return (None if k == 0 else f"{_face_label(faces, i)}: the mesher failed or took over {limit:g} s at "
                    f"chord tolerance {tolerance:.3g} m and angle {angular:g} rad; meshed at {chord:.3g} m and "
                    f"{angle:g} rad"), stalled
        partial = partial or results.get(i)
    results[i] = partial
    if partial is not None:
        return (f"{_face_label(faces, i)}: at every setting the mesher's triangles cover part of the face only "
                f"(their area more than {COVERED:.0%} off the face's); the first kept"), stalled
    return None, stalled


def _mesh_guarded(shape, faces, tolerance, angular, limit, results) -> list[str]:
    """All faces in one child; a face that stalls the child, crashes it or gets no triangles is
    meshed again on its own (:func:`_retry_alone`) and the rest continue in a new child. A face
    that stalled and got no triangles in the end is an error; one the mesher finishes without
    triangles is left for the part builder to report."""
    notes, stalled = [], set()
    pending = list(range(len(faces)))
    while pending:
        stuck = _guarded_pass(lambda j: mesh_face(faces[j], tolerance, angular), pending, limit, results)
        if stuck is None:
            break
        pending = pending[pending.index(stuck) + 1:]
        results.pop(stuck, None)
    for i in [i for i in range(len(faces)) if not _good(results.get(i))]:
        note, hung = _retry_alone(faces, i, tolerance, angular, limit, results)
        notes += [note] if note else []
        stalled |= {i} if hung else set()
    hung = [i for i in sorted(stalled) if results.get(i) is None]
    if hung:
        tried = ", ".join(f"{c:.3g} m / {a:g} rad" for c, a in fallbacks(tolerance, angular))
        raise StepFormatError(f"{_face_label(faces, hung[0])}: OpenCascade's mesher gives no triangles within "
                              f"{limit:g} s at any of the chord / angle tolerances {tried}; try a larger chord "
                              "tolerance")
    return notes


def mesh_shape(shape, tolerance: float, angular_tolerance: float = DEFAULT_ANGULAR_TOLERANCE,
               time_limit: float | None = FACE_TIME_LIMIT) -> tuple[dict[int, tuple], list[str]]:
    """Mesh every face of ``shape`` (chord ``tolerance`` m, ``angular_tolerance`` rad), each within
    ``time_limit`` seconds (see the module docstring). Returns ({face number (1-based, the order of
    ``TopExp.MapShapes``): (uv, triangles, moments) or None}, warnings); ``moments``: the face's
    ``FaceMoments`` for its surface's own normal, or None."""
    from OCP.BRepTools import BRepTools

    BRepTools.Clean_s(shape)  # a triangulation stored in the file or by an earlier call is replaced
    faces = _faces(shape)
    if any(_is_bspline(face) for face in faces):  # the face moments evaluate B-splines with scipy:
        import scipy.interpolate  # noqa: F401  imported once here, not again in every child
    results: dict[int, tuple | None] = {}
    notes: list[str] = []
    if time_limit is not None and hasattr(os, "fork"):
        notes = _mesh_guarded(shape, faces, tolerance, angular_tolerance, float(time_limit), results)
    else:  # unguarded: the same fallbacks in this process
        for i, face in enumerate(faces):
            for chord, angle in fallbacks(tolerance, angular_tolerance):
                data = mesh_face(face, chord, angle)
                results[i] = data if _good(data) else results.get(i) or data
                if _good(data):
                    break
    return {i + 1: None if data is None else (data[0], data[1], data[3]) for i, data in results.items()}, notes


def face_triangles(face, surface, data) -> tuple[np.ndarray, np.ndarray] | None:
    """(vertices (n, 3), triangles (m, 3)) of a face meshed by :func:`mesh_shape` (``data``: its
    (uv, triangles, ...) or None), wound outward, vertices at the surface's points S(u, v) of the nodes
    (``surface``: an adaptor of the face's located surface); None when there are no triangles."""
    from OCP.TopAbs import TopAbs_Orientation

    if data is None:
        return None
    uv, triangles = data[:2]
    vertices = np.empty((len(uv), 3))
    for k, (u, v) in enumerate(uv):
        p = surface.Value(float(u), float(v))
        vertices[k] = (p.X(), p.Y(), p.Z())
    if face.Orientation() == TopAbs_Orientation.TopAbs_REVERSED:
        triangles = triangles[:, [0, 2, 1]]
    # triangles at a pole (a sphere's, a cone's apex) have two nodes at the same point: dropped
    P = vertices[triangles]
    twice_area = np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), axis=1)
    scale = float(np.ptp(vertices, axis=0).max()) if len(vertices) else 0.0
    triangles = triangles[twice_area > 1e-14 * scale**2]
    if not len(triangles):
        return None
    return vertices, triangles
