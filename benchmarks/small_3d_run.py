"""One small 3D contact rung of the NGSolve comparison (docs/peers.md, "3D: a ball on a block"):
``ibfem run --quiet --no-estimate`` on sphere_on_flat with both bodies' element size and refinement
levels set, as whole processes; per run the wall and CPU time (user + system, from ``os.wait4``),
the peak resident memory, a and N, and the stages the run's summary times (grid, assembly,
factorisation, iterations, results).

With ``--against DIR`` the runs alternate with the same command on the ibfem package found in
DIR (a folder holding an ``ibfem`` package, put first on ``PYTHONPATH``; e.g. an unpacked older
commit with ``geometry``, ``solver`` and ``importers`` linked into its ``ibfem`` folder), so that
two versions are compared on a shared machine by the ratio of alternated runs. DIR's modules are
compiled to bytecode first, as this tree's are (with ``PYTHONDONTWRITEBYTECODE`` set, a folder
never compiled would compile every module it imports in each run: some 0.3 s of CPU that is
not the solver's, which made an unchanged tree look 13 % faster than its own copy).

With ``--grid`` each process times the grid stage alone (both bodies' octrees, cut-cell moments
and face rules; a fresh scene each time) ``--grid-passes`` times in-process by its CPU time and
prints the fastest, with a digest of every body's moments, statuses, boundary areas and the
face rules of the faces its conditions name (the only rules a run keeps; every face's rule enters
the boundary areas) (equal digests: bitwise the same grids).

    python benchmarks/small_3d_run.py                         # h0 0.25 with 5 levels, 3 runs
    python benchmarks/small_3d_run.py --h0 0.2 --levels 5 --repeat 4 --against /tmp/before
    python benchmarks/small_3d_run.py --grid --repeat 3 --against /tmp/before
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import peers  # noqa: E402  (the rung's scene and the bytecode step of the comparison)

STAGES = ("grid_s", "assembly_s", "factor_s", "iterations_s", "results_s")

#: the grid stage in-process: the fastest CPU time of PASSES passes and the grids' digest
GRID_SCRIPT = """
import hashlib, sys, time
import numpy as np
from ibfem.solver.contact.driver import ContactDriver
from ibfem.solver.io.scene import load_scene
best = float("inf")
for _ in range(int(sys.argv[2])):
    driver = ContactDriver(load_scene(sys.argv[1]).problem)
    t = time.process_time()
    driver._discretise()
    best = min(best, time.process_time() - t)
digest = hashlib.sha256()
for body in driver.bodies:
    for array in (body.moments, body.status, body.boundary_area):
        digest.update(np.ascontiguousarray(array).tobytes())
    named = {getattr(bc, "edge", None) for bc in driver.problem.boundary_conditions if bc.body == body.name}
    for name in sorted(set(body.face_rules) & named):
        for array in body.face_rules[name]:
            digest.update(np.ascontiguousarray(array).tobytes())
print(best, digest.hexdigest()[:16])
"""


def run_once(scene: Path, out: Path, pythonpath: str | None) -> dict:
    env = dict(os.environ)
    if pythonpath:
        env["PYTHONPATH"] = pythonpath + os.pathsep + env.get("PYTHONPATH", "")
    cmd = [sys.executable, "-m", "ibfem", "run", str(scene), "--out", str(out), "--quiet", "--no-estimate"]
    with tempfile.TemporaryFile("w+") as log:
        t0 = time.perf_counter()
        proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=env, cwd=scene.parent)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - t0
        if os.waitstatus_to_exitcode(status) != 0:
            log.seek(0)
            raise SystemExit(f"{' '.join(cmd)} failed:\n{log.read()}")
    summary = json.loads((out / "summary.json").read_text())
    contact = summary["contacts"][0]
    return {"wall_s": wall, "cpu_s": usage.ru_utime + usage.ru_stime, "peak_mb": usage.ru_maxrss / 1024.0,
            "a": contact["semi_axes"][0], "N": contact["normal_force"],
            **{k: summary["timings"][k] for k in STAGES}}


def compile_folder(folder: Path) -> None:
    """Write the bytecode of the ``ibfem`` package in ``folder``, its linked subpackages included
    (compileall itself does not follow links to folders)."""
    import compileall
    import io
    from contextlib import redirect_stdout

    with redirect_stdout(io.StringIO()):
        for entry in sorted((folder / "ibfem").iterdir()):
            if entry.is_dir():
                compileall.compile_dir(entry.resolve(), quiet=2, workers=1)
            elif entry.suffix == ".py":
                compileall.compile_file(entry, quiet=2)


def grid_once(scene: Path, passes: int, pythonpath: str | None) -> dict:
    env = dict(os.environ)
    if pythonpath:
        env["PYTHONPATH"] = pythonpath + os.pathsep + env.get("PYTHONPATH", "")
    cmd = [sys.executable, "-c", GRID_SCRIPT, str(scene), str(passes)]
    done = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=scene.parent)
    if done.returncode != 0:
        raise SystemExit(f"the grid stage failed:\n{done.stderr}")
    cpu, digest = done.stdout.split()[-2:]
    return {"cpu_s": float(cpu), "digest": digest}


def grid_report(label: str, runs: list[dict]) -> None:
    cpu = ", ".join(f"{r['cpu_s'] * 1e3:.1f}" for r in runs)
    print(f"{label}: grid stage CPU {cpu} ms (mean {statistics.mean(r['cpu_s'] for r in runs) * 1e3:.1f}); "
          f"digest {runs[0]['digest']}")


def report(label: str, runs: list[dict]) -> None:
    mean = {k: statistics.mean(r[k] for r in runs) for k in runs[0]}
    cpu = ", ".join(f"{r['cpu_s']:.2f}" for r in runs)
    wall = ", ".join(f"{r['wall_s']:.2f}" for r in runs)
    stages = " ".join(f"{k[:-2]} {mean[k]:.3f}" for k in STAGES)
    print(f"{label}: CPU {cpu} s (mean {mean['cpu_s']:.3f}); wall {wall} s (mean {mean['wall_s']:.3f}); "
          f"peak {max(r['peak_mb'] for r in runs):.0f} MB; a {runs[0]['a']:.9g} N {runs[0]['N']:.9g}\n"
          f"  stages (mean, s): {stages}")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--h0", type=float, default=0.25, help="both bodies' element size (default 0.25)")
    ap.add_argument("--levels", type=int, default=5, help="refinement levels about the contact (default 5)")
    ap.add_argument("--repeat", type=int, default=3, help="runs of each version (default 3)")
    ap.add_argument("--against", help="a folder with another ibfem package, run alternately")
    ap.add_argument("--grid", action="store_true", help="time the grid stage alone, in-process")
    ap.add_argument("--grid-passes", type=int, default=5, help="grid stages per process with --grid (default 5)")
    args = ap.parse_args()
    peers.compile_bytecode()
    if args.against:
        compile_folder(Path(args.against))
    with tempfile.TemporaryDirectory() as tmp:
        scene = Path(tmp) / "rung.json"
        scene.write_text(json.dumps(peers.sphere_scene_data(args.h0, args.levels)))
        if args.grid:
            return compare_grids(scene, args)
        this, other = [], []
        for k in range(args.repeat):
            this.append(run_once(scene, Path(tmp) / f"this{k}", None))
            if args.against:
                other.append(run_once(scene, Path(tmp) / f"other{k}", args.against))
    print(f"h0 {args.h0}, {args.levels} levels, {args.repeat} runs each; load average {os.getloadavg()[0]:.1f}")
    report("this tree", this)
    if other:
        report(f"--against {args.against}", other)
        ratio = statistics.mean(r["cpu_s"] for r in this) / statistics.mean(r["cpu_s"] for r in other)
        print(f"CPU time ratio (this / other): {ratio:.3f}")
    return 0


def compare_grids(scene: Path, args) -> int:
    this, other = [], []
    for _ in range(args.repeat):
        this.append(grid_once(scene, args.grid_passes, None))
        if args.against:
            other.append(grid_once(scene, args.grid_passes, args.against))
    print(f"h0 {args.h0}, {args.levels} levels, the grid stage: the fastest of {args.grid_passes} passes per process, "
          f"{args.repeat} processes each; load average {os.getloadavg()[0]:.1f}")
    grid_report("this tree", this)
    if other:
        grid_report(f"--against {args.against}", other)
        ratio = statistics.mean(r["cpu_s"] for r in this) / statistics.mean(r["cpu_s"] for r in other)
        same = "the same" if this[0]["digest"] == other[0]["digest"] else "different"
        print(f"CPU time ratio (this / other): {ratio:.3f}; digests {same}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
