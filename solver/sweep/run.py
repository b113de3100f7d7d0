"""One sweep from its file to its results: cases built and validated, earlier records read,
the cases left run on the engine, each result written as it arrives, table and plots."""

from __future__ import annotations

import threading
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

from .cases import Case, build_cases, pack_files, scene_digest
from .engine import DaskSession, EngineOptions, run_serial
from .progress import SweepProgress
from .records import Records, output_values, warn
from .spec import Sweep
from .worker import fingerprint, run_case


@dataclass
class SweepOutcome:
    out: Path
    cases: list[Case]
    records: Records
    ran: int = 0
    skipped: int = 0
    engine: str = ""
    plots: list[Path] = field(default_factory=list)

    def record(self, case: Case) -> dict[str, Any]:
        return self.records.latest.get(case.hash, {})

    @property
    def counts(self) -> Counter:
        return Counter(self.record(c).get("status", "pending") for c in self.cases)

    @property
    def all_ok(self) -> bool:
        return all(self.record(c).get("status") == "ok" for c in self.cases)


def _payload(sweep: Sweep, case: Case, opts: EngineOptions, shared_files: bool) -> dict:
    scene = case.scene
    files: dict[str, bytes] = {}
    if opts.remote and not shared_files:
        import json

        scene = json.loads(json.dumps(scene))
        files = pack_files(scene, sweep.base_dir)
    return {"hash": case.hash, "index": case.index, "scene": scene, "files": files,
            "base_dir": str(sweep.base_dir.resolve()), "label": f"{sweep.label} {case.label}",
            "fingerprint": fingerprint(), "timeout": opts.case_timeout}


class _Collector:
    """Turns each arriving result into a record, its case directory and a fresh table."""

    def __init__(self, sweep: Sweep, cases: list[Case], records: Records, progress: SweepProgress):
        self.sweep, self.cases, self.records, self.progress = sweep, cases, records, progress
        self.by_hash = {c.hash: c for c in cases}
        self.last_csv = 0.0

    def record(self, case: Case, result: dict) -> None:
        rec = {"hash": case.hash, "case": case.index, "params": case.params,
               "status": result.get("status", "error"), "message": result.get("message", ""),
               "outputs": output_values(result.get("summary"), self.sweep.columns),
               "wall_s": result.get("wall_s"), "peak_memory_mb": result.get("peak_memory_mb"),
               "worker": result.get("worker", ""), "ibfem": result.get("ibfem", "")}
        if case.scene:
            d = self.records.write_case_dir(case.hash, case.scene, result.get("files") or {})
            rec["dir"] = d.relative_to(self.records.out).as_posix()
        self.records.append(rec)

    def __call__(self, result: dict) -> None:
        case = self.by_hash[result["hash"]]
        self.record(case, result)
        self.progress.case_done(case.index, result.get("status", "error"), result.get("wall_s"),
                                result.get("message", ""))
        if time.perf_counter() - self.last_csv > 1.0:
            self.records.write_csv(self.cases, self.sweep.columns)
            self.last_csv = time.perf_counter()


def _import_plotting() -> None:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot  # noqa: F401
    except ImportError:
        pass


def _started(progress: SweepProgress, what: str, workers: int, quiet: bool) -> None:
    progress.set_slots(workers)
    if not quiet:
        warn(f"running on {what} ({workers} workers)")


def run_sweep(sweep: Sweep, out: str | Path, opts: EngineOptions | None = None, retry_failed: bool = False,
              quiet: bool = False, shared_files: bool = False, runner: Callable = run_case,
              plots: bool = True) -> SweepOutcome:
    """Run the cases of ``sweep`` that have no record in ``out`` yet (and the failed ones with
    ``retry_failed``); results are written as they arrive. ``runner`` is the task (tests)."""
    opts = opts or EngineOptions()
    # the cluster starts (and its workers warm up) while the cases are built and checked; without
    # the extra this stops here, before anything is written, with one line naming it
    session = None if opts.serial else DaskSession(opts)
    try:
        return _run(sweep, Path(out), opts, retry_failed, quiet, shared_files, runner, plots, session)
    finally:
        if session is not None:
            session.close()


def _run(sweep: Sweep, out: Path, opts: EngineOptions, retry_failed: bool, quiet: bool, shared_files: bool,
         runner: Callable, plots: bool, session) -> SweepOutcome:
    cases = build_cases(sweep)
    records = Records(Path(out), scene_digest(sweep.base)).load()
    if records.ignored:
        warn(f"{records.ignored} earlier records in {records.jsonl} are of another base scene or cut short: ignored")
    outcome = SweepOutcome(Path(out), cases, records)
    progress = SweepProgress(0, quiet=quiet)
    collect = _Collector(sweep, cases, records, progress)
    for case in cases:
        if case.status == "invalid" and records.latest.get(case.hash, {}).get("message") != case.message:
            collect.record(case, {"status": "invalid", "message": case.message})
    todo = records.to_run([c.hash for c in cases if c.status != "invalid"], retry_failed)
    payloads = []
    for case in cases:
        if case.hash in todo:
            try:
                payloads.append(_payload(sweep, case, opts, shared_files))
            except (OSError, ValueError) as err:
                collect.record(case, {"status": "error", "message": f"cannot send the case's files: {err}"})
    invalid = sum(c.status == "invalid" for c in cases)
    outcome.ran, outcome.skipped = len(payloads), len(cases) - len(payloads) - invalid
    progress.total = len(payloads)
    if not quiet:
        warn(f"{len(cases)} cases: {len(payloads)} to run, {outcome.skipped} recorded earlier, {invalid} invalid")
    try:
        if not payloads:
            outcome.engine = "none (nothing left to run)"
        elif opts.serial:
            outcome.engine = run_serial(payloads, collect, runner)
        else:
            session.ready()
            _started(progress, session.description, session.workers, quiet)
            if plots:  # the driver waits on the workers: load the plotting library meanwhile
                threading.Thread(target=_import_plotting, name="ibfem-sweep-plots", daemon=True).start()
            outcome.engine = session.run(payloads, collect, runner)
            session.close_in_background()  # overlaps the table and plots
    finally:
        progress.close()
        records.write_csv(cases, sweep.columns)
    if plots:
        from .plots import write_plots

        outcome.plots = write_plots(outcome)
    return outcome
