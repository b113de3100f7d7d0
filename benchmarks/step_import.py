"""Import time of a STEP part with a few hundred faces: a 240 x 240 x 10 mm plate with a
12 x 12 grid of holes R = 5 mm, each hole's top edge filleted R = 1 mm (6 planes, 144 cylinders,
144 tori: 294 faces). Builds the part with OpenCascade, writes it to a temporary STEP file, then
times ``importers.step.load_part`` (read, mesh, build; median of 3) and ``verify_projection``.

Run: .venv/bin/python benchmarks/step_import.py (also in make bench)
"""

from __future__ import annotations

import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

N, PITCH, R_HOLE, R_FILLET = 12, 20.0, 5.0, 1.0


def plate_with_holes():
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCylinder
    from OCP.BRep import BRep_Builder
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.GeomAbs import GeomAbs_CurveType
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt
    from OCP.TopAbs import TopAbs_ShapeEnum
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS, TopoDS_Compound

    plate = BRepPrimAPI_MakeBox(N * PITCH, N * PITCH, 10.0).Shape()
    tools = TopoDS_Compound()
    builder = BRep_Builder()
    builder.MakeCompound(tools)
    for i in range(N):
        for j in range(N):
            axis = gp_Ax2(gp_Pnt((i + 0.5) * PITCH, (j + 0.5) * PITCH, -1.0), gp_Dir(0, 0, 1), gp_Dir(0, 1, 0))
            builder.Add(tools, BRepPrimAPI_MakeCylinder(axis, R_HOLE, 12.0).Shape())
    drilled = BRepAlgoAPI_Cut(plate, tools).Shape()
    fillet = BRepFilletAPI_MakeFillet(drilled)
    explorer = TopExp_Explorer(drilled, TopAbs_ShapeEnum.TopAbs_EDGE)
    while explorer.More():
        edge = TopoDS.Edge(explorer.Current())
        curve = BRepAdaptor_Curve(edge)
        if curve.GetType() == GeomAbs_CurveType.GeomAbs_Circle and curve.Value(0.0).Z() > 5.0:
            fillet.Add(R_FILLET, edge)
        explorer.Next()
    return fillet.Shape()


def main() -> None:
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer

    from ibfem.geometry.verify import verify_projection
    from ibfem.importers.step import load_part
    from ibfem.importers.step.reader import _quiet_messenger

    _quiet_messenger()
    t0 = time.perf_counter()
    shape = plate_with_holes()
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "plate.step"
        writer = STEPControl_Writer()
        writer.Transfer(shape, STEPControl_AsIs)
        writer.Write(str(path))
        print(f"built and wrote {path.stat().st_size / 1e6:.2f} MB in {time.perf_counter() - t0:.1f} s")
        times, part = [], None
        for _ in range(3):
            t = time.perf_counter()
            part = load_part(path)
            times.append(time.perf_counter() - t)
        t = time.perf_counter()
        report = verify_projection(part, 1e-4)
        t_verify = time.perf_counter() - t
    counts = ", ".join(f"{n} {k}" for k, n in sorted(part.faces_by_type().items()))
    tris = sum(len(f.mesh.faces) for f in part.faces.values() if f.mesh is not None)
    print(f"{len(part.faces)} faces ({counts}), {len(part.edges)} edges, {tris} triangles")
    print(f"load_part: median {statistics.median(times):.2f} s of {', '.join(f'{x:.2f}' for x in times)} "
          f"(last: {part.metadata['timing']})")
    print(f"verify: {t_verify:.2f} s, max position error {report['max_error']:.2e} m, "
          f"normal error {report['max_normal_error']:.2e} rad")


if __name__ == "__main__":
    main()
