"""Write fixtures/step/half_cylinder_on_block.step: the `make demo` geometry (fixtures/onshape/half_cylinder_on_block)
built with OpenCascade, so the STEP import can be compared with the Onshape one.

A half cylinder R = 50 mm (centre (0, 50) mm, its lower half) resting on a 200 x 100 mm block (top at
y = 0), both extruded 20 mm along +z, in millimetres (the STEP file's unit; the importer converts to
metres). The solids are named in the file ('half cylinder', 'block') by their MANIFOLD_SOLID_BREP
entities. Run: .venv/bin/python examples/step/make_half_cylinder_on_block.py (deterministic, < 1 s).
"""

from __future__ import annotations

import re
from pathlib import Path

HERE = Path(__file__).resolve().parent


def build():
    """The two solids: the half cylinder as the extrusion of a half disk (one cylindrical face),
    the block as a box."""
    from OCP.BRep import BRep_Builder
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeWire
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakePrism
    from OCP.GC import GC_MakeArcOfCircle
    from OCP.gp import gp_Pnt, gp_Vec
    from OCP.TopoDS import TopoDS_Compound

    left, bottom, right = gp_Pnt(-50, 50, 0), gp_Pnt(0, 0, 0), gp_Pnt(50, 50, 0)
    arc = BRepBuilderAPI_MakeEdge(GC_MakeArcOfCircle(left, bottom, right).Value()).Edge()
    flat = BRepBuilderAPI_MakeEdge(right, left).Edge()
    half_disk = BRepBuilderAPI_MakeFace(BRepBuilderAPI_MakeWire(arc, flat).Wire(), True).Face()
    half = BRepPrimAPI_MakePrism(half_disk, gp_Vec(0, 0, 20)).Shape()
    block = BRepPrimAPI_MakeBox(gp_Pnt(-100, -100, 0), gp_Pnt(100, 0, 20)).Shape()
    compound = TopoDS_Compound()
    builder = BRep_Builder()
    builder.MakeCompound(compound)
    builder.Add(compound, half)
    builder.Add(compound, block)
    return compound


def write(path: Path = HERE.parents[1] / "fixtures" / "step" / "half_cylinder_on_block.step") -> Path:
    from OCP.Interface import Interface_Static
    from OCP.Message import Message, Message_Gravity
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer

    for printer in Message.DefaultMessenger_s().Printers():
        printer.SetTraceLevel(Message_Gravity.Message_Fail)
    writer = STEPControl_Writer()
    Interface_Static.SetCVal_s("write.step.unit", "MM")
    writer.Transfer(build(), STEPControl_AsIs)
    writer.Write(str(path))
    text = path.read_text()
    # the products of the solids, in order: OpenCascade names them "... translator 8.0 W.k", W counting
    # the writes of this process
    for k, name in enumerate(("half cylinder", "block"), 1):
        text = re.sub(rf"PRODUCT\('[^']*translator[^']* \d+\.{k}',\s*'[^']*'", f"PRODUCT('{name}','{name}'", text)
    text = re.sub(r"'\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d'", "'2026-01-01T00:00:00'", text)  # a stable file
    path.write_text(text)
    return path


if __name__ == "__main__":
    print(f"wrote {write()}")
