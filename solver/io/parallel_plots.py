"""The pictures of a run rendered in other processes while the run goes on.

Rendering (matplotlib) and the rest of the run need nothing from each other once the solution,
its recovered stresses and the bodies' output meshes exist, so other processes render the
pictures while the run solves the error estimate's coarser grid and clips and writes the
bodies: with two idle cores one process renders the fields over the bodies and another the
contact and line profiles, with one idle core one process all of them, and the output takes
about the longest of the processes instead of their sum.

Two ways of starting them. A :class:`PictureWorker` started early in the run (``ibfem run``
starts it as soon as the scene is read, whatever the machine's load) imports matplotlib and the
plotting modules while the run imports the solver and solves, then renders the job it is sent
(the problem, the solution and the summary, pickled: a few megabytes in 2D), forking once more
for the second group when two cores are idle. Where the problem does not pickle (a 3D part whose
geometry holds local functions) or no worker was started, children are forked when the pictures
start and inherit the solution as it is (no copy), importing matplotlib themselves; without an
idle core (the load average at or above the cores) such a child would only share the same cores
and add its own import after the solve, so the pictures are then rendered here after the other
files, as they are where a process cannot be forked (a platform without ``fork``, a daemonic
worker process of a pool). A process that fails for any reason other than a missing matplotlib
has its pictures rendered again here, so that its error is raised where it happens, with its own
traceback."""

from __future__ import annotations

import multiprocessing
import os
import pickle
import threading
import time
from pathlib import Path
from typing import Any, Mapping

from ibfem.solver.model import problem as pb

__all__ = ["PlotJob", "PictureWorker"]


def _render(out_dir: Path, problem: pb.Problem, solution: pb.Solution, summary: Mapping[str, Any],
            outputs: Mapping[str, Any], groups: tuple[str, ...]) -> tuple[list[Path], str | None]:
    """(files written, None) or ([], the reason) when matplotlib is missing."""
    from .plots import write_plots

    try:  # matplotlib is imported when the first figure is made
        return write_plots(out_dir, problem, solution, summary, outputs, groups), None
    except ImportError as err:
        return [], f"plots not written: matplotlib is not installed ({err}); pip install 'ibfem[pictures]'"


def _outcome(args: tuple, groups: tuple[str, ...]) -> tuple:
    """What a process reports of one group of pictures: (status, file names, missing, seconds)."""
    t0 = time.perf_counter()
    try:
        files, missing = _render(*args, groups)
        return "ok", [str(p) for p in files], missing, time.perf_counter() - t0
    except BaseException as err:  # noqa: BLE001 - reported to the parent, which renders again
        return "failed", repr(err), None, time.perf_counter() - t0


def _child(writer, *args) -> None:
    try:
        writer.send(_outcome(args[:-1], args[-1]))
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


def _shares(groups: tuple[str, ...], processes: int) -> list[tuple[str, ...]]:
    """The groups of pictures each of ``processes`` processes renders."""
    return [groups] if processes == 1 else [(group,) for group in groups] if processes else []


def _warm_up() -> float:
    """Import what rendering and a job's unpickling need; the seconds it took."""
    t0 = time.perf_counter()
    try:
        from matplotlib.backends import backend_agg  # noqa: F401 - imported here, while the run solves

        import ibfem.solver.solution  # noqa: F401 - the classes a job's solution pickles
        from . import plots  # noqa: F401
    except ImportError:  # reported with the job: a missing matplotlib is the reason given
        pass
    return time.perf_counter() - t0


def _serve(conn) -> None:
    """The worker: warm up, wait for one job (None or a closed pipe: nothing to do), render its
    first share here and the others in forked children, report every share in order."""
    warm = _warm_up()
    try:
        job = conn.recv()
    except EOFError:
        return
    if job is None:
        return
    args, shares = pickle.loads(job)
    children = []
    for groups in shares[1:]:
        reader, writer = multiprocessing.Pipe(duplex=False)
        pid = os.fork()
        if pid == 0:  # the second share's process: report and leave without the worker's cleanup
            try:
                reader.close()
                _child(writer, *args, groups)
            finally:
                os._exit(0)
        writer.close()
        children.append((pid, reader))
    conn.send((_outcome(args, shares[0]), warm))
    for pid, reader in children:
        try:
            conn.send((reader.recv(), warm))
        except EOFError:  # the child died without a word
            conn.send((("died", [], None, 0.0), warm))
        finally:
            reader.close()
            os.waitpid(pid, 0)
    conn.close()


class PictureWorker:
    """A process started early in a run that imports matplotlib and the plotting modules while
    the run goes on, then renders the pictures it is sent (:class:`PlotJob`). It is started
    whatever the machine's load: the import and the rendering cost the same CPU time in it as in
    the run's own process, and on a busy machine it still imports while the run solves.
    :meth:`start` returns None where it cannot be used: no ``fork``, or a problem that does not
    pickle (its pictures are then rendered by children forked when they start)."""

    def __init__(self, process, conn):
        self.process, self.conn, self.busy = process, conn, False

    @classmethod
    def start(cls, problem: pb.Problem) -> PictureWorker | None:
        context = _fork_context()
        if context is None:
            return None
        try:
            pickle.dumps(problem)
        except Exception:  # noqa: BLE001 - local functions in a geometry: children forked later instead
            return None
        conn, child_end = context.Pipe()
        process = context.Process(target=_serve, args=(child_end,), daemon=True)
        process.start()
        child_end.close()
        return cls(process, conn)

    def submit(self, args: tuple, shares: list[tuple[str, ...]]) -> bool:
        """Send a job; False when it cannot be sent (it does not pickle, the worker is gone or
        already has one)."""
        if self.busy or not self.process.is_alive():
            return False
        try:
            job = pickle.dumps((args, shares), protocol=pickle.HIGHEST_PROTOCOL)
        except Exception:  # noqa: BLE001 - something in the solution that does not pickle
            return False
        try:
            self.conn.send(job)
        except OSError:
            return False
        self.busy = True
        return True

    def stop(self) -> None:
        """Let the worker go without a job (it leaves when the run ends in any case)."""
        if not self.busy:
            try:
                self.conn.send(None)
            except OSError:
                pass
        self.conn.close()


class PlotJob:
    """Start rendering the pictures, each group of them (solver.io.plots.GROUPS: the fields, the
    profiles) in another process where possible: the ``worker`` started earlier in the run when
    it takes the job, else forked children; :meth:`result` waits for them. ``summary`` and
    ``outputs`` are the processes' as they are when the job starts."""

    def __init__(self, out_dir: Path, problem: pb.Problem, solution: pb.Solution, summary: Mapping[str, Any],
                 outputs: Mapping[str, Any], parallel: bool = True, worker: PictureWorker | None = None):
        from .plots import GROUPS

        self.args = (Path(out_dir), problem, solution, summary, dict(outputs))
        self.children: list[tuple[Any, Any, tuple[str, ...]]] = []
        self.worker: PictureWorker | None = None
        self.warm_up_s = 0.0
        context = _fork_context() if parallel else None
        if worker is not None and parallel:
            shares = _shares(GROUPS, 2 if idle_cores() >= 2 else 1)
            if worker.submit(self.args, shares):
                self.worker, self.shares = worker, shares
                return
        if worker is not None:
            worker.stop()
        children = min(len(GROUPS), idle_cores()) if context is not None else 0
        for groups in _shares(GROUPS, children):
            reader, writer = context.Pipe(duplex=False)
            process = context.Process(target=_child, args=(writer, *self.args, groups), daemon=True)
            process.start()
            writer.close()
            self.children.append((process, reader, groups))

    @property
    def parallel(self) -> bool:
        return bool(self.children) or self.worker is not None

    @property
    def processes(self) -> int:
        """The processes rendering the pictures (0: this one)."""
        return len(self.shares) if self.worker is not None else len(self.children)

    def result(self) -> tuple[list[Path], str | None, float]:
        """(files written, the reason when matplotlib is missing, the rendering's seconds: the
        longest process's)."""
        if not self.parallel:
            t0 = time.perf_counter()
            files, missing = _render(*self.args, ("fields", "profiles"))
            return files, missing, time.perf_counter() - t0
        files, reasons, seconds = [], [], 0.0
        for groups, (status, written, missing, took) in self._outcomes():
            if status != "ok":  # rendered again here: its error is raised with its own traceback
                t0 = time.perf_counter()
                written, missing = _render(*self.args, groups)
                took = time.perf_counter() - t0
            files += [Path(p) for p in written]
            reasons += [missing] if missing and missing not in reasons else []
            seconds = max(seconds, took)
        return files, "; ".join(reasons) or None, seconds

    def _outcomes(self):
        """(groups, outcome) of every share, as the processes report them."""
        if self.worker is None:
            for process, reader, groups in self.children:
                yield groups, self._wait(process, reader)
            return
        conn, alive = self.worker.conn, True
        for groups in self.shares:
            try:
                outcome, self.warm_up_s = conn.recv() if alive else (("died", [], None, 0.0), self.warm_up_s)
            except (EOFError, OSError):  # the worker died without a word (killed, out of memory)
                alive, outcome = False, ("died", [], None, 0.0)
            yield groups, outcome
        conn.close()
        self.worker.process.join()

    @staticmethod
    def _wait(process, reader):
        try:
            return reader.recv()
        except EOFError:  # the child died without a word (killed, out of memory)
            return "died", [], None, 0.0
        finally:
            reader.close()
            process.join()
