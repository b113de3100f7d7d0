"""The size ``ibfem run --check`` estimates for a scene against what the run then uses:

    python benchmarks/check_table.py examples/solid/sphere_on_flat.toml [more scenes] [--max-memory GB]

For each scene the estimate (solver.io.run_size.run_size, the numbers ``--check``
prints) is made in a process of its own (this one imports nothing of ibfem: a run's process,
forked from it, would count its pages in the run's peak memory); the run is ``ibfem run SCENE --quiet`` in a child process, its dofs read
from summary.json (the bodies' ``dofs``), its peak memory the child's largest resident set
(``wait4``; Linux), its time the wall time of the child (start, imports and writing included)
and the solver's own (``solver_total_s``). A scene estimated above ``--max-memory`` is listed
and not run; one the scene check refuses (larger than the machine) is listed with its reason. Prints a Markdown table with the ratios used / estimated.

``--runs FILE`` appends each run's measurements (dofs, peak memory, times, load average) to
FILE, one JSON line per run, and takes a scene's run from FILE instead of running it again when
FILE has one: the estimate is always made anew, so a changed estimate is tabulated against the
runs already measured (a run does not depend on the estimate)."""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

_HEADER = ("| example | dofs: estimated | used | used / est. | peak memory: estimated (GB) | used (GB) | used / est. "
           "| run (s) | solver (s) |\n|---|---|---|---|---|---|---|---|---|")


#: the estimate, made in a process of its own: this one stays small, so that a run's peak memory,
#: which counts what the run's process holds from its start (a forked process holds its parent's
#: pages), is the run's own
_ESTIMATE = ("import json, sys\n"
             "from ibfem.solver.io.scene import SceneError, load_scene\n"
             "from ibfem.solver.io.run_size import run_size\n"
             "try:\n    size, _ = run_size(load_scene(sys.argv[1]).problem)\n"
             "except SceneError as err:\n    print(json.dumps({'refused': str(err).split(': ', 1)[-1]}))\n"
             "else:\n    print(json.dumps({'dofs': size.dofs, 'memory': size.memory}))")


class _Size:
    def __init__(self, dofs: float, memory: float):
        self.dofs, self.memory = dofs, memory


def _estimate(scene_path: str):
    """The estimate (dofs, memory) of ``--check``, or the reason the scene check refuses the scene."""
    done = subprocess.run([sys.executable, "-c", _ESTIMATE, scene_path], capture_output=True, text=True, check=True)
    found = json.loads(done.stdout.strip().splitlines()[-1])
    return found["refused"] if "refused" in found else _Size(found["dofs"], found["memory"])


def _run(scene_path: str, out: Path) -> tuple[dict, float, float]:
    """(summary, peak resident memory in bytes, wall seconds) of ``ibfem run``."""
    t0 = time.perf_counter()
    child = subprocess.Popen([sys.executable, "-m", "ibfem", "run", scene_path, "--out", str(out), "--quiet"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - t0
    child.returncode = os.waitstatus_to_exitcode(status)
    errors = child.stderr.read().decode(errors="replace") if child.stderr else ""
    if child.returncode not in (0, 1):  # 1: written, not converged
        raise RuntimeError(f"{scene_path}: ibfem run exited with {child.returncode}: {errors.strip()[-400:]}")
    summary = json.loads((out / "summary.json").read_text())
    return summary, usage.ru_maxrss * 1024.0, wall


def _measured(scene_path: str, out: Path, runs: Path | None) -> dict:
    """The run's measurements: from ``runs`` when it holds the scene, else run (and appended)."""
    if runs is not None and runs.is_file():
        for line in runs.read_text().splitlines():
            kept = json.loads(line)
            if kept["scene"] == scene_path:
                return kept
    load = os.getloadavg()[0]
    summary, peak, wall = _run(scene_path, out)
    kept = {"scene": scene_path, "dofs": sum(float(b.get("dofs") or 0) for b in summary["bodies"].values()),
            "peak_bytes": peak, "wall_s": wall, "solver_s": summary["timings"].get("solver_total_s", float("nan")),
            "load_average": [load, os.getloadavg()[0]], "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}
    if runs is not None:
        with runs.open("a") as f:
            f.write(json.dumps(kept) + "\n")
    return kept


def row(scene_path: str, out: Path, max_memory: float, runs: Path | None = None) -> str:
    name = str(Path(scene_path).with_suffix("")).removeprefix("examples/")  # subfolders tell scenes apart
    est = _estimate(scene_path)
    if isinstance(est, str):  # the scene check refuses a grid larger than the machine
        return f"| {name} | refused by the check: {est} | | | | | | | |"
    if est.memory > max_memory:
        return (f"| {name} | {est.dofs:.3g} | not run | | {est.memory / 2**30:.2f} | not run (estimate above "
                f"{max_memory / 2**30:.3g} GB) | | | |")
    m = _measured(scene_path, out, runs)
    dofs, peak, wall, solver_s = m["dofs"], m["peak_bytes"], m["wall_s"], m["solver_s"]
    return (f"| {name} | {est.dofs:.3g} | {dofs:.3g} | {dofs / est.dofs:.2f} | {est.memory / 2**30:.2f} | "
            f"{peak / 2**30:.2f} | {peak / est.memory:.2f} | {wall:.1f} | {solver_s:.1f} |")


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scenes", nargs="+")
    ap.add_argument("--max-memory", type=float, default=2.0, metavar="GB",
                    help="scenes estimated above this are not run (default 2)")
    ap.add_argument("--runs", type=Path, default=None, metavar="FILE",
                    help="runs measured before (JSON lines): reused, and new runs appended")
    args = ap.parse_args(argv)
    root = Path(tempfile.mkdtemp(prefix="ibfem-check-"))
    print(_HEADER, flush=True)
    for path in args.scenes:
        print(row(path, root / Path(path).stem, args.max_memory * 2**30, args.runs), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
