"""Every 3D example solved in two checkouts, alternated, to show what the code between them did
to the examples' answers and cost: per example the contacts' semi-axes a, b and normal force N
(a single body: its probes' von Mises stress and displacement), the dofs, the iterations, the
CPU time (user + system of the solving process) and its peak resident memory, with the ratios of
the second checkout's values to the first's.

Each checkout (``git worktree add ../base COMMIT``) is a directory with the project and its own ``.venv`` (an editable install of that
checkout). The scenes are the ``model = "solid"`` scene files present in both checkouts (or the
ones named), each solved from the second checkout's copy so both solve the same file (their
parsed contents are compared, comments aside, and a difference is recorded as ``same_file``). Runs alternate: for each example and round,
first then second on even rounds, second then first on odd rounds, one process at a time. The
machine's load average is recorded around every run: compare the CPU-time ratios, not the times.

    python benchmarks/examples_3d_unchanged.py --first ../base --second . --rounds 2 \\
        --json out/examples_3d_unchanged.json
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

#: a relative change of an answer beyond which the table marks the example as moved
MOVED = 5e-4
EXAMPLE_DIRS = ("examples/solid", "examples/cad", "examples/step", "examples/onshape", "examples/contact3d")


def solid_scenes(root: Path) -> set[str]:
    """The ``model = "solid"`` scene files under the example folders of one checkout (relative)."""
    found = set()
    for folder in EXAMPLE_DIRS:
        for path in sorted((root / folder).glob("*.toml")):
            with open(path, "rb") as f:
                if tomllib.load(f).get("model") == "solid":
                    found.add(str(path.relative_to(root)))
    return found


def _parsed(path: Path) -> dict:
    with open(path, "rb") as f:
        return tomllib.load(f)


def tree_rss_gb(pid: int) -> float:
    """Resident memory of a process and its descendants, GB (from /proc)."""
    total, todo = 0, [pid]
    while todo:
        p = todo.pop()
        try:
            with open(f"/proc/{p}/status") as f:
                total += next((int(line.split()[1]) for line in f if line.startswith("VmRSS:")), 0)
            with open(f"/proc/{p}/task/{p}/children") as f:
                todo += [int(c) for c in f.read().split()]
        except (FileNotFoundError, ProcessLookupError, StopIteration):
            continue
    return total / 1024**2


def solve_in(checkout: Path, scene: Path, out: Path, memory_limit_gb: float, flags: tuple[str, ...] = ()) -> dict:
    """Solve ``scene`` with the checkout's own interpreter; CPU seconds and peak memory of the run.

    The run is stopped once its processes hold more than ``memory_limit_gb`` (reported as such).
    """
    python = checkout / ".venv" / "bin" / "python"
    load_before = os.getloadavg()[0]
    t0 = time.perf_counter()
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "log.txt", "w") as log:
        proc = subprocess.Popen([str(python), "-m", "ibfem", "run", "--quiet", *flags, str(scene), "--out", str(out)],
                                cwd=checkout, stdout=log, stderr=subprocess.STDOUT, env=dict(os.environ, MPLBACKEND="Agg"),
                                start_new_session=True)
        over = 0.0
        while True:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid:
                break
            rss = tree_rss_gb(proc.pid)
            if rss > memory_limit_gb and not over:
                over = rss
                os.killpg(proc.pid, signal.SIGKILL)
            time.sleep(0.2)
        proc.returncode = os.waitstatus_to_exitcode(status)
    run = {"wall_s": time.perf_counter() - t0, "cpu_s": usage.ru_utime + usage.ru_stime,
           "peak_gb": usage.ru_maxrss / 1024**2, "load": [load_before, os.getloadavg()[0]]}
    summary = out / "summary.json"
    if over:
        run["error"] = [f"stopped at {over:.2f} GB, above the {memory_limit_gb} GB allowed"]
        return run
    if not summary.exists():
        run["error"] = (out / "log.txt").read_text(errors="replace").strip().splitlines()[-3:]
        return run
    run.update(read_answers(json.loads(summary.read_text())))
    return run


def read_answers(summary: dict) -> dict:
    """The compared answers of one summary.json: contacts' a, b, N; else the probes' stress."""
    answers = {"converged": summary.get("converged"),
               "dofs": sum(b.get("dofs", 0) for b in summary.get("bodies", {}).values())}
    iterations = summary.get("iterations", {})
    answers["iterations"] = iterations.get("total") if isinstance(iterations, dict) else None
    contacts = []
    for c in summary.get("contacts", []):
        a, b = (c.get("semi_axes") or [None, None])[:2]
        contacts.append({"a": a, "b": b, "N": c.get("normal_force"), "shape": c.get("region_shape", "ellipse")})
    answers["contacts"] = contacts
    answers["timings"] = {k: v for k, v in summary.get("timings", {}).items() if k.endswith("_s")}
    answers["probes"] = [{"von_mises": p.get("von_mises"), "uz": (p.get("displacement") or [None] * 3)[2]}
                         for p in summary.get("probes", [])]
    return answers


def ratio(new, old):
    if new is None or old in (None, 0):
        return None
    return new / old - 1.0


def compare(first: dict, second: dict) -> dict:
    """Relative differences second / first - 1 of every compared answer."""
    out = {}
    for i, (c1, c2) in enumerate(zip(first.get("contacts", []), second.get("contacts", []))):
        for key in ("a", "b", "N"):
            out[f"contact{i}.{key}"] = ratio(c2[key], c1[key])
    for i, (p1, p2) in enumerate(zip(first.get("probes", []), second.get("probes", []))):
        for key in ("von_mises", "uz"):
            out[f"probe{i}.{key}"] = ratio(p2[key], p1[key])
    return out


def table(results: list[dict]) -> str:
    """Markdown: one row per example with both checkouts' answers, differences and CPU ratios."""
    rows = ["| example | a, b, N (first) | a, b, N: second against first | dofs | CPU s first / second (ratio) | "
            "solve's wall s first / second, without the accuracy estimate; the estimate's s | peak GB | load |",
            "|---|---|---|---|---|---|---|---|"]
    for r in results:
        runs1, runs2 = r["first"], r["second"]
        ok1 = [x for x in runs1 if "error" not in x]
        ok2 = [x for x in runs2 if "error" not in x]
        if not ok1 or not ok2:
            err = (runs1 + runs2)[0].get("error") if (runs1 + runs2) else None
            rows.append(f"| {r['scene']} | {'failed: ' + ' '.join(err or []) if not ok1 else ''} | "
                        f"{'failed: ' + ' '.join(runs2[0].get('error', [])) if not ok2 else ''} | | | | |")
            continue
        base, head = ok1[0], ok2[0]
        if base["contacts"]:
            vals = "; ".join(f"{c['a']:.6g}, {c['b']:.6g} m, {c['N']:.6g} N" for c in base["contacts"])
        else:
            vals = "; ".join(f"probe von Mises {p['von_mises']:.6g} Pa" for p in base["probes"])
        moved = compare(base, head)
        diffs = ", ".join(f"{k} {100 * v:+.4f} %" for k, v in moved.items() if v is not None)
        if any(v is not None and abs(v) > MOVED for v in moved.values()):
            diffs += f" (**moved by more than {100 * MOVED:g} %**)"
        cpu = " / ".join(f"{x['cpu_s']:.1f}; {y['cpu_s']:.1f} ({y['cpu_s'] / x['cpu_s']:.2f})" for x, y in zip(ok1, ok2))
        solve = " / ".join(f"{x['timings'].get('solver_total_s', 0):.1f}; {y['timings'].get('solver_total_s', 0):.1f}"
                           for x, y in zip(ok1, ok2))
        estimate = ", ".join(f"{y['timings'].get('estimate_s', 0):.1f}" for y in ok2)
        peak = f"{max(x['peak_gb'] for x in ok1):.2f} / {max(x['peak_gb'] for x in ok2):.2f}"
        load = f"{min(min(x['load']) for x in ok1 + ok2):.1f}-{max(max(x['load']) for x in ok1 + ok2):.1f}"
        rows.append(f"| {r['scene']} | {vals} | {diffs} | {base['dofs']} / {head['dofs']} | {cpu} | {solve}; {estimate} | {peak} | {load} |")
    return "\n".join(rows)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--first", required=True, type=Path, help="the earlier checkout (with its .venv)")
    parser.add_argument("--second", default=Path("."), type=Path, help="the later checkout (default: here)")
    parser.add_argument("--rounds", type=int, default=2, help="alternated pairs per example")
    parser.add_argument("--scenes", nargs="*", help="scene files (relative to a checkout); default: the solid ones in both")
    parser.add_argument("--memory-limit", type=float, default=2.4, help="GB a run may hold before it is stopped")
    parser.add_argument("--second-flags", nargs="*", default=[], help="options of the second checkout's ibfem run "
                        "(e.g. --no-estimate; pass as --second-flags=--no-estimate)")
    parser.add_argument("--exclude", nargs="*", default=[], help="scene files to leave out")
    parser.add_argument("--json", type=Path, help="write every run's numbers here")
    args = parser.parse_args(argv)
    first, second = args.first.resolve(), args.second.resolve()
    scenes = [s for s in args.scenes or sorted(solid_scenes(first) & solid_scenes(second)) if s not in args.exclude]
    results = []
    with tempfile.TemporaryDirectory(prefix="examples3d_") as tmp:
        for scene in scenes:
            same = (first / scene).exists() and _parsed(first / scene) == _parsed(second / scene)
            record = {"scene": scene, "same_file": same, "first": [], "second": []}
            for k in range(args.rounds):
                order = [("first", first), ("second", second)]
                for label, checkout in order if k % 2 == 0 else order[::-1]:
                    flags = tuple(args.second_flags) if label == "second" else ()
                    run = solve_in(checkout, second / scene, Path(tmp) / f"{label}{k}_{Path(scene).stem}", args.memory_limit, flags)
                    record[label].append(run)
                    print(f"{scene} {label} round {k}: CPU {run['cpu_s']:.1f} s, {run['peak_gb']:.2f} GB, "
                          f"load {run['load'][0]:.1f}-{run['load'][1]:.1f}, {run.get('contacts') or run.get('error')}",
                          flush=True)
            results.append(record)
            if args.json:
                args.json.parent.mkdir(parents=True, exist_ok=True)
                args.json.write_text(json.dumps(results, indent=1))
    print(table(results))


if __name__ == "__main__":
    sys.exit(main())
