"""OpenCascade-built parts for the STEP/IGES importer tests: the true parameters are
the ones passed to OpenCascade here, in millimetres, independent of the reader."""

from __future__ import annotations

import math
from pathlib import Path

MM = 1e-3
ORIGIN = (1.0, 2.0, 3.0)  # mm
AXIS = (0.0, 0.6, 0.8)
CYLINDER = {"radius": 10.0, "height": 30.0}
SPHERE = {"radius": 7.0}
CONE = {"r1": 10.0, "r2": 4.0, "height": 20.0}
TORUS = {"major": 20.0, "minor": 5.0}
BOX = (20.0, 30.0, 10.0)
FILLET = 3.0
PRISM_POLES = [(0.0, 0.0, 0.0), (10.0, 5.0, 0.0), (20.0, -3.0, 0.0), (30.0, 0.0, 0.0)]
PRISM_HEIGHT = 15.0
REVOLVED_POINTS = [(5.0, 0.0, 0.0), (8.0, 0.0, 3.0), (6.0, 0.0, 7.0), (9.0, 0.0, 10.0)]
LOFT_SECTIONS = [(10.0, 0.0), (6.0, 10.0), (9.0, 20.0)]


def _ax2():
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

    return gp_Ax2(gp_Pnt(*ORIGIN), gp_Dir(*AXIS))


def _bspline_through(points):
    from OCP.collections import Array1_gp_Pnt
    from OCP.GeomAPI import GeomAPI_PointsToBSpline
    from OCP.gp import gp_Pnt

    arr = Array1_gp_Pnt(1, len(points))
    for i, p in enumerate(points, 1):
        arr.SetValue(i, gp_Pnt(*p))
    return GeomAPI_PointsToBSpline(arr).Curve()


def _polygon_face(first_edge, corners):
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeWire
    from OCP.gp import gp_Pnt

    wire = BRepBuilderAPI_MakeWire()
    wire.Add(first_edge)
    for a, b in zip(corners[:-1], corners[1:]):
        wire.Add(BRepBuilderAPI_MakeEdge(gp_Pnt(*a), gp_Pnt(*b)).Edge())
    return BRepBuilderAPI_MakeFace(wire.Wire(), True).Face()


def filleted_box():
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox
    from OCP.TopAbs import TopAbs_ShapeEnum
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    box = BRepPrimAPI_MakeBox(*BOX).Shape()
    fillet = BRepFilletAPI_MakeFillet(box)
    explorer = TopExp_Explorer(box, TopAbs_ShapeEnum.TopAbs_EDGE)
    while explorer.More():
        fillet.Add(FILLET, TopoDS.Edge(explorer.Current()))
        explorer.Next()
    return fillet.Shape()


def revolved():
    """A B-spline profile in the xz plane (x from 5 to 9 mm) turned about z."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeRevol
    from OCP.gp import gp_Ax1, gp_Dir, gp_Pnt

    curve = _bspline_through(REVOLVED_POINTS)
    face = _polygon_face(BRepBuilderAPI_MakeEdge(curve).Edge(),
                         [REVOLVED_POINTS[-1], (0.0, 0.0, 10.0), (0.0, 0.0, 0.0), REVOLVED_POINTS[0]])
    return BRepPrimAPI_MakeRevol(face, gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1))).Shape()


def prism():
    """A B-spline edge and three lines in z = 0, extruded 15 mm along z; returns (shape, curve)."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge
    from OCP.BRepPrimAPI import BRepPrimAPI_MakePrism
    from OCP.gp import gp_Vec

    curve = _bspline_through(PRISM_POLES)
    face = _polygon_face(BRepBuilderAPI_MakeEdge(curve).Edge(),
                         [PRISM_POLES[-1], (30.0, -20.0, 0.0), (0.0, -20.0, 0.0), PRISM_POLES[0]])
    return BRepPrimAPI_MakePrism(face, gp_Vec(0, 0, PRISM_HEIGHT)).Shape(), curve


def loft():
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeWire
    from OCP.BRepOffsetAPI import BRepOffsetAPI_ThruSections
    from OCP.gp import gp_Ax2, gp_Circ, gp_Dir, gp_Pnt

    sections = BRepOffsetAPI_ThruSections(True, False)
    for r, z in LOFT_SECTIONS:
        circle = gp_Circ(gp_Ax2(gp_Pnt(0, 0, z), gp_Dir(0, 0, 1)), r)
        sections.AddWire(BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(circle).Edge()).Wire())
    sections.Build()
    return sections.Shape()


def primitives() -> dict:
    from OCP.BRepPrimAPI import (BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCone, BRepPrimAPI_MakeCylinder,
                                 BRepPrimAPI_MakeSphere, BRepPrimAPI_MakeTorus)
    from OCP.gp import gp_Pnt

    return {
        "cylinder": BRepPrimAPI_MakeCylinder(_ax2(), CYLINDER["radius"], CYLINDER["height"]).Shape(),
        "sphere": BRepPrimAPI_MakeSphere(gp_Pnt(*ORIGIN), SPHERE["radius"]).Shape(),
        "cone": BRepPrimAPI_MakeCone(_ax2(), CONE["r1"], CONE["r2"], CONE["height"]).Shape(),
        "torus": BRepPrimAPI_MakeTorus(_ax2(), TORUS["major"], TORUS["minor"]).Shape(),
        "box": BRepPrimAPI_MakeBox(25.4, 50.8, 12.7).Shape(),
        "fillet": filleted_box(),
        "revolved": revolved(),
        "prism": prism()[0],
        "loft": loft(),
    }


def write_step(shape, path: Path, unit: str = "MM") -> Path:
    """Write ``shape`` (built in mm) to a STEP file whose length unit is ``unit``."""
    from OCP.Interface import Interface_Static
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer

    writer = STEPControl_Writer()
    before = Interface_Static.CVal_s("write.step.unit")
    Interface_Static.SetCVal_s("write.step.unit", unit)
    try:
        writer.Transfer(shape, STEPControl_AsIs)
        writer.Write(str(path))
    finally:
        Interface_Static.SetCVal_s("write.step.unit", before)
    return path


def write_iges(shape, path: Path, unit: str = "MM") -> Path:
    from OCP.IGESControl import IGESControl_Writer

    writer = IGESControl_Writer(unit, 1)  # B-rep mode: solids, not loose surfaces
    writer.AddShape(shape)
    writer.ComputeModel()
    writer.Write(str(path))
    return path


def solid_contains(shape, point_m) -> bool:
    """OpenCascade's classification of a point (m) against a solid built in mm (strictly inside)."""
    from OCP.BRepClass3d import BRepClass3d_SolidClassifier
    from OCP.gp import gp_Pnt
    from OCP.TopAbs import TopAbs_State

    c = BRepClass3d_SolidClassifier(shape, gp_Pnt(*(float(x) / MM for x in point_m)), 1e-9)
    return c.State() == TopAbs_State.TopAbs_IN


def exact_area(face_shape) -> float:
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    props = GProp_GProps()
    BRepGProp.SurfaceProperties_s(face_shape, props)
    return props.Mass()


def rounded_box_volume(a: float, b: float, c: float, r: float) -> float:
    """Steiner's formula: the box with edges rounded by r is the inner box (a-2r, b-2r, c-2r)
    grown by a ball of radius r."""
    p, q, s = a - 2 * r, b - 2 * r, c - 2 * r
    return p * q * s + 2 * (p * q + q * s + s * p) * r + math.pi * (p + q + s) * r**2 + 4.0 / 3.0 * math.pi * r**3
