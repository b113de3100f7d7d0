"""Direct (SuperLU) against iterative (CG + smoothed-aggregation AMG) linear solves on the turned
Lame annulus of examples/single_body, each size and solver in its own process (wall time, peak
memory, error of the radial displacement against Lame).

    python benchmarks/linear_solvers.py [--quick] [--sizes H ...]

Prints a table and writes benchmarks/results/linear_solvers.json. The crossover measured here
sets solver.fem.linalg.ITERATIVE_DOFS (the "auto" choice)."""

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
from ibfem import solver
h, method = float(sys.argv[1]), sys.argv[2]
d = tomllib.load(open(sys.argv[3], "rb"))
d["bodies"][0]["element_size"] = h
d["output"] = {"vtk": False}
d["solver"] = {"linear_solver": method}
scene = solver.load_scene(d, base_dir=".")
t = time.perf_counter()
sol = solver.solve(scene.problem)
wall = time.perf_counter() - t
turn = np.radians(30.0)
pts = np.array([[1.2, 0.3], [0.5, 1.6]]) @ np.array([[np.cos(turn), np.sin(turn)], [-np.sin(turn), np.cos(turn)]])
r = np.linalg.norm(pts, axis=1)
E, nu, p, a, b = 2e11, 0.3, 1e8, 1.0, 2.0
exact = p * a**2 / (E * (b**2 - a**2)) * (1 + nu) * ((1 - 2 * nu) * r + b**2 / r)
err = float(np.max(np.abs(np.linalg.norm(sol.displacement(pts), axis=1) - exact) / exact))
print(json.dumps({"h": h, "method": method, "dofs": sol.body_info["ring"]["dofs"], "solve_s": wall,
                  "linear_s": sol.timings.get("solve_s"), "converged": sol.converged, "error": err,
                  "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e3}))
"""


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="two small sizes only")
    ap.add_argument("--sizes", type=float, nargs="*", default=None, help="element sizes (m)")
    args = ap.parse_args(argv)
    sizes = args.sizes or ([0.01, 0.005] if args.quick else [0.01, 0.005, 0.0035, 0.0022])
    scene = ROOT / "examples" / "single_body" / "lame_quarter_annulus_turned.toml"
    rows = []
    for h in sizes:
        for method in ("direct", "iterative"):  # alternating, each in its own process
            out = subprocess.run([sys.executable, "-c", CHILD, str(h), method, str(scene)], capture_output=True,
                                 text=True, cwd=ROOT)
            if out.returncode:
                print(f"h = {h} {method}: failed\n{out.stderr[-2000:]}", file=sys.stderr)
                continue
            row = json.loads(out.stdout.strip().splitlines()[-1])
            rows.append(row)
            print(f"h={h:<8g} {method:9s} dofs={row['dofs']:>8d} solve {row['solve_s']:7.2f} s (linear "
                  f"{row['linear_s']:6.2f} s)  peak {row['peak_mb']:7.0f} MB  error {row['error']:.1e}", flush=True)
    (HERE / "results").mkdir(exist_ok=True)
    (HERE / "results" / "linear_solvers.json").write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
