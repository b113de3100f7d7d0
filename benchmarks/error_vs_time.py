"""Run time against error: every validation scene of examples/ on a sweep of
grids (the innermost refinement one level coarser, as shipped, one level finer), each run in
its own process so that its peak memory is its own. Per run: wall time, peak resident memory,
degrees of freedom, iterations, and the errors in a (against Hertz for the computed force),
c/a (against Cattaneo-Mindlin) and the pressure profile (RMS inside 0.9 a, in p0).

Writes benchmarks/results/error_vs_time.{json,csv} and error_vs_time.png (error in a against
wall time, one line per scene).

    .venv/bin/python benchmarks/error_vs_time.py [--quick]   # --quick: shipped grids only
"""

from __future__ import annotations

import argparse
import csv
import json
import resource
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT))

KEYS = ["scene", "level_shift", "converged", "dofs", "min_element_size", "iterations", "wall_s", "peak_rss_mb",
        "a_error", "ca_error", "pressure_rms", "shear_rms", "cells_across"]


def run_single(scene: str, shift: int) -> dict:
    """One scene with its innermost refinement shifted by ``shift`` levels (this process)."""
    from ibfem.solver.reports.validate import compare_contact, run_scene_data

    path = ROOT / "examples" / f"{scene}.toml"
    data = tomllib.loads(path.read_text())
    for body in data["bodies"]:
        ref = body.get("refinement") or []
        if ref:
            ref[-1]["levels"] = max(0, int(ref[-1]["levels"]) + shift)
    data.setdefault("output", {}).update(vtk=False, plots=False)
    t0 = time.perf_counter()
    out = Path(tempfile.gettempdir()) / f"ibfem_bench_{scene}_{shift}"
    sc, solution, summary = run_scene_data(data, path.name, out, base_dir=path.parent)
    wall = time.perf_counter() - t0
    row = {
        "scene": scene, "level_shift": shift, "converged": bool(summary["converged"]),
        "dofs": sum(b["dofs"] for b in summary["bodies"].values()),
        "min_element_size": min(b["min_element_size"] for b in summary["bodies"].values()),
        "iterations": summary["iterations"]["total"], "wall_s": wall,
        "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
    }
    if summary["contacts"]:
        m = compare_contact(sc.problem, summary["contacts"][0], summary)
        row.update({k: m.get(k) for k in ("a_error", "ca_error", "pressure_rms", "shear_rms")})
        if m.get("a_hertz"):
            row["cells_across"] = 2 * m["a_hertz"] / row["min_element_size"]
    return row


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="the shipped grids only")
    ap.add_argument("--single", nargs=2, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.single:
        print(json.dumps(run_single(args.single[0], int(args.single[1]))))
        return 0
    scenes = sorted(p.stem for p in (ROOT / "examples").glob("*.toml"))
    shifts = [0] if args.quick else [-1, 0, 1]
    rows = []
    for scene in scenes:
        for shift in shifts:
            r = subprocess.run([sys.executable, __file__, "--single", scene, str(shift)], capture_output=True, text=True)
            if r.returncode != 0:
                row = {"scene": scene, "level_shift": shift, "converged": False, "error": r.stderr.strip().splitlines()[-1:]}
            else:
                row = json.loads(r.stdout.strip().splitlines()[-1])
            rows.append(row)
            a_err = row.get("a_error")
            print(f"{scene:36s} levels {shift:+d}: dofs {row.get('dofs', 0):7d}  {row.get('wall_s', float('nan')):6.2f} s  "
                  f"{row.get('peak_rss_mb', float('nan')):6.0f} MB  error in a "
                  + (f"{100 * a_err:6.2f} %" if isinstance(a_err, float) else "   n/a"), flush=True)
    out = HERE / "results"
    out.mkdir(exist_ok=True)
    (out / "error_vs_time.json").write_text(json.dumps(rows, indent=2))
    with open(out / "error_vs_time.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=KEYS, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(7, 5))
        for scene in scenes:
            pts = sorted((r["wall_s"], 100 * r["a_error"]) for r in rows
                         if r["scene"] == scene and isinstance(r.get("a_error"), float) and r.get("wall_s"))
            if pts:
                ax.plot(*zip(*pts), "o-", label=scene)
        ax.set(xlabel="wall time [s]", ylabel="error in a against Hertz [%]", yscale="log",
               title="run time against error (grids: innermost level -1, 0, +1)")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out / "error_vs_time.png", dpi=90)
    except ImportError:
        pass
    print(f"written {out / 'error_vs_time.json'}, .csv and .png")
    return 0 if all(r.get("converged") for r in rows if r["scene"] != "ellipse_on_block_tessellated") else 1


if __name__ == "__main__":
    sys.exit(main())
