"""The pictures of a run rendered in a second process while the first writes the other files.

Rendering (matplotlib) and the VTU files (numpy) need nothing from each other once the summary
and the bodies' output meshes exist, so a forked child renders the pictures while the parent
clips and writes the bodies: on two cores the output takes about the longer of the two instead
of their sum. The child inherits the solution as it is (no copy, no pickling) and sends back only
the names of the files it wrote. Where a process cannot be forked (a platform without ``fork``,
a daemonic worker process of a pool) the pictures are rendered in this process, one after the
other, as they would be without this module. A child that fails for any reason other than a
missing matplotlib has the pictures rendered again here, so that its error is raised where it
happens, with its own traceback."""

from __future__ import annotations

import multiprocessing
import threading
import time
from pathlib import Path
from typing import Any, Mapping

from ibfem.solver.model import problem as pb

__all__ = ["PlotJob"]


def _render(out_dir: Path, problem: pb.Problem, solution: pb.Solution, summary: Mapping[str, Any],
            outputs: Mapping[str, Any]) -> tuple[list[Path], str | None]:
    """(files written, None) or ([], the reason) when matplotlib is missing."""
    from .plots import write_plots

    try:  # matplotlib is imported when the first figure is made
        return write_plots(out_dir, problem, solution, summary, outputs), None
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


def _fork_context():
    if threading.active_count() > 1:  # a process forks safely with one thread only
        return None
    if "fork" not in multiprocessing.get_all_start_methods() or multiprocessing.current_process().daemon:
        return None
    return multiprocessing.get_context("fork")


class PlotJob:
    """Start rendering the pictures (in a forked child where possible); :meth:`result` waits
    for them. ``summary`` and ``outputs`` are the child's as they are when the job starts."""

    def __init__(self, out_dir: Path, problem: pb.Problem, solution: pb.Solution, summary: Mapping[str, Any],
                 outputs: Mapping[str, Any], parallel: bool = True):
        self.args = (Path(out_dir), problem, solution, summary, dict(outputs))
        self.process = self.reader = None
        context = _fork_context() if parallel else None
        if context is not None:
            self.reader, writer = context.Pipe(duplex=False)
            self.process = context.Process(target=_child, args=(writer, *self.args), daemon=True)
            self.process.start()
            writer.close()

    @property
    def parallel(self) -> bool:
        return self.process is not None

    def result(self) -> tuple[list[Path], str | None, float]:
        """(files written, the reason when matplotlib is missing, the rendering's seconds)."""
        if self.process is not None:
            try:
                status, files, missing, seconds = self.reader.recv()
            except EOFError:  # the child died without a word (killed, out of memory)
                status = "died"
            finally:
                self.reader.close()
                self.process.join()
            if status == "ok":
                return [Path(p) for p in files], missing, seconds
        t0 = time.perf_counter()
        files, missing = _render(*self.args)
        return files, missing, time.perf_counter() - t0
