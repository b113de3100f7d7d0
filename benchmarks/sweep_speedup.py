"""Sweep speed-up: a 12-case sweep of a 2-3 s scene on the embedded Dask cluster with
2 workers against ``--serial``, each timed as the whole ``ibfem sweep`` command (start-up,
cluster, imports, every case, table and plots), runs alternating, medians compared.

The scene: example 4 (cylinder on flat, partial slip) with the inner refinement at 6 levels over
radius 0.07 (2.2 s a case after the first, about 2.6 s as a whole ``ibfem run``; 2026-11-26: the
5 levels of earlier measurements became a 1.2 s case with the sparse contact terms), friction
from 0.15 to 0.6 in 12 steps. Both engines must give the same
table (the outputs of every case equal to the last digit).

    python benchmarks/sweep_speedup.py [--repeat 3] [--workers 2]

Writes benchmarks/results/sweep_speedup.json. Target: speed-up >= 1.7 on 2 cores."""

from __future__ import annotations

import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

SWEEP = """[sweep]
name = "benchmark: example 4 friction, 12 cases"
scene = "{scene}"
mode = "grid"

[sweep.set]
"bodies.*.refinement.-1.levels" = 6
"bodies.*.refinement.-1.radius" = 0.07
"output.vtk" = false
"output.plots" = false

[sweep.parameters]
"contacts.0.friction" = {{ start = 0.15, stop = 0.6, num = 12 }}

[sweep.outputs]
columns = ["converged", "contacts.0.normal_force", "contacts.0.tangential_force", "contacts.0.half_width",
           "contacts.0.stick_half_width"]
"""


def run_once(sweep: Path, out: Path, serial: bool, workers: int) -> tuple[float, list[dict]]:
    cmd = [sys.executable, "-m", "ibfem.solver.cli", "sweep", str(sweep), "--out", str(out), "--quiet"]
    cmd += ["--serial"] if serial else ["--workers", str(workers)]
    t0 = time.perf_counter()
    done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, env=dict(os.environ, MPLBACKEND="Agg"))
    seconds = time.perf_counter() - t0
    if done.returncode != 0:
        raise SystemExit(f"sweep failed ({'serial' if serial else 'dask'}): {done.stderr.strip()}")
    with open(out / "results.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    return seconds, rows


def _outputs(rows: list[dict]) -> list[tuple]:
    keys = [k for k in rows[0] if k.startswith("contacts.") or k in ("case", "status")]
    return [tuple(r[k] for k in keys) for r in rows]


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=3, help="runs of each engine (alternating)")
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args(argv)
    times: dict[str, list[float]] = {"serial": [], "dask": []}
    tables = {}
    with tempfile.TemporaryDirectory(prefix="ibfem-sweep-bench-") as tmp:
        sweep = Path(tmp) / "bench.toml"
        sweep.write_text(SWEEP.format(scene=(ROOT / "examples" / "cylinder_on_flat_partial_slip.toml").as_posix()))
        for k in range(args.repeat):
            for engine in ("serial", "dask") if k % 2 == 0 else ("dask", "serial"):
                seconds, rows = run_once(sweep, Path(tmp) / f"{engine}{k}", engine == "serial", args.workers)
                times[engine].append(seconds)
                tables.setdefault(engine, _outputs(rows))
                print(f"run {k + 1}/{args.repeat} {engine:6s}: {seconds:6.1f} s "
                      f"({sum(r['status'] == 'ok' for r in rows)}/12 ok)", flush=True)
    same = tables["serial"] == tables["dask"]
    med = {e: statistics.median(t) for e, t in times.items()}
    speedup = med["serial"] / med["dask"]
    result = {"cases": 12, "workers": args.workers, "repeat": args.repeat, "cores": os.cpu_count(),
              "seconds": times, "median_s": med, "speedup": speedup, "identical_tables": same,
              "load_average_after": os.getloadavg(), "when": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}
    (HERE / "results").mkdir(exist_ok=True)
    (HERE / "results" / "sweep_speedup.json").write_text(json.dumps(result, indent=1) + "\n")
    print(f"median serial {med['serial']:.1f} s, embedded {args.workers} workers {med['dask']:.1f} s: "
          f"speed-up {speedup:.2f} (target 1.7); tables identical: {same}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
