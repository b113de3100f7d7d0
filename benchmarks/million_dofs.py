"""A 2D contact scene of more than 10^6 dofs: the peer problem of docs/peers.md (lower
half disc R = 1 on a block, steel, frictionless, benchmarks/scenes/peer_half_disc.toml) with the
contact refinement at 6 levels over radius 0.32 (h0 0.05: finest cell 0.78 mm, about 1.04 M dofs),
run as ``ibfem run`` in its own process. Reports dofs, wall time, peak memory (the child's maximum
resident set), the solver's phases, and the half-width and force against the converged NGSolve
P3 reference of docs/peers.md (a 0.076644 m, N 5.09190e8 N/m).

    python benchmarks/million_dofs.py [--levels 6] [--radius 0.32]

Targets: under 60 s and 4 GB. Writes benchmarks/results/million_dofs.json."""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SCENE = HERE / "scenes" / "peer_half_disc.toml"
REFERENCE = {"half_width": 0.076644, "normal_force": 5.09190e8}


def scene_text(levels: int, radius: float) -> str:
    text = SCENE.read_text()
    old = 'refinement = [{ levels = 4, around = "contact", radius = 0.3 }]'
    if text.count(old) != 2:
        raise SystemExit(f"{SCENE}: the two bodies' refinement lines changed; update {Path(__file__).name}")
    return text.replace(old, f'refinement = [{{ levels = {levels}, around = "contact", radius = {radius} }}]')


def run(levels: int, radius: float) -> dict:
    with tempfile.TemporaryDirectory(prefix="ibfem-1m-") as tmp:
        scene = Path(tmp) / "million.toml"
        scene.write_text(scene_text(levels, radius))
        t0 = time.perf_counter()
        done = subprocess.run([sys.executable, "-m", "ibfem.solver.cli", "run", str(scene), "--quiet"], cwd=tmp,
                              capture_output=True, text=True, env=dict(os.environ, MPLBACKEND="Agg"))
        wall = time.perf_counter() - t0
        peak_kb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
        if done.returncode != 0:
            raise SystemExit(f"ibfem run failed ({done.returncode}): {done.stderr.strip()[-2000:]}")
        summary = json.loads((Path(tmp) / "out" / scene.stem / "summary.json").read_text())
    contact = summary["contacts"][0]
    dofs = sum(b["dofs"] for b in summary["bodies"].values())
    return {
        "levels": levels, "radius": radius, "dofs": dofs, "wall_s": round(wall, 2),
        "peak_mb": round(peak_kb / 1024, 1),  # the largest child's: this is the only one
        "converged": summary["converged"], "timings": summary["timings"],
        "half_width": contact["half_width"], "normal_force": contact["normal_force"],
        "half_width_error": contact["half_width"] / REFERENCE["half_width"] - 1.0,
        "normal_force_error": contact["normal_force"] / REFERENCE["normal_force"] - 1.0,
    }


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--levels", type=int, default=6)
    ap.add_argument("--radius", type=float, default=0.32)
    args = ap.parse_args(argv)
    r = run(args.levels, args.radius)
    t = r["timings"]
    print(f"{r['dofs']} dofs: {r['wall_s']} s wall, peak {r['peak_mb']} MB, converged {r['converged']}")
    print(f"  phases: grid {t['grid_s']:.1f} s, assembly {t['assembly_s']:.1f} s, factor {t['factor_s']:.1f} s, "
          f"iterations {t['iterations_s']:.1f} s, results {t['results_s']:.1f} s")
    print(f"  a = {r['half_width']:.7f} m ({100 * r['half_width_error']:+.3f} % from the reference), "
          f"N = {r['normal_force']:.6e} N/m ({100 * r['normal_force_error']:+.3f} %)")
    ok = r["converged"] and r["dofs"] >= 1_000_000 and r["wall_s"] < 60.0 and r["peak_mb"] < 4096
    print("  target (>= 1M dofs, < 60 s, < 4 GB):", "met" if ok else "NOT met")
    out = HERE / "results" / "million_dofs.json"
    out.parent.mkdir(exist_ok=True)
    out.write_text(json.dumps(r, indent=1))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
