"""Signed distances of STEP solids near their edges, vertices and seams against OpenCascade's own
answers: the side by ``BRepClass3d_SolidClassifier``, the distance to the boundary by
``BRepExtrema_DistShapeShape`` (independent of the importer's surfaces, tessellation and edges).

The parts are built here with OpenCascade and written to STEP: a box with two rounded edges (planes
meeting cylinders tangentially, corners where a fillet ends), the quarter of a ball's lower half
(two symmetry planes and a sphere meeting at the pole, as in the shipped CAD example) and a
cylinder with a chamfered rim (a cone, the cylinder's seam). The points are scattered about every
edge at a third of, at and at three times the tessellation's tolerance: where a face's triangles
alone cannot tell whether a foot lies on the face.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("OCP")

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "examples" / "cad"))

import make_quarter_ball  # noqa: E402
import test_step_support as S  # noqa: E402
from ibfem.geometry.solids.part_solid import PartSolid  # noqa: E402
from ibfem.importers.step import load_part  # noqa: E402

MM = 1e-3


def _edges(shape):
    from OCP.TopAbs import TopAbs_ShapeEnum
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    explorer = TopExp_Explorer(shape, TopAbs_ShapeEnum.TopAbs_EDGE)
    while explorer.More():
        yield TopoDS.Edge(explorer.Current())
        explorer.Next()


def box_with_two_fillets():
    """A 20 x 30 x 10 mm box with a vertical and a horizontal edge rounded (radius 4 mm)."""
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox

    box = BRepPrimAPI_MakeBox(20.0, 30.0, 10.0).Shape()
    fillet = BRepFilletAPI_MakeFillet(box)
    for k, edge in enumerate(_edges(box)):
        if k in (0, 5):
            fillet.Add(4.0, edge)
    return fillet.Shape()


def chamfered_cylinder():
    """A cylinder of radius 10 mm and height 20 mm, its top rim chamfered 2 mm."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeChamfer
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder

    cylinder = BRepPrimAPI_MakeCylinder(10.0, 20.0).Shape()
    chamfer = BRepFilletAPI_MakeChamfer(cylinder)
    for edge in _edges(cylinder):
        curve = BRepAdaptor_Curve(edge)
        if curve.GetType().name == "GeomAbs_Circle" and curve.Value(curve.FirstParameter()).Z() > 10.0:
            chamfer.Add(2.0, edge)
    return chamfer.Shape()


PARTS = {"rounded box": box_with_two_fillets, "quarter ball": make_quarter_ball.build,
         "chamfered cylinder": chamfered_cylinder}


def _edge_samples(shape, per_edge: int = 12) -> np.ndarray:
    """Points (mm) along every edge of the shape, seams and their ends included."""
    from OCP.BRep import BRep_Tool
    from OCP.BRepAdaptor import BRepAdaptor_Curve

    out = []
    for edge in _edges(shape):
        if BRep_Tool.Degenerated_s(edge):
            continue
        curve = BRepAdaptor_Curve(edge)
        for t in np.linspace(curve.FirstParameter(), curve.LastParameter(), per_edge):
            p = curve.Value(t)
            out.append([p.X(), p.Y(), p.Z()])
    return np.array(out)


def _kernel(shape, points_mm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """OpenCascade's side (+1 inside, -1 outside, 0 on) and distance to the shell (mm)."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex
    from OCP.BRepClass3d import BRepClass3d_SolidClassifier
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape
    from OCP.gp import gp_Pnt
    from OCP.TopAbs import TopAbs_ShapeEnum, TopAbs_State
    from OCP.TopExp import TopExp_Explorer

    shell = TopExp_Explorer(shape, TopAbs_ShapeEnum.TopAbs_SHELL).Current()
    classifier = BRepClass3d_SolidClassifier(shape)
    side, dist = [], []
    for x in points_mm:
        p = gp_Pnt(*map(float, x))
        classifier.Perform(p, 1e-9)
        state = classifier.State()
        side.append(1 if state == TopAbs_State.TopAbs_IN else -1 if state == TopAbs_State.TopAbs_OUT else 0)
        dist.append(BRepExtrema_DistShapeShape(BRepBuilderAPI_MakeVertex(p).Vertex(), shell).Value())
    return np.array(side), np.array(dist)


@pytest.mark.parametrize("name", sorted(PARTS))
def test_signed_distance_near_edges_agrees_with_the_kernel(name, tmp_path):
    from ibfem.importers.step.reader import _quiet_messenger

    _quiet_messenger()
    shape = PARTS[name]()
    solid = PartSolid(load_part(str(S.write_step(shape, tmp_path / "part.step"))))
    tol = solid.tolerance / MM
    rng = np.random.default_rng(3)
    along = _edge_samples(shape)
    points = np.concatenate([along + rng.normal(scale=s * tol, size=along.shape) for s in (1 / 3, 1.0, 3.0)])
    side, dist = _kernel(shape, points)
    got = np.asarray(solid.signed_distance(points * MM), float) / MM
    decided = side != 0
    assert decided.sum() > 0.95 * len(points)
    wrong = np.flatnonzero(decided & (np.sign(got) != side))
    assert not len(wrong), (len(wrong), points[wrong[:3]], got[wrong[:3]], side[wrong[:3]])
    # the kernel's distance is exact to its own precision (1e-7 mm); the faces' are to round-off
    assert np.abs(np.abs(got) - dist).max() < 1e-6, np.abs(np.abs(got) - dist).max()


def test_a_foot_just_beyond_a_symmetry_face_rim_is_no_foot(tmp_path):
    """Beside a symmetry plane of the quarter ball, just below the sphere: the plane's foot lies
    outside its quarter disc (by less than the tessellation's sag), so the nearest point is on the
    sphere and the point is outside, |x - c| - R away (c the centre, R = 25 mm)."""
    solid = PartSolid(load_part(str(make_quarter_ball.write(tmp_path / "quarter.step"))))
    p = np.array([[0.563, 0.048, -0.05], [3.0, 0.02, 0.15]])  # mm
    want = 25.0 - np.linalg.norm(p - [0.0, 0.0, 25.0], axis=1)
    assert solid.tolerance / MM > 0.048  # the band the triangles alone would accept
    got = np.asarray(solid.signed_distance(p * MM), float) / MM
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)
