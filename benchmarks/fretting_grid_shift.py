"""How much a shifted grid changes the 2D fretting example's energy per cycle, per sample spacing
of the friction history (the contact's ``sample_spacing``, in finest cells) and ``band_fraction``.

The example (examples/fretting/cylinder_on_flat_fretting.toml, three cycles at 20 points per
cycle) is solved on its own grid and on grids shifted by the given offsets (fractions of the
coarsest cell); per complete cycle it prints the energy from the loop and from the friction work
against the Mindlin-Deresiewicz closed form for the cycle's amplitude and normal force
(solver.reports.validate_fretting.compare), and the change each shift makes to either energy.

    .venv/bin/python benchmarks/fretting_grid_shift.py                         # 1/16 and 1/64
    .venv/bin/python benchmarks/fretting_grid_shift.py --spacings 0.0625 --band-fraction 0.25 \
        --offsets 0.37 0.21 0.13 0.71
    .venv/bin/python benchmarks/fretting_grid_shift.py --seat --offsets 0.37 0.21
    .venv/bin/python benchmarks/fretting_grid_shift.py --spacings 0.015625 --points-per-cycle 40 --offsets

``--seat`` runs instead the cylinder R = 1 m in the concave seat R = 2 m
(examples/cylinder_in_concave_partial_slip.toml) with the normal displacement held and the
tangential one (4.0e-4 m) cycled twice at 20 points per cycle, against the closed form with the
relative radius 2 m (the scene of tests/test_fretting.py's concave seat test).

Each run takes about 4 s of CPU and 0.2 GB; prints only, writes its runs' files to a temporary
folder.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
import tomllib
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
EXAMPLE = HERE.parent / "examples" / "fretting" / "cylinder_on_flat_fretting.toml"
SEAT = HERE.parent / "examples" / "cylinder_in_concave_partial_slip.toml"


def _seat_scene() -> dict:
    """The concave seat's fretting scene (two cycles of 4.0e-4 m at 20 points per cycle)."""
    data = tomllib.loads(SEAT.read_text(encoding="utf-8"))
    data["solver"].pop("load_steps", None)
    data["solver"]["steps_per_unit"] = 4
    data["paths"] = [{"name": "hold", "points": [[0.0, 0.0], [1.0, 1.0], [3.0, 1.0]]},
                     {"name": "fret", "cycle": {"amplitude": 1.0, "cycles": 2, "points_per_cycle": 20, "start": 1.0}}]
    load = data["boundary_conditions"][0]
    load.update(value=[4.0e-4, load["value"][1]], path=["fret", "hold"])
    return data


def run(spacing: float, band_fraction: float | None, offset: list[float] | None, out: Path,
        seat: bool = False, points_per_cycle: int = 20) -> dict:
    """The example (or the concave seat) at this sample spacing and grid offset: its cycles
    against the closed form."""
    from ibfem.solver.io.output import write_scene_results
    from ibfem.solver.io.scene import scene_from_dict
    from ibfem.solver.reports.validate_fretting import compare
    from ibfem.solver.solving import solve

    data = _seat_scene() if seat else tomllib.loads(EXAMPLE.read_text(encoding="utf-8"))
    data["output"] = {"vtk": False, "plots": False}
    data["paths"][1]["cycle"]["points_per_cycle"] = points_per_cycle
    data["contacts"][0]["sample_spacing"] = spacing
    if band_fraction is not None:
        data["solver"]["band_fraction"] = band_fraction
    if offset is not None:
        data["solver"]["grid_offset"] = list(offset)
    sc = scene_from_dict(data, label=str(EXAMPLE), base_dir=EXAMPLE.parent)
    cpu = time.process_time()
    solution = solve(sc.problem)
    cpu = time.process_time() - cpu
    summary = write_scene_results(out, sc, solution)
    result = compare(summary, dict(np.load(out / "profiles_0.npz")), 2.0 if seat else 1.0, 2.0e11, 0.3)
    return {"cycles": result["cycles"], "converged": solution.converged, "solves": solution.iterations["total"],
            "cpu_s": cpu, "c_error": max(abs(r["c_error_over_a"]) for r in result["steps"])}


def _line(label: str, r: dict, base: dict | None) -> str:
    text = f"  {label:<14} converged {r['converged']!s:<5} {r['solves']} solves {r['cpu_s']:.1f} s CPU, |c - c'| <= {r['c_error']:.4f} a;"
    for k, c in enumerate(r["cycles"]):
        text += (f" cycle {k + 1}: loop {c['energy_loop']:.2f} ({c['loop_error']:+.2%}), friction "
                 f"{c['energy_friction']:.2f} ({c['friction_error']:+.2%})")
        if base is not None:
            b = base["cycles"][k]
            text += (f" shift: loop {c['energy_loop'] / b['energy_loop'] - 1.0:+.2%}, friction "
                     f"{c['energy_friction'] / b['energy_friction'] - 1.0:+.2%}")
        text += ";"
    return text


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--spacings", type=float, nargs="+", default=[1.0 / 16.0, 1.0 / 64.0])
    ap.add_argument("--band-fraction", type=float, default=None)
    ap.add_argument("--points-per-cycle", type=int, default=20)
    ap.add_argument("--seat", action="store_true", help="the concave seat instead of the example")
    ap.add_argument("--offsets", type=float, nargs="*", default=[0.37, 0.21, 0.13, 0.71],
                    help="pairs of grid offsets (fractions of the coarsest cell)")
    args = ap.parse_args(argv)
    if len(args.offsets) % 2:
        ap.error("--offsets takes pairs")
    offsets = [args.offsets[i:i + 2] for i in range(0, len(args.offsets), 2)]
    ok = True
    with tempfile.TemporaryDirectory() as tmp:
        for spacing in args.spacings:
            print(f"sample_spacing {spacing:g}, band_fraction {args.band_fraction or 'default'} (J/m; against the closed form)")
            base = run(spacing, args.band_fraction, None, Path(tmp) / "aligned", args.seat, args.points_per_cycle)
            print(_line("aligned", base, None))
            ok &= base["converged"]
            for off in offsets:
                r = run(spacing, args.band_fraction, off, Path(tmp) / "shifted", args.seat, args.points_per_cycle)
                print(_line(f"shift {off[0]:g}, {off[1]:g}", r, base))
                ok &= r["converged"]
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
