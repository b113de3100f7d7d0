"""Contact scenes of about a million dofs, each run in its own process.

3D (the default): the full ball on a block on a wider plate with a finer far field
(benchmarks/scenes/ball_on_plate_million.toml: a half ball R = 0.5 m on a plate 2.7 x 2.7 x 0.5 m,
steel, friction 0.2, five load steps; element size R / 20, two levels of refinement, finest cells
6.25 mm as in examples/solid/full/ball_on_block.toml), solved by ``solve`` as ``ibfem run`` does.
Prints dofs, contact dofs, wall and CPU time and peak resident memory of the child
(``/usr/bin/time``), the machine's load average before and after, the driver's stage times, the
``--check`` size estimate against the real peak, and the answer against theory: a, b against Hertz
for the computed normal force and c/a against Mindlin (as benchmarks/full_3d.py). Targets: at
least 0.95e6 dofs, converged, within 600 s wall and 8 GB.

2D (``--2d``): the peer problem of docs/peers.md (lower half disc R = 1 on a block, steel,
frictionless, benchmarks/scenes/peer_half_disc.toml) with the contact refinement at 6 levels over
radius 0.32 (h0 0.05: finest cell 0.78 mm, about 1.04 M dofs), run as ``ibfem run``; the half-width
and force against the converged NGSolve P3 reference of docs/peers.md (a 0.076644 m,
N 5.09190e8 N/m). Targets: under 60 s and 4 GB.

    python benchmarks/million_dofs.py [--scene SCENE.toml] [--threads 2] [--no-size-check]
    python benchmarks/million_dofs.py --2d [--levels 6] [--radius 0.32]

Writes benchmarks/results/million_dofs.json (3D) or million_dofs_2d.json (2D).

Measured (2026-11-28, ``--threads 2``, 2 cores shared with other jobs): 1,008,240 dofs, 9,180
contact dofs, 40 trials, converged, a = b = 0.045571 m (-0.67 % from Hertz), c/a 0.8562 (Mindlin
0.8562): 382.4 s wall, 326.9 s CPU, 7.01 GB at load 1-3; 393.4 s, 312.2 s, 6.98 GB at load 5-3;
745.9 s, 326.8 s, 7.06 GB at load 6-7. The ``--check`` estimate: 9.18e5 dofs, 3.96 GB."""

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
sys.path.insert(0, str(HERE))
import full_3d  # noqa: E402  (the 3D child and its timing: benchmarks/full_3d.py)

SCENE_3D = HERE / "scenes" / "ball_on_plate_million.toml"
SCENE_2D = HERE / "scenes" / "peer_half_disc.toml"
REFERENCE_2D = {"half_width": 0.076644, "normal_force": 5.09190e8}
TARGET_3D = {"dofs": 950_000, "wall_s": 600.0, "peak_gb": 8.0}

#: the scene check skipped (``--no-size-check``): its estimate is still recorded
NO_SIZE_CHECK = "from ibfem.solver.io import scene_solid\nscene_solid.size_problems = lambda problem, label: []\n"


def run_3d(scene: Path, threads: int | None, size_check: bool) -> dict:
    """The 3D scene solved in a child process: its row of benchmarks/full_3d.py plus the process's
    wall and CPU time, peak memory and the load average before and after."""
    env = {"IBFEM_THREADS": str(threads)} if threads is not None else {}
    child = full_3d.CHILD if size_check else NO_SIZE_CHECK + full_3d.CHILD
    load_before = os.getloadavg()
    timed = full_3d.timed_child(child, [str(scene), "-1"], env)
    if timed is None:
        raise SystemExit(f"{scene}: the run failed (its error above)")
    row, wall, cpu, peak_gb = timed
    row.update(process_wall_s=wall, process_cpu_s=cpu, peak_gb=peak_gb, environment=env,
               load_average=[load_before, os.getloadavg()])
    return row


def report_3d(r: dict) -> bool:
    """Print the 3D row; whether it meets the targets."""
    t = r["timings"]
    load = ", ".join("/".join(f"{v:.1f}" for v in trio) for trio in r["load_average"])
    print(f"{r['dofs']} dofs ({r['contact_dofs']} contact dofs): {r['process_wall_s']:.1f} s wall, "
          f"{r['process_cpu_s']:.1f} s CPU, peak {r['peak_gb']:.2f} GB, converged {r['converged']}, "
          f"{r['iterations']} trials; load average (1/5/15 min) before, after: {load}")
    print("  stages (wall s): " + ", ".join(f"{k[:-2]} {v:.1f}" for k, v in t.items() if k.endswith("_s")))
    print(f"  --check estimate: {r['estimated_dofs']:.3g} dofs, {r['estimated_memory_gb']:.2f} GB "
          f"(real: {r['dofs']} dofs, {r['peak_gb']:.2f} GB)")
    print(f"  N = {r['normal_force']:.6g} N: a = {r['a']:.6f} m ({100 * r['a_error']:+.2f} % from Hertz "
          f"{r['hertz_a']:.6f}), b = {r['b']:.6f} m ({100 * r['b_error']:+.2f} %)")
    if "stick_ratio" in r:
        print(f"  c/a = {r['stick_ratio']:.4f}, Mindlin {r['mindlin_stick_ratio']:.4f} "
              f"(Q = {r['tangential_force']:.6g} N)")
    ok = (r["converged"] and r["dofs"] >= TARGET_3D["dofs"] and r["process_wall_s"] <= TARGET_3D["wall_s"]
          and r["peak_gb"] <= TARGET_3D["peak_gb"])
    print("  target (>= 0.95e6 dofs, converged, <= 600 s wall, <= 8 GB):", "met" if ok else "NOT met")
    return ok


def scene_text_2d(levels: int, radius: float) -> str:
    text = SCENE_2D.read_text()
    old = 'refinement = [{ levels = 4, around = "contact", radius = 0.3 }]'
    if text.count(old) != 2:
        raise SystemExit(f"{SCENE_2D}: the two bodies' refinement lines changed; update {Path(__file__).name}")
    return text.replace(old, f'refinement = [{{ levels = {levels}, around = "contact", radius = {radius} }}]')


def run_2d(levels: int, radius: float) -> dict:
    with tempfile.TemporaryDirectory(prefix="ibfem-1m-") as tmp:
        scene = Path(tmp) / "million.toml"
        scene.write_text(scene_text_2d(levels, radius))
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
        "half_width_error": contact["half_width"] / REFERENCE_2D["half_width"] - 1.0,
        "normal_force_error": contact["normal_force"] / REFERENCE_2D["normal_force"] - 1.0,
    }


def report_2d(r: dict) -> bool:
    t = r["timings"]
    print(f"{r['dofs']} dofs: {r['wall_s']} s wall, peak {r['peak_mb']} MB, converged {r['converged']}")
    print(f"  phases: grid {t['grid_s']:.1f} s, assembly {t['assembly_s']:.1f} s, factor {t['factor_s']:.1f} s, "
          f"iterations {t['iterations_s']:.1f} s, results {t['results_s']:.1f} s")
    print(f"  a = {r['half_width']:.7f} m ({100 * r['half_width_error']:+.3f} % from the reference), "
          f"N = {r['normal_force']:.6e} N/m ({100 * r['normal_force_error']:+.3f} %)")
    ok = r["converged"] and r["dofs"] >= 1_000_000 and r["wall_s"] < 60.0 and r["peak_mb"] < 4096
    print("  target (>= 1M dofs, < 60 s, < 4 GB):", "met" if ok else "NOT met")
    return ok


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--2d", dest="two_d", action="store_true", help="the 2D peer scene instead of the 3D one")
    ap.add_argument("--scene", type=Path, default=SCENE_3D, help="3D: the scene (default: %(default)s)")
    ap.add_argument("--threads", type=int, default=None, help="3D: IBFEM_THREADS of the run")
    ap.add_argument("--no-size-check", action="store_true",
                    help="3D: solve a scene the size check refuses (its estimate is still reported)")
    ap.add_argument("--levels", type=int, default=6, help="2D: contact refinement levels")
    ap.add_argument("--radius", type=float, default=0.32, help="2D: contact refinement radius")
    args = ap.parse_args(argv)
    if args.two_d:
        r, name = run_2d(args.levels, args.radius), "million_dofs_2d.json"
        ok = report_2d(r)
    else:
        r, name = run_3d(args.scene, args.threads, not args.no_size_check), "million_dofs.json"
        ok = report_3d(r)
    out = HERE / "results" / name
    out.parent.mkdir(exist_ok=True)
    out.write_text(json.dumps(r, indent=1))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
