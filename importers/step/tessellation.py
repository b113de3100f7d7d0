"""Triangles of the faces: OpenCascade's incremental mesher (``BRepMesh_IncrementalMesh``) at a
chord tolerance (linear deflection, m) and an angular tolerance (rad) the user can set.

Each face's triangulation is read with its nodes' (u, v) parameters; the vertices are the face's
surface evaluated there, ``S(u, v)``. For nodes inside the face this is what the mesher computed
anyway; for nodes on the face's edges it puts them on this face's surface (the edge's 3D curve
may stray from it by up to the edge's tolerance, 1e-7 m typically), so every vertex lies on the
exact surface the face carries, as the projection check of ``ibfem verify`` expects. Triangles of
reversed faces are re-wound, so every face's triangles are wound with the solid's outward normal;
triangles of zero area (two nodes at a pole) are dropped.
"""

from __future__ import annotations

import numpy as np

__all__ = ["mesh_shape", "face_triangles", "default_tolerance", "DEFAULT_ANGULAR_TOLERANCE"]

DEFAULT_ANGULAR_TOLERANCE = 0.25  # rad
DEFAULT_RELATIVE_TOLERANCE = 1e-3  # of the bounding box diagonal


def default_tolerance(shape) -> float:
    """Chord tolerance of 1e-3 of the shape's bounding-box diagonal (m)."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    box = Bnd_Box()
    BRepBndLib.Add_s(shape, box)
    lo, hi = box.CornerMin(), box.CornerMax()
    diag = float(np.linalg.norm([hi.X() - lo.X(), hi.Y() - lo.Y(), hi.Z() - lo.Z()]))
    return DEFAULT_RELATIVE_TOLERANCE * diag if diag > 0 else 1e-6


def mesh_shape(shape, tolerance: float, angular_tolerance: float = DEFAULT_ANGULAR_TOLERANCE) -> None:
    """Triangulate every face of ``shape`` in place (chord ``tolerance`` m, ``angular_tolerance`` rad)."""
    from OCP.BRepMesh import BRepMesh_IncrementalMesh
    from OCP.BRepTools import BRepTools

    BRepTools.Clean_s(shape)  # a triangulation stored in the file or by an earlier call is replaced
    mesher = BRepMesh_IncrementalMesh(shape, float(tolerance), False, float(angular_tolerance), False)
    mesher.Perform()


def face_triangles(face, surface) -> tuple[np.ndarray, np.ndarray] | None:
    """(vertices (n, 3), triangles (m, 3)) of a meshed face, wound outward, vertices at the
    surface's points S(u, v) of the nodes (``surface``: an adaptor of the face's located
    surface); None when the mesher produced nothing for the face."""
    from OCP.BRep import BRep_Tool
    from OCP.TopAbs import TopAbs_Orientation
    from OCP.TopLoc import TopLoc_Location

    loc = TopLoc_Location()
    tri = BRep_Tool.Triangulation_s(face, loc)
    if tri is None or tri.NbTriangles() == 0:
        return None
    n = tri.NbNodes()
    if tri.HasUVNodes():
        vertices = np.empty((n, 3))
        for i in range(1, n + 1):
            uv = tri.UVNode(i)
            p = surface.Value(uv.X(), uv.Y())
            vertices[i - 1] = (p.X(), p.Y(), p.Z())
    else:  # pragma: no cover - BRepMesh always stores (u, v)
        trsf = loc.Transformation()
        vertices = np.array([[q.X(), q.Y(), q.Z()] for q in (tri.Node(i).Transformed(trsf) for i in range(1, n + 1))])
    triangles = np.array([tri.Triangle(i).Get() for i in range(1, tri.NbTriangles() + 1)], dtype=np.int64) - 1
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
