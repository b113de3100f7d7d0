"""Volumes of CAD solids against OpenCascade: for every STEP/IGES file in a directory (or the files
given), each closed solid's PartSolid.volume and centroid (the divergence theorem over each face's
parameter domain with its exact surface) against OpenCascade's BRepGProp volume and centre of mass
of the same solid, at the file's own placement and again after the whole part is turned (0.7 rad
about [1, 2, 3]) and moved 10 times its size away (written to a temporary STEP file in metres and
imported again).

Prints a markdown table: file, solids, the largest relative difference in volume at each placement
(signed) and the solid it belongs to, the largest distance between the centroids over the solid's
size (its box diagonal) at either placement, and the seconds taken.

Run: .venv/bin/python benchmarks/cad_volumes.py DIR_OR_FILES... [--no-placed]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

SUFFIXES = {".step", ".stp", ".iges", ".igs"}


def reference_volumes(shape) -> list[tuple[float, np.ndarray]]:
    """BRepGProp volume and centre of mass of each solid of ``shape``, in the importer's order of bodies."""
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    from ibfem.importers.step.part import _bodies

    out = []
    for kind, sub, _ in _bodies(shape):
        if kind == "SOLID":
            props = GProp_GProps()
            BRepGProp.VolumeProperties_s(sub, props, 1e-10)
            c = props.CentreOfMass()
            out.append((abs(props.Mass()), np.array([c.X(), c.Y(), c.Z()])))
    return out


def part_volumes(path: Path) -> list[tuple[str, float | None, np.ndarray | None, float]]:
    """(body id, PartSolid volume and centroid, None when it is not a closed solid, size) of each
    solid body."""
    from ibfem.geometry.solids.part_solid import PartSolid
    from ibfem.importers.step import load_part

    part = load_part(path)
    out = []
    for bid, body in part.bodies.items():
        if body.body_type != "SOLID":
            continue
        try:
            solid = PartSolid(part, bid)
            out.append((bid, solid.volume, solid.centroid, solid.size))
        except ValueError:
            out.append((bid, None, None, 0.0))
    return out


def placed_copy(shape, folder: Path):
    """``shape`` turned 0.7 rad about [1, 2, 3] and moved 10 of its sizes along [1, -1, 1], as STEP:
    (path, the placement as a function of points (3,))."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Transform
    from OCP.gp import gp_Ax1, gp_Dir, gp_Pnt, gp_Trsf, gp_Vec
    from OCP.Interface import Interface_Static
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer

    box = Bnd_Box()
    BRepBndLib.Add_s(shape, box)
    lo, hi = box.CornerMin(), box.CornerMax()
    size = ((hi.X() - lo.X()) ** 2 + (hi.Y() - lo.Y()) ** 2 + (hi.Z() - lo.Z()) ** 2) ** 0.5
    turn, move = gp_Trsf(), gp_Trsf()
    turn.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(1, 2, 3)), 0.7)
    move.SetTranslation(gp_Vec(10 * size, -10 * size, 10 * size))
    placed = BRepBuilderAPI_Transform(BRepBuilderAPI_Transform(shape, turn, True).Shape(), move, True).Shape()
    writer = STEPControl_Writer()
    Interface_Static.SetCVal_s("xstep.cascade.unit", "M")  # the shape is in metres (the reader's unit)
    Interface_Static.SetCVal_s("write.step.unit", "M")
    writer.Transfer(placed, STEPControl_AsIs)
    path = folder / "placed.step"
    writer.Write(str(path))
    both = move.Multiplied(turn)

    def place(p):
        q = gp_Pnt(*map(float, p))
        q.Transform(both)
        return np.array([q.X(), q.Y(), q.Z()])

    return path, place


def _worst(volumes, reference, place=lambda p: p) -> tuple[str, float | None, float, int]:
    """(body, largest relative difference in volume, largest centroid distance / size, open bodies)
    of imported solids against the references (their centres placed by ``place``)."""
    worst, body, off, open_ = None, "", 0.0, 0
    for (bid, v, c, size), (ref, centre) in zip(volumes, reference):
        if v is None:
            open_ += 1
            continue
        d = v / ref - 1.0
        if worst is None or abs(d) > abs(worst):
            worst, body = d, bid
        off = max(off, float(np.linalg.norm(c - place(centre))) / size)
    return body, worst, off, open_


def measure(path: Path, placed: bool) -> str:
    from ibfem.importers.step.reader import read_shape

    t = time.perf_counter()
    shape, _ = read_shape(path)
    reference = reference_volumes(shape)
    if not reference:
        return f"| {path.name} | 0 | no solids | | | {time.perf_counter() - t:.0f} |"
    body, worst, off, open_ = _worst(part_volumes(path), reference)
    cells = [f"{worst:+.1e} ({body})" if worst is not None else "-"]
    if placed:
        with tempfile.TemporaryDirectory() as folder:
            copy, place = placed_copy(shape, Path(folder))
            moved = part_volumes(copy)
        if len(moved) != len(reference):
            cells.append(f"{len(moved)} solids read back")
        else:
            b2, w2, off2, _ = _worst(moved, reference, place)
            cells.append(f"{w2:+.1e} ({b2})" if w2 is not None else "-")
            off = max(off, off2)
    else:
        cells.append("not measured")
    extra = f", {open_} open" if open_ else ""
    return (f"| {path.name} | {len(reference)}{extra} | {cells[0]} | {cells[1]} | {off:.0e} | "
            f"{time.perf_counter() - t:.0f} |")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("paths", nargs="+", help="STEP/IGES files or directories holding them")
    ap.add_argument("--no-placed", action="store_true", help="only at the file's own placement")
    args = ap.parse_args(argv)
    files = []
    for p in map(Path, args.paths):
        files += sorted(f for f in p.iterdir() if f.suffix.lower() in SUFFIXES) if p.is_dir() else [p]
    print("| file | solids | largest relative difference (body) | turned and moved 10 sizes away | "
          "centroid offset / size | time (s) |")
    print("|---|---|---|---|---|---|")
    for f in files:
        try:
            print(measure(f, not args.no_placed), flush=True)
        except Exception as exc:  # one bad file must not hide the others' rows
            print(f"| {f.name} | error: {type(exc).__name__}: {exc} | | | |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
