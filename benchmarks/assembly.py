"""Assembly rate, solve time and peak memory of the IBFEM core against problem size.

A 4 x 2 plate with a circular hole (exact arcs, cut cells all round it), sliding symmetry
edges and a traction, solved on uniform grids of decreasing element size. Each size runs in
its own subprocess so that the peak resident memory (getrusage ru_maxrss) belongs to it.

    .venv/bin/python benchmarks/assembly.py            # up to ~3e5 dofs, about a minute
    .venv/bin/python benchmarks/assembly.py --large    # adds ~1e6 dofs (minutes, ~GBs)

Writes benchmarks/results/assembly.json.
"""

from __future__ import annotations

import argparse
import json
import platform
import resource
import subprocess
import sys
import time
from pathlib import Path

DEFAULT_SIZES = [0.04, 0.02, 0.01, 0.007]
LARGE_SIZES = [0.004]


def run_one(h: float) -> dict:
    import numpy as np

    from ibfem.geometry.shapes import profile_from_shape
    from ibfem.solver.fem.space import discretise_body
    from ibfem.solver.model.options import SolverOptions
    from ibfem.solver.solving import solve
    from ibfem.solver.model.problem import BodyModel, Material, Problem, Sliding, Traction

    prof = profile_from_shape({"type": "profile", "edges": [
        {"name": "bottom", "type": "line", "start": [0.5, 0.0], "end": [4.0, 0.0]},
        {"name": "right", "type": "line", "start": [4.0, 0.0], "end": [4.0, 2.0]},
        {"name": "top", "type": "line", "start": [4.0, 2.0], "end": [0.0, 2.0]},
        {"name": "left", "type": "line", "start": [0.0, 2.0], "end": [0.0, 0.5]},
        {"name": "hole", "type": "arc", "center": [0, 0], "radius": 0.5, "start_angle": 90, "end_angle": 0}],
        "rotate_deg": 7.0})
    steel = Material("steel", 2e11, 0.3)
    body = BodyModel("plate", prof, steel, h)
    prob = Problem("bench", "plane_strain", 1.0, (body,),
                   (Sliding("plate", "bottom"), Sliding("plate", "left"), Traction("plate", "right", (1e8, 0.0))))
    settings = SolverOptions()
    # assembly alone (volume stiffness of every cell), timed apart from the solve
    t = time.perf_counter()
    disc = discretise_body(body, 0, prob.model, True, settings)
    t_grid = time.perf_counter() - t
    disc.n_total = disc.n_dofs
    t = time.perf_counter()
    k = disc.stiffness(settings.fictitious_stiffness)
    t_asm = time.perf_counter() - t
    cells = len(disc.grid.level)
    del k
    sol = solve(prob)
    rss_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    ref = np.array([-1e8 * 2.0, 0.0])  # the left edge carries the whole load back
    rel = float(np.linalg.norm(sol.reactions["plate/left"] - np.array([[np.cos(np.deg2rad(7)), -np.sin(np.deg2rad(7))], [np.sin(np.deg2rad(7)), np.cos(np.deg2rad(7))]]) @ ref) / 2e8)
    return {
        "element_size": h,
        "cells": cells,
        "cut_cells": int((disc.grid.status == 2).sum()),
        "dofs": sol.body_info["plate"]["dofs"],
        "grid_s": t_grid,
        "volume_assembly_s": t_asm,
        "assembly_cells_per_s": cells / t_asm,
        "solve_total_s": sol.timings["total_s"],
        "solve_assembly_s": sol.timings["assembly_s"],
        "linear_solve_s": sol.timings["solve_s"],
        "peak_rss_mb": rss_mb,
        "reaction_equilibrium_error": rel,
    }


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--large", action="store_true", help="add the ~1e6 dof size")
    ap.add_argument("--single", type=float, help=argparse.SUPPRESS)
    ap.add_argument("--out", default=str(Path(__file__).parent / "results" / "assembly.json"))
    args = ap.parse_args()
    if args.single is not None:
        print(json.dumps(run_one(args.single)))
        return 0
    sizes = DEFAULT_SIZES + (LARGE_SIZES if args.large else [])
    rows = []
    for h in sizes:
        r = subprocess.run([sys.executable, __file__, "--single", str(h)], capture_output=True, text=True)
        if r.returncode != 0:
            print(r.stderr, file=sys.stderr)
            return 1
        row = json.loads(r.stdout.strip().splitlines()[-1])
        rows.append(row)
        print(f"h={h:<7} cells={row['cells']:>8} dofs={row['dofs']:>8} "
              f"assembly {row['assembly_cells_per_s']:.3g} cells/s ({row['volume_assembly_s']:.2f} s), "
              f"grid {row['grid_s']:.2f} s, solve {row['linear_solve_s']:.2f} s, total {row['solve_total_s']:.2f} s, "
              f"peak {row['peak_rss_mb']:.0f} MB", flush=True)
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"machine": platform.platform(), "python": platform.python_version(), "runs": rows}, indent=2))
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
