"""The pictures of a run rendered in a second process while the first goes on with the run.

Rendering (matplotlib) and the rest of the run need nothing from each other once the solution,
its recovered stresses and the bodies' output meshes exist, so forked children render the
pictures while the parent solves the error estimate's coarser grid (``ibfem run`` starts them
right after the solve) and clips and writes the bodies: with two idle cores one child the fields over the bodies and another
the contact and line profiles, with one idle core one child all of them, and the output takes
about the longest of the processes instead of their sum. Without an idle core (the load average
at or above the cores) a second process would only share the same cores and cost its own start
and import, so the pictures are rendered here after the other files. The child inherits the solution as it is (no copy, no pickling) and sends back only
the names of the files it wrote. Where a process cannot be forked (a platform without ``fork``,
a daemonic worker process of a pool) the pictures are rendered in this process, one after the
other, as they would be without this module. A child that fails for any reason other than a
missing matplotlib has its pictures rendered again here, so that its error is raised where it
happens, with its own traceback."""

from __future__ import annotations

import multiprocessing
import os
import threading
import time
from pathlib import Path
from typing import Any, Mapping

from ibfem.solver.model import problem as pb

__all__ = ["PlotJob"]


def _render(out_dir: Path, problem: pb.Problem, solution: pb.Solution, summary: Mapping[str, Any],
            outputs: Mapping[str, Any], groups: tuple[str, ...]) -> tuple[list[Path], str | None]:
    """(files written, None) or ([], the reason) when matplotlib is missing."""
    from .plots import write_plots

    try:  # matplotlib is imported when the first figure is made
        return write_plots(out_dir, problem, solution, summary, outputs, groups), None
    except ImportError as err:
        return [], f"plots not written: matplotlib is not installed ({err}); pip install 'ibfem[pictures]'"


def _child(writer, *args) -> None:
    t0 = time.perf_counter()
    try:
        files, missing = _render(*args)
        writer.send(("ok", [str(p) for p in files], missing, time.perf_counter() - t0))
    except BaseException as err:  # noqa: BLE001 - reported to the parent, which renders again
        writer.send(("failed", repr(err), None, time.perf_counter() - t0))
    finally:
        writer.close()


def idle_cores() -> int:
    """The cores the machine's load leaves idle (this process, running, is part of the load):
    the cores this process may use less the one-minute load average, rounded down."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        cores = os.cpu_count() or 1
    try:
        load = os.getloadavg()[0]
    except (AttributeError, OSError):  # no load average (Windows)
        load = 1.0
    return max(0, int(cores - load))


def _fork_context():
    if threading.active_count() > 1:  # a process forks safely with one thread only
        return None
    if "fork" not in multiprocessing.get_all_start_methods() or multiprocessing.current_process().daemon:
        return None
    return multiprocessing.get_context("fork")


class PlotJob:
    """Start rendering the pictures, each group of them (solver.io.plots.GROUPS: the fields, the
    profiles) in a forked child where possible; :meth:`result` waits for them. ``summary`` and
    ``outputs`` are the children's as they are when the job starts."""

    def __init__(self, out_dir: Path, problem: pb.Problem, solution: pb.Solution, summary: Mapping[str, Any],
                 outputs: Mapping[str, Any], parallel: bool = True):
        from .plots import GROUPS

        self.args = (Path(out_dir), problem, solution, summary, dict(outputs))
        self.children: list[tuple[Any, Any, tuple[str, ...]]] = []
        context = _fork_context() if parallel else None
        children = min(len(GROUPS), idle_cores()) if context is not None else 0
        shares = [GROUPS] if children == 1 else [(group,) for group in GROUPS] if children else []
        for groups in shares:
            reader, writer = context.Pipe(duplex=False)
            process = context.Process(target=_child, args=(writer, *self.args, groups), daemon=True)
            process.start()
            writer.close()
            self.children.append((process, reader, groups))

    @property
    def parallel(self) -> bool:
        return bool(self.children)

    def result(self) -> tuple[list[Path], str | None, float]:
        """(files written, the reason when matplotlib is missing, the rendering's seconds: the
        longest child's)."""
        if not self.children:
            t0 = time.perf_counter()
            files, missing = _render(*self.args, ("fields", "profiles"))
            return files, missing, time.perf_counter() - t0
        files, reasons, seconds = [], [], 0.0
        for process, reader, groups in self.children:
            status, written, missing, took = self._wait(process, reader)
            if status != "ok":  # rendered again here: its error is raised with its own traceback
                t0 = time.perf_counter()
                written, missing = _render(*self.args, groups)
                took = time.perf_counter() - t0
            files += [Path(p) for p in written]
            reasons += [missing] if missing and missing not in reasons else []
            seconds = max(seconds, took)
        return files, "; ".join(reasons) or None, seconds

    @staticmethod
    def _wait(process, reader):
        try:
            return reader.recv()
        except EOFError:  # the child died without a word (killed, out of memory)
            return "died", [], None, 0.0
        finally:
            reader.close()
            process.join()
