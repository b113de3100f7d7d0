"""Write quarter_ball.step: a quarter of a ball's lower half, written by OpenCascade, in millimetres.

The ball has radius 25 mm and its centre at (0, 0, 25) mm, so that its lowest point touches the
plane z = 0 at the origin. The part is the lower half (z <= 25 mm) cut by the planes x = 0 and
y = 0 to the quarter x >= 0, y >= 0: one spherical face, the flat top (z = 25 mm) and two flat
symmetry faces. The sphere's axis is the z axis, so the sphere's pole (a singular point of its
parametrisation) is the contact point: the importer has to project there exactly.

The solid is named 'quarter ball' in the file (its product). Run:
    .venv/bin/python examples/cad/make_quarter_ball.py [OUT.step]
(deterministic, under a second; the scene examples/cad/quarter_ball_on_block.toml reads the file).
"""

from __future__ import annotations

import math
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
RADIUS_MM = 25.0


def build(radius: float = RADIUS_MM):
    """The quarter half ball as an OpenCascade solid (lengths in the file's unit)."""
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeSphere
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

    frame = gp_Ax2(gp_Pnt(0.0, 0.0, radius), gp_Dir(0.0, 0.0, 1.0), gp_Dir(1.0, 0.0, 0.0))
    # latitudes from the lower pole to the equator, longitudes from the x axis to the y axis
    return BRepPrimAPI_MakeSphere(frame, radius, -math.pi / 2, 0.0, math.pi / 2).Shape()


def write_step(shape, path: Path, name: str) -> Path:
    """Write an OpenCascade ``shape`` to ``path`` as STEP in millimetres with its product named
    ``name`` and a fixed time stamp (the same file on every run); returns the path."""
    from OCP.Interface import Interface_Static
    from OCP.Message import Message, Message_Gravity
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer

    for printer in Message.DefaultMessenger_s().Printers():
        printer.SetTraceLevel(Message_Gravity.Message_Fail)
    writer = STEPControl_Writer()
    Interface_Static.SetCVal_s("write.step.unit", "MM")
    writer.Transfer(shape, STEPControl_AsIs)
    path = Path(path)
    writer.Write(str(path))
    text = path.read_text()
    text = re.sub(r"PRODUCT\('[^']*',\s*'[^']*'", f"PRODUCT('{name}','{name}'", text, count=1)
    text = re.sub(r"'\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d'", "'2026-01-01T00:00:00'", text)  # a stable file
    path.write_text(text)
    return path


def write(path: Path = HERE / "quarter_ball.step", radius: float = RADIUS_MM, name: str = "quarter ball") -> Path:
    """Write the part to ``path`` in millimetres with its product named ``name``; returns the path."""
    return write_step(build(radius), path, name)


if __name__ == "__main__":
    print(f"wrote {write(Path(sys.argv[1]) if len(sys.argv) > 1 else HERE / 'quarter_ball.step')}")
