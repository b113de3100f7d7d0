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


def run(spacing: float, band_fraction: float | None, offset: list[float] | None, out: Path) -> dict:
    """The example at this sample spacing and grid offset: its cycles against the closed form."""
    from ibfem.solver.io.output import write_scene_results
    from ibfem.solver.io.scene import scene_from_dict
    from ibfem.solver.reports.validate_fretting import compare
    from ibfem.solver.solving import solve

    data = tomllib.loads(EXAMPLE.read_text(encoding="utf-8"))
    data["output"] = {"vtk": False, "plots": False}
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
    result = compare(summary, dict(np.load(out / "profiles_0.npz")), 1.0, 2.0e11, 0.3)
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
    ap.add_argument("--offsets", type=float, nargs="+", default=[0.37, 0.21, 0.13, 0.71],
                    help="pairs of grid offsets (fractions of the coarsest cell)")
    args = ap.parse_args(argv)
    if len(args.offsets) % 2:
        ap.error("--offsets takes pairs")
    offsets = [args.offsets[i:i + 2] for i in range(0, len(args.offsets), 2)]
    ok = True
    with tempfile.TemporaryDirectory() as tmp:
        for spacing in args.spacings:
            print(f"sample_spacing {spacing:g}, band_fraction {args.band_fraction or 'default'} (J/m; against the closed form)")
            base = run(spacing, args.band_fraction, None, Path(tmp) / "aligned")
            print(_line("aligned", base, None))
            ok &= base["converged"]
            for off in offsets:
                r = run(spacing, args.band_fraction, off, Path(tmp) / "shifted")
                print(_line(f"shift {off[0]:g}, {off[1]:g}", r, base))
                ok &= r["converged"]
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
