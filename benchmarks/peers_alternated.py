"""The peer study's deciding rungs as alternated whole processes, on CPU time: on a shared machine
the wall times of `make bench-peers` depend on what else runs, and NGSolve's two TaskManager
threads wait actively when another process holds a core, so its CPU time grows with the load too.
Here each round runs every rung once, in turn (ibfem's rungs, NGSolve's with 1 and 2 threads),
and the rounds are repeated: the minimum and median CPU time (user + system) of each rung over
the rounds, its peak memory, and its errors in a and N against the references of
benchmarks/peers.py.

    python benchmarks/peers_alternated.py [--problem steel|aluminium] [--rounds 5]

Rungs (the ones that decide the time to 0.3 % and 0.1 % in a and N, docs/peers.md): ibfem graded
from 0.12 m with 4, 5 and 6 levels on h0 0.2, ibfem's uniform far field h0 0.05 with 3 and 4
levels (the earlier ladder), NGSolve P2 at h_c 0.016, 0.008 (h_max 0.25) and 0.004 (0.2). Needs NGSolve.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import peers  # noqa: E402

IBFEM_RUNGS = [(0.2, 4, 0.12), (0.2, 5, 0.12), (0.2, 6, 0.12), (0.05, 3, None), (0.05, 4, None)]
NGSOLVE_RUNGS = [(0.016, 0.25), (0.008, 0.25), (0.004, 0.2)]
THREADS = (1, 2)


def rungs(problem: str, workdir: Path) -> list[tuple[str, object]]:
    """(label, a function running the rung once and returning its row)."""
    out = [(f"ibfem {r[0]}/{r[1]}" + (f" graded {r[2]}" if r[2] else " uniform"),
            lambda r=r: peers.run_ibfem(problem, r[0], r[1], workdir, r[2])) for r in IBFEM_RUNGS]
    out += [(f"NGSolve h_c {hc} {t} thread{'s' if t > 1 else ''}",
             lambda hc=hc, hm=hm, t=t: peers.run_ngsolve(problem, hc, hm, threads=t))
            for hc, hm in NGSOLVE_RUNGS for t in THREADS]
    return out


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--problem", choices=list(peers.PROBLEMS), default="steel")
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args(argv)
    peers.check_ngsolve()
    peers.compile_bytecode()
    load = os.getloadavg()
    with tempfile.TemporaryDirectory(prefix="ibfem_peers_alt_") as tmp:
        runs = rungs(args.problem, Path(tmp))
        rows = {label: [] for label, _ in runs}
        for _ in range(args.rounds):
            for label, run in runs:
                rows[label].append(peers.add_errors(run()))
    print(f"{args.problem}, {args.rounds} rounds, load average {load[0]:.1f} / {load[1]:.1f} / {load[2]:.1f} "
          f"before, {os.getloadavg()[0]:.1f} after")
    print("| rung | dofs | CPU min (s) | CPU median (s) | peak (MB) | error in a and N | NGSolve's fitted a: error in a and N |")
    print("|---|---|---|---|---|---|---|")
    for label, rs in rows.items():
        r, cpu = rs[0], [x["cpu_s"] for x in rs]
        if "aN_error" not in r:
            print(f"| {label} | failed: {r.get('error')} | | | | | |")
            continue
        fit = f"{100 * r['a_fitN_error']:.3f} %" if "a_fitN_error" in r else ""
        print(f"| {label} | {r['dofs']} | {min(cpu):.2f} | {statistics.median(cpu):.2f} | "
              f"{max(x['peak_mb'] for x in rs):.0f} | {100 * r['aN_error']:.3f} % | {fit} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
