"""Write ball.step: a whole ball of radius 1 mm about the origin, written by OpenCascade in millimetres.

One closed SPHERE face (bounded by its seam and two degenerate edges at the poles), as CAD systems
write a ball: the sphere's axis is -z, so one pole of its parametrisation (a singular point) is the
ball's lowest point, where it touches the block of ball_on_block_reference_point.toml. The solid is
named 'ball' in the file (its product). Run:
    .venv/bin/python examples/cad/make_ball.py [OUT.step]
(deterministic, under a second).
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
RADIUS_MM = 1.0


def build(radius: float = RADIUS_MM):
    """The ball as an OpenCascade solid (lengths in the file's unit), its axis along -z."""
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeSphere
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

    return BRepPrimAPI_MakeSphere(gp_Ax2(gp_Pnt(0.0, 0.0, 0.0), gp_Dir(0.0, 0.0, -1.0), gp_Dir(1.0, 0.0, 0.0)),
                                  radius).Shape()


def write(path: Path = HERE / "ball.step", radius: float = RADIUS_MM, name: str = "ball") -> Path:
    """Write the ball to ``path`` in millimetres with its product named ``name``; returns the path."""
    sys.path.insert(0, str(HERE))
    from make_quarter_ball import write_step  # the STEP writer of the quarter ball's script

    return write_step(build(radius), path, name)


if __name__ == "__main__":
    print(f"wrote {write(Path(sys.argv[1]) if len(sys.argv) > 1 else HERE / 'ball.step')}")
