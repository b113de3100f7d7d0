"""``ibfem sweep SWEEP.toml``: many variants of one scene on Dask.

Exit codes: 0 every case ok; 1 some case not ok (not converged, error, timeout, invalid,
killed: see results.csv); 2 the sweep file is invalid; 3 the engine cannot run (Dask not
installed, no scheduler, workers with another ibfem); 4 the results cannot be written."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def register(sub: "argparse._SubParsersAction") -> None:
    p = sub.add_parser(
        "sweep", help="run a parameter sweep of a scene",
        description="Run every case of a sweep file ([sweep] name, scene, mode; [sweep.parameters]; [sweep.outputs]) on an embedded Dask "
        "cluster, an existing one (--scheduler-address, --scheduler-file, DASK_SCHEDULER_ADDRESS) or in this "
        "process (--serial). Results: OUT/results.jsonl, OUT/results.csv, OUT/cases/<hash>/, OUT/plots/.")
    p.add_argument("sweep_file", help="sweep description (TOML)")
    p.add_argument("--out", default=None, help="output directory (default: out/<sweep file name>)")
    p.add_argument("--serial", action="store_true", help="run the cases in this process, one after the other "
                   "(no Dask needed)")
    p.add_argument("--dry-run", action="store_true", help="list the cases (and which are invalid), run nothing")
    p.add_argument("--workers", type=int, default=None, help="embedded cluster: worker processes (default: cores)")
    p.add_argument("--memory-limit", default=None, help="embedded cluster: memory per worker, e.g. 4GB "
                   "(default: Dask's share of the machine)")
    p.add_argument("--scheduler-address", default=None, help="an existing Dask scheduler, tcp://HOST:PORT "
                   "(default: $DASK_SCHEDULER_ADDRESS, else an embedded cluster)")
    p.add_argument("--scheduler-file", default=None, help="an existing Dask scheduler's scheduler file")
    p.add_argument("--case-timeout", type=float, default=None, metavar="SECONDS",
                   help="stop a case that runs longer (status timeout); each case then runs in a child process")
    p.add_argument("--retry-failed", action="store_true", help="also rerun the cases recorded as error, "
                   "timeout or killed (finished cases are always skipped)")
    p.add_argument("--shared-files", action="store_true", help="an existing cluster's workers read the "
                   "scene's files (onshape / step paths) from the same paths: do not send them")
    p.add_argument("--no-plots", action="store_true", help="write no plots")
    p.add_argument("--quiet", action="store_true", help="no progress display")
    p.add_argument("--traceback", action="store_true", help="show tracebacks of internal errors")
    p.set_defaults(handler=_sweep)


def _err(text: str) -> None:
    for line in str(text).splitlines() or [""]:
        print(f"ibfem sweep: {line}", file=sys.stderr)


def _dry_run(sweep, out: Path) -> int:
    from .cases import build_cases, canonical, scene_digest
    from .records import Records

    cases = build_cases(sweep)
    records = Records(out, scene_digest(sweep.base)).load()
    print(f"{sweep.label}: {sweep.name!r}, mode {sweep.mode}, {len(cases)} cases, scene {sweep.scene_path}")
    for c in cases:
        params = ", ".join(f"{k} = {canonical(v)}" for k, v in c.params.items())
        done = records.latest.get(c.hash, {}).get("status")
        state = f"invalid: {c.message}" if c.status == "invalid" else (f"recorded {done}" if done else "to run")
        print(f"  {c.index:4d} {c.hash}  {params}  [{state}]")
    bad = sum(c.status == "invalid" for c in cases)
    print(f"{len(cases) - bad} valid, {bad} invalid; results would go to {out}/")
    return 0


def _sweep(args: argparse.Namespace) -> int:
    from .engine import EngineError, EngineOptions
    from .spec import SweepError, load_sweep

    try:
        sweep = load_sweep(args.sweep_file)
    except SweepError as err:
        _err(str(err))
        return 2
    out = Path(args.out) if args.out else Path("out") / Path(args.sweep_file).stem
    if args.dry_run:
        return _dry_run(sweep, out)
    if args.workers is not None and args.workers < 1:
        _err(f"--workers = {args.workers}: must be at least 1")
        return 2
    if args.case_timeout is not None and not args.case_timeout > 0:
        _err(f"--case-timeout = {args.case_timeout}: must be a positive number of seconds")
        return 2
    opts = EngineOptions(serial=args.serial, workers=args.workers, scheduler_address=args.scheduler_address,
                         scheduler_file=args.scheduler_file, memory_limit=args.memory_limit,
                         case_timeout=args.case_timeout)
    from .run import run_sweep

    try:
        outcome = run_sweep(sweep, out, opts, retry_failed=args.retry_failed, quiet=args.quiet,
                            shared_files=args.shared_files, plots=not args.no_plots)
    except EngineError as err:
        _err(str(err))
        return 3
    except OSError as err:
        _err(f"cannot write results to {out}: {err.strerror or err}")
        return 4
    counts = ", ".join(f"{n} {s}" for s, n in sorted(outcome.counts.items()))
    print(f"{sweep.name}: {len(outcome.cases)} cases ({counts}); ran {outcome.ran} on {outcome.engine}, "
          f"skipped {outcome.skipped} recorded earlier; results in {out}/results.csv")
    return 0 if outcome.all_ok else 1
