"""The peer study of issue 12 (``make bench-peers``): ibfem beside NGSolve P2 on the same contact
problem, time to error.

Problem (benchmarks/scenes/peer_half_disc.toml): lower half disc R = 1 centred (0, 1) on the block
[-2, 2] x [-2, 0], plane strain, the block's bottom fixed, the disc's flat top moved by
(0, -0.0107), frictionless. ``steel``: both E 2e11, nu 0.3; ``aluminium``: the disc E 7e10,
nu 0.33 on the steel block. Errors in the half-width a and the normal force N against the
converged references below (docs/peers.md says how they were obtained).

Each run is its own process (``ibfem run`` on a scene generated from the base scene with the
rung's element size and refinement levels, VTU and plots off; ``benchmarks/peers_ngsolve.py``
for NGSolve), the two ladders interleaved (ibfem, NGSolve, ibfem, ...), each rung ``--repeat``
times (the fastest kept). Wall time is the child process's whole life (imports, meshing, solve,
output); CPU time and peak memory (maximum resident set) come from ``os.wait4``. NGSolve's a is
reported twice: where its gap closes (the definition) and from a fit of the gap opening
(docs/peers.md). The time to reach 1 %, 0.3 % and 0.1 % error in a is interpolated on each
ladder (log-log between the last rung above and the first rung at or below the error, on the
running best error), the ratio NGSolve/ibfem printed beside it, on wall and on CPU time.

    python benchmarks/peers.py [--quick] [--problem steel|aluminium|all] [--repeat N]
    python benchmarks/peers.py --report benchmarks/results/peers.json   # the tables again, no runs

Writes benchmarks/results/peers.json and peers.md. Needs the ``peers`` extra (ngsolve).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
BASE_SCENE = HERE / "scenes" / "peer_half_disc.toml"
RESULTS = HERE / "results"
TARGETS = (0.01, 0.003, 0.001)

STEEL = (2.0e11, 0.3)
ALUMINIUM = (7.0e10, 0.33)
# Converged references (docs/peers.md): NGSolve P3, curved, gap along the frame normal between
# points at the same x, a from the fitted gap opening, meshes h_c 0.004 .. 0.00025 agreeing to
# 6e-5 (a) and 1.5e-5 (N). The issue's own steel reference is kept beside it ("issue").
PROBLEMS = {
    "steel": {"disc": STEEL, "block": STEEL, "a": 0.076644, "N": 5.09190e8,
              "issue": {"a": 0.076667, "N": 5.09216e8}},
    "aluminium": {"disc": ALUMINIUM, "block": STEEL, "a": 0.078940, "N": 2.84707e8},
}
# (element_size, refinement levels) of both bodies
IBFEM_LADDER = [(0.1, 2), (0.1, 3), (0.05, 3), (0.05, 4), (0.05, 5)]
# NGSolve: (element size along the contact h_c, largest element size)
NGSOLVE_LADDER = [(0.016, 0.25), (0.008, 0.25), (0.004, 0.2), (0.002, 0.1), (0.001, 0.1), (0.0005, 0.05), (0.00025, 0.05)]
QUICK_IBFEM = [(0.1, 3), (0.05, 3)]
QUICK_NGSOLVE = [(0.004, 0.2), (0.002, 0.1)]


def scene_data(problem: str, element_size: float, levels: int) -> dict:
    """The base scene with this problem's materials and this rung's grids, VTU and plots off."""
    data = tomllib.loads(BASE_SCENE.read_text())
    spec = PROBLEMS[problem]
    data["materials"] = [
        {"name": "disc_material", "youngs_modulus": spec["disc"][0], "poissons_ratio": spec["disc"][1]},
        {"name": "block_material", "youngs_modulus": spec["block"][0], "poissons_ratio": spec["block"][1]},
    ]
    for body in data["bodies"]:
        body["material"] = f"{body['name']}_material"
        body["element_size"] = element_size
        for ref in body.get("refinement") or []:
            ref["levels"] = levels
    data["name"] = f"peer {problem} h0 {element_size} levels {levels}"
    data.setdefault("output", {}).update(vtk=False, plots=False)
    return data


def run_child(cmd: list[str]) -> tuple[int, str, str, float, float, float]:
    """Runs one process: return code, stdout, stderr, wall time (s), peak resident memory (MB),
    CPU time (user + system, s)."""
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        t0 = time.perf_counter()
        proc = subprocess.Popen(cmd, stdout=out, stderr=err, cwd=ROOT)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - t0
        proc.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        return (proc.returncode, out.read(), err.read(), wall, usage.ru_maxrss / 1024.0,
                usage.ru_utime + usage.ru_stime)


def run_ibfem(problem: str, element_size: float, levels: int, workdir: Path) -> dict:
    tag = f"ibfem_{problem}_{element_size}_{levels}"
    scene = workdir / f"{tag}.json"
    scene.write_text(json.dumps(scene_data(problem, element_size, levels)))
    out = workdir / tag
    ibfem = Path(sys.executable).with_name("ibfem")
    cmd = [str(ibfem), "run", str(scene), "--out", str(out), "--quiet"]
    code, _, err, wall, peak, cpu = run_child(cmd)
    row = {"code": "ibfem", "problem": problem, "rung": f"h0 {element_size}, {levels} levels",
           "element_size": element_size, "levels": levels, "wall_s": wall, "cpu_s": cpu,
           "peak_mb": peak, "exit": code}
    if code not in (0, 1):
        row["error"] = err.strip().splitlines()[-1:] if err.strip() else [f"exit {code}"]
        return row
    summary = json.loads((out / "summary.json").read_text())
    contact = summary["contacts"][0]
    row.update(converged=bool(summary["converged"]), a=contact["half_width"], N=contact["normal_force"],
               dofs=sum(b["dofs"] for b in summary["bodies"].values()),
               iterations=summary["iterations"]["total"], solver_s=summary["timings"].get("solver_total_s"))
    return row


def run_ngsolve(problem: str, hc: float, hmax: float, order: int = 2, threads: int = 2) -> dict:
    spec = PROBLEMS[problem]
    cmd = [sys.executable, str(HERE / "peers_ngsolve.py"), "--hc", str(hc), "--hmax", str(hmax), "--threads", str(threads),
           "--order", str(order), "--disc-E", str(spec["disc"][0]), "--disc-nu", str(spec["disc"][1]),
           "--block-E", str(spec["block"][0]), "--block-nu", str(spec["block"][1])]
    code, out, err, wall, peak, cpu = run_child(cmd)
    row = {"code": f"NGSolve P{order}", "problem": problem, "rung": f"h_c {hc}, h_max {hmax}", "hc": hc,
           "hmax": hmax, "wall_s": wall, "cpu_s": cpu, "peak_mb": peak, "exit": code}
    if code != 0:
        row["error"] = err.strip().splitlines()[-1:] if err.strip() else [f"exit {code}"]
        return row
    res = json.loads(out.strip().splitlines()[-1])
    row.update(converged=True, a=res["a_closing"], a_fit=res["a"], N=res["N"], dofs=res["dofs"],
               iterations=res["newton_iterations"], solver_s=res["total_in_process_s"])
    return row


def best_of(run, repeat: int) -> dict:
    """The run repeated: the fastest of ``repeat`` (the results are deterministic; the machine is shared)."""
    rows = [run() for _ in range(repeat)]
    best = min(rows, key=lambda r: r["wall_s"])
    best["wall_all_s"] = [r["wall_s"] for r in rows]
    best["cpu_all_s"] = [r["cpu_s"] for r in rows]
    best["peak_mb"] = max(r["peak_mb"] for r in rows)
    return best


def add_errors(row: dict) -> dict:
    spec = PROBLEMS[row["problem"]]
    for key in ("a", "a_fit", "N"):
        if key in row:
            row[f"{key}_error"] = row[key] / spec[key[0]] - 1.0
            if "issue" in spec:
                row[f"{key}_error_issue"] = row[key] / spec["issue"][key[0]] - 1.0
    return row


def time_to_error(rows: list[dict], target: float, key: str = "a_error", clock: str = "wall_s") -> dict | None:
    """Time (``clock``: wall_s or cpu_s) and peak memory to reach |error| <= target on one ladder
    (None: never)."""
    pts = sorted((r[clock], abs(r[key]), r["peak_mb"]) for r in rows
                 if isinstance(r.get(key), float) and math.isfinite(r[key]))
    best, prev = math.inf, None
    for wall, err, peak in pts:
        if err < best:
            if err <= target:
                if prev is None or prev[1] <= 0 or err <= 0:
                    return {"time_s": wall, "peak_mb": peak, "bound": prev is None}
                f = (math.log(target) - math.log(prev[1])) / (math.log(err) - math.log(prev[1]))
                t = math.exp(math.log(prev[0]) + f * (math.log(wall) - math.log(prev[0])))
                return {"time_s": t, "peak_mb": peak, "bound": False}
            best, prev = err, (wall, err)
    return None


def comparison(rows: list[dict], problem: str, ng_key: str = "a_error") -> list[dict]:
    """Time to each target error in a, ibfem's a against NGSolve's ``ng_key`` estimate."""
    out = []
    ib = [r for r in rows if r["problem"] == problem and r["code"] == "ibfem"]
    ng = [r for r in rows if r["problem"] == problem and r["code"].startswith("NGSolve")]
    for target in TARGETS:
        ti, tn = time_to_error(ib, target), time_to_error(ng, target, ng_key)
        ci, cn = time_to_error(ib, target, clock="cpu_s"), time_to_error(ng, target, ng_key, clock="cpu_s")
        out.append({"problem": problem, "ngsolve_a": "gap closing" if ng_key == "a_error" else "gap opening fit",
                    "target": target, "ibfem": ti, "ngsolve": tn,
                    "ratio": tn["time_s"] / ti["time_s"] if ti and tn else None,
                    "ibfem_cpu": ci, "ngsolve_cpu": cn,
                    "ratio_cpu": cn["time_s"] / ci["time_s"] if ci and cn else None})
    return out


def fmt_row(r: dict) -> str:
    if "a" not in r:
        return (f"| {r['problem']} | {r['code']} | {r['rung']} | | | {r['wall_s']:.2f} | {r['cpu_s']:.2f} "
                f"| {r['peak_mb']:.0f} | failed: {r.get('error')} | | |")
    fit = f"{r['a_fit']:.6f} ({100 * r['a_fit_error']:+.3f} %)" if "a_fit" in r else ""
    return (f"| {r['problem']} | {r['code']} | {r['rung']} | {r['dofs']} | {r['iterations']} | {r['wall_s']:.2f} "
            f"| {r['cpu_s']:.2f} | {r['peak_mb']:.0f} | {r['a']:.6f} ({100 * r['a_error']:+.3f} %) | {fit} "
            f"| {r['N']:.5e} ({100 * r['N_error']:+.3f} %) |")


def fmt_cmp(c: dict) -> str:
    def cell(t):
        if t is None:
            return "not reached"
        return f"{'<= ' if t['bound'] else ''}{t['time_s']:.2f} s, {t['peak_mb']:.0f} MB"
    def ratio(x):
        return f"{x:.2f}" if x else "-"
    return (f"| {c['problem']} | {c['ngsolve_a']} | {100 * c['target']:g} % | {cell(c['ibfem'])} "
            f"| {cell(c['ngsolve'])} | {ratio(c['ratio'])} | {ratio(c['ratio_cpu'])} |")


def write_results(rows: list[dict], cmps: list[dict], quick: bool) -> str:
    lines = ["| problem | code | rung | dofs | iterations | wall (s) | CPU (s) | peak (MB) | a (error) "
             "| a, NGSolve's gap-opening fit (error) | N (error) |",
             "|---|---|---|---|---|---|---|---|---|---|---|", *map(fmt_row, rows), "",
             "| problem | NGSolve's a | error in a | ibfem (wall, memory) | NGSolve P2 (wall, memory) "
             "| NGSolve / ibfem, wall | same, CPU time |", "|---|---|---|---|---|---|---|", *map(fmt_cmp, cmps)]
    text = "\n".join(lines)
    RESULTS.mkdir(exist_ok=True)
    suffix = "_quick" if quick else ""
    (RESULTS / f"peers{suffix}.json").write_text(json.dumps(
        {"references": PROBLEMS, "rows": rows, "comparison": cmps, "quick": quick}, indent=2))
    (RESULTS / f"peers{suffix}.md").write_text(
        f"# Peer study (benchmarks/peers.py{' --quick' if quick else ''})\n\n{text}\n")
    return text


def check_ngsolve() -> None:
    r = subprocess.run([sys.executable, "-c", "import ngsolve"], capture_output=True)
    if r.returncode != 0:
        raise SystemExit("benchmarks/peers.py needs NGSolve: pip install -e '.[peers]' (the `peers` extra)")


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="two rungs per code (a smoke check)")
    ap.add_argument("--problem", choices=["steel", "aluminium", "all"], default="all")
    ap.add_argument("--repeat", type=int, default=2, help="runs per rung, the fastest kept (default 2: the machine may be shared)")
    ap.add_argument("--ngsolve-threads", type=int, default=2, help="NGSolve's TaskManager threads (default 2)")
    ap.add_argument("--report", type=Path, help="no runs: the tables again from the rows of this peers.json")
    args = ap.parse_args(argv)
    problems = ["steel", "aluminium"] if args.problem == "all" else [args.problem]
    if args.report:
        rows = [add_errors(r) for r in json.loads(args.report.read_text())["rows"] if r["problem"] in problems]
        cmps = [c for p in problems for key in ("a_error", "a_fit_error") for c in comparison(rows, p, key)]
        print(write_results(rows, cmps, args.quick))
        return 0
    check_ngsolve()
    load = os.getloadavg()[0]
    if load > 0.5:
        print(f"warning: load average {load:.1f} before the runs: wall times include other processes' "
              "(compare cpu_s in the JSON, or rerun on a quiet machine)", file=sys.stderr)
    ib_ladder = QUICK_IBFEM if args.quick else IBFEM_LADDER
    ng_ladder = QUICK_NGSOLVE if args.quick else NGSOLVE_LADDER
    rows = []
    with tempfile.TemporaryDirectory(prefix="ibfem_peers_") as tmp:
        for problem in problems:
            for i in range(max(len(ib_ladder), len(ng_ladder))):
                runs = []
                if i < len(ib_ladder):
                    runs.append(lambda p=problem, r=ib_ladder[i]: run_ibfem(p, *r, Path(tmp)))
                if i < len(ng_ladder):
                    runs.append(lambda p=problem, r=ng_ladder[i]: run_ngsolve(p, *r, threads=args.ngsolve_threads))
                for run in runs:
                    rows.append(add_errors(best_of(run, args.repeat)))
                    print(fmt_row(rows[-1]), flush=True)
    ok = all("a" in r for r in rows)
    previous = RESULTS / f"peers{'_quick' if args.quick else ''}.json"
    if args.problem != "all" and previous.exists():   # keep the other problem's rows
        rows += [r for r in json.loads(previous.read_text())["rows"] if r["problem"] not in problems]
        problems = [p for p in PROBLEMS if any(r["problem"] == p for r in rows)]
        rows.sort(key=lambda r: problems.index(r["problem"]))
    cmps = [c for p in problems for key in ("a_error", "a_fit_error") for c in comparison(rows, p, key)]
    print()
    print(write_results(rows, cmps, args.quick))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
