"""3D core: Lame's thick sphere octant (examples/solid/lame_sphere.toml) over a ladder
of element sizes, each in its own process: dofs, grid / assembly / solve times, assembly rate
in cells per second, peak memory, the largest radial-displacement error over 200 interior
points against Lame, and the fitted convergence slope. ``--large`` adds h = 0.0228 (about 1.03M
dofs, AMG-CG).

    python benchmarks/solid.py [--quick] [--large] [--sizes H ...]

Prints a table and writes benchmarks/results/solid.json."""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

CHILD = r"""
import json, resource, sys, time, tomllib
import numpy as np
from ibfem.solver.io.scene import load_scene
from ibfem.solver.solving import solve
from ibfem.solver.reference.theory import lame_sphere
h = float(sys.argv[1])
d = tomllib.load(open(sys.argv[2], "rb"))
d["bodies"][0]["element_size"] = h
d["output"] = {"vtk": False}
scene = load_scene(d, label="lame_sphere.toml", base_dir=".")
t = time.perf_counter()
sol = solve(scene.problem)
wall = time.perf_counter() - t
rng = np.random.default_rng(0)
u = np.abs(rng.normal(size=(200, 3)))
u /= np.linalg.norm(u, axis=1)[:, None]
r = rng.uniform(1.2, 1.8, 200)
exact = lame_sphere(r, 1.0, 2.0, 1e8, 2e11, 0.3)[0]
radial = np.einsum("qi,qi->q", sol.displacement(u * r[:, None]), u)
err = float(np.max(np.abs(radial / exact - 1.0)))
cells = sol.body_info["shell"]["elements"]
print(json.dumps({"h": h, "dofs": sol.body_info["shell"]["dofs"], "cells": cells, "wall_s": wall,
                  "grid_s": sol.timings["grid_s"], "assembly_s": sol.timings["assembly_s"],
                  "solve_s": sol.timings["solve_s"],
                  "cells_per_s": cells / (sol.timings["grid_s"] + sol.timings["assembly_s"]),
                  "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, "max_error": err}))
"""


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="two coarse grids only")
    ap.add_argument("--large", action="store_true", help="add h = 0.0228 (about 1.03M dofs)")
    ap.add_argument("--sizes", type=float, nargs="+", metavar="H", help="run these element sizes only")
    args = ap.parse_args(argv)
    sizes = [0.25, 0.125] if args.quick else [0.25, 0.125, 0.0625, 0.045]
    if args.large:
        sizes.append(0.0228)
    if args.sizes:
        sizes = args.sizes
    scene = ROOT / "examples" / "solid" / "lame_sphere.toml"
    rows = []
    print(f"{'h':>7} {'dofs':>8} {'grid s':>7} {'assem s':>8} {'solve s':>8} {'cells/s':>9} {'MB':>7} {'max err u_r':>12}")
    for h in sizes:
        out = subprocess.run([sys.executable, "-c", CHILD, str(h), str(scene)], capture_output=True, text=True, cwd=ROOT)
        if out.returncode != 0:
            print(out.stderr, file=sys.stderr)
            return 1
        row = json.loads(out.stdout.strip().splitlines()[-1])
        rows.append(row)
        print(f"{h:7.4f} {row['dofs']:8d} {row['grid_s']:7.2f} {row['assembly_s']:8.2f} {row['solve_s']:8.2f} "
              f"{row['cells_per_s']:9.0f} {row['peak_mb']:7.0f} {row['max_error']:12.2e}", flush=True)
    import numpy as np

    hs = np.log([r["h"] for r in rows])
    errs = np.log([r["max_error"] for r in rows])
    slope = float(np.polyfit(hs, errs, 1)[0]) if len(rows) > 1 else float("nan")
    print(f"convergence slope of the radial displacement: {slope:.2f}")
    out_dir = HERE / "results"
    out_dir.mkdir(exist_ok=True)
    (out_dir / "solid.json").write_text(json.dumps({"rows": rows, "slope": slope}, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
