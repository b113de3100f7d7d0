"""The pictures of a run rendered in other processes while the run goes on.

Rendering (matplotlib) and the rest of the run need nothing from each other once the solution,
its recovered stresses and the bodies' output meshes exist, so other processes render the
pictures while the run solves the error estimate's coarser grid and clips and writes the
bodies, and the output takes about the longest of the processes instead of their sum.

Two ways of starting them. A :class:`PictureWorker` started early in the run (``ibfem run``
starts it before it loads a scene whose file asks for pictures, whatever the machine's load, and
replaces it by one forked from the loaded scene when the problem holds functions that do not
pickle) imports matplotlib and the plotting modules while the run loads the scene and solves,
then renders the job it is sent (the problem, the summary and the 2D bodies' output meshes or
the solution, pickled: a few megabytes in 2D) with a helper forked from it: the two take the pictures one at a time (2D:
``fields.png``, each contact's close-up, the profiles), the worker at once, the helper when the
run's own writing is done (its core is then free) or at once when the machine has two idle
cores. Where the problem does not pickle (a 3D part whose geometry holds local functions) or no
worker was started, children are forked when the pictures start and inherit the solution as it
is (no copy), importing matplotlib themselves: one whatever the load (it renders beside the
error estimate and the VTK files), one per group of pictures (the fields, the profiles) with two
idle cores. Where a process cannot be forked (a platform without ``fork``, a daemonic worker
process of a pool, another thread alive) the pictures are rendered here after the other files.
A process that fails for any reason other than a missing matplotlib has its pictures rendered
again here, so that its error is raised where it happens, with its own traceback."""

from __future__ import annotations

import gc
import io
import json
import os
import pickle
import sys
import types
import threading
import time
import tomllib
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

if TYPE_CHECKING:  # only named in annotations: a worker started before the run's imports needs none
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


def _scene_pictures(scene_path: Path) -> str | None:
    """The ``model`` of a scene file whose ``[output]`` table sets ``plots = true``, None when it
    asks for no pictures (read as text: the scene is validated later; an unreadable file asks
    for nothing)."""
    try:
        text = scene_path.read_bytes().decode("utf-8-sig")
        data = json.loads(text) if scene_path.suffix.lower() == ".json" else tomllib.loads(text)
        if data.get("output", {}).get("plots") is not True:
            return None
        return str(data.get("model", "plane_strain"))
    except (OSError, ValueError, AttributeError, RecursionError):  # TOMLDecodeError is a ValueError
        return None


def _fork_context():
    if threading.active_count() > 1 and "ibfem.geometry" in sys.modules:  # the projections' pool
        from ibfem.geometry import release_threads

        release_threads()
    if threading.active_count() > 1:  # a process forks safely with one thread only
        return None
    import multiprocessing  # here: a run without pictures needs none of it

    if "fork" not in multiprocessing.get_all_start_methods() or multiprocessing.current_process().daemon:
        return None
    return multiprocessing.get_context("fork")


def _shares(groups: tuple[str, ...], processes: int) -> list[tuple[str, ...]]:
    """The groups of pictures each of ``processes`` processes renders."""
    return [groups] if processes == 1 else [(group,) for group in groups] if processes else []


def _warm_up() -> float:
    """Import what rendering needs (matplotlib's figure and axes modules included: a tenth of a
    second that the first picture would otherwise pay); the seconds it took. A throw-away
    picture drawn while no job has come (to fill matplotlib's caches) was tried and dropped:
    alternating runs of plate_with_hole and lame_quarter_annulus wrote their output slower
    with it."""
    t0 = time.perf_counter()
    try:
        from matplotlib.backends import backend_agg  # noqa: F401 - imported here, while the run solves
        from matplotlib import figure  # noqa: F401

        from . import plots  # noqa: F401
    except ImportError:  # reported with the job: a missing matplotlib is the reason given
        pass
    return time.perf_counter() - t0


def _while_waiting(conn, planar: bool) -> None:
    """While no job has come, what the job will need first: for a 2D run, the empty figures of
    its field picture and a stress line picture (:func:`solver.io.plots.prepare_figures`: their
    axes and tick marks, about a quarter of those pictures' time); for a 3D run, the solver's
    solution classes, which its job unpickles (a worker started before the scene was loaded does
    not have them; a 2D job whose bodies' output meshes are made goes without its solution and
    needs none)."""
    if conn.poll(0):
        return
    try:
        if planar:
            from .plots import prepare_figures

            prepare_figures()
        else:
            import ibfem.solver.solution  # noqa: F401
    except ImportError:  # matplotlib missing: reported with the job
        pass


#: the start of a message that gives the field picture's layout ahead of the job
_LAYOUT = b"layout:"


def _next_job(conn) -> bytes:
    """The job's message (empty: none will come). A layout message before it
    (:meth:`PictureWorker.start`) has the field picture's fixed parts drawn while the run
    solves, unless the job is already waiting."""
    while True:
        message = conn.recv_bytes()
        if not message.startswith(_LAYOUT):
            return message
        if conn.poll(0):
            continue
        try:
            from .plots import prepare_field_background

            prepare_field_background(*pickle.loads(message[len(_LAYOUT):]))
        except ImportError:  # matplotlib missing: reported with the job
            pass


def _local_functions(problem) -> dict[int, Any]:
    """The local functions (closures, lambdas) the problem holds, by id: they do not pickle, but
    a worker forked after the problem was made holds the same objects at the same addresses, so
    a job refers to them by id (:class:`_Pickler`) instead of copying them."""
    seen, found, stack = set(), {}, [problem]
    while stack:
        obj = stack.pop()
        if id(obj) in seen or isinstance(obj, (int, float, str, bytes, type)) or type(obj).__module__ == "numpy":
            continue
        seen.add(id(obj))
        if isinstance(obj, types.FunctionType) and "<locals>" in obj.__qualname__:
            found[id(obj)] = obj
        else:
            stack.extend(gc.get_referents(obj))
    return found


class _Pickler(pickle.Pickler):
    """Pickles a job with the problem's local functions as references (:func:`_local_functions`)."""

    def __init__(self, file, shared: dict[int, Any]):
        super().__init__(file, protocol=pickle.HIGHEST_PROTOCOL)
        self.shared = shared

    def persistent_id(self, obj):
        return id(obj) if id(obj) in self.shared and self.shared[id(obj)] is obj else None


class _Unpickler(pickle.Unpickler):
    def __init__(self, file, shared: dict[int, Any]):
        super().__init__(file)
        self.shared = shared

    def persistent_load(self, pid):
        return self.shared[pid]


def _dumps(obj, shared: dict[int, Any]) -> bytes:
    buffer = io.BytesIO()
    _Pickler(buffer, shared).dump(obj)
    return buffer.getvalue()


def _claim(args: tuple, tasks: tuple[str, ...], counter) -> tuple:
    """Render the pictures of ``tasks`` one at a time, each taken from the shared ``counter``
    (the next task no process has taken yet) until none is left. What the process reports:
    (status, the tasks rendered, file names, the reason pictures are missing or the error,
    seconds)."""
    t0 = time.perf_counter()
    done: list[str] = []
    files: list[str] = []
    reason = None
    while True:
        with counter.get_lock():
            k = counter.value
            counter.value = k + 1
        if k >= len(tasks):
            return "ok", done, files, reason, time.perf_counter() - t0
        try:
            written, missing = _render(*args, (tasks[k],))
        except BaseException as err:  # noqa: BLE001 - reported to the run, which renders again
            return "failed", done, files, repr(err), time.perf_counter() - t0
        done.append(tasks[k])
        files += [str(p) for p in written]
        reason = reason or missing


def _helper(args: tuple, tasks: tuple[str, ...], counter, go, writer) -> None:
    """The worker's second process: it takes tasks once the run says its own core is free (a
    word on ``go``: its writing is done, or the machine has a second idle core), or leaves when
    the worker has taken them all."""
    outcome = ("ok", [], [], None, 0.0)
    try:
        while not go.poll(0.01):
            if counter.value >= len(tasks):
                break
        else:
            try:
                go.recv()
            except EOFError:  # the run is gone without a word: nothing to render for
                return
            outcome = _claim(args, tasks, counter)
    finally:
        writer.send(outcome)
        writer.close()


def _serve(conn, go, shared: dict[int, Any], planar: bool) -> None:
    """The worker: warm up (and prepare while no job has come, :func:`_while_waiting`), wait for
    one job (an empty message or a closed pipe: nothing to do), fork a helper for it and render
    its tasks with the helper (:func:`_claim`), report both processes' outcomes (the worker's,
    then the helper's)."""
    warm = _warm_up()
    _while_waiting(conn, planar)
    try:
        job = _next_job(conn)
    except EOFError:
        return
    if not job:
        return
    args, tasks = _Unpickler(io.BytesIO(job), shared).load()
    import multiprocessing

    counter = multiprocessing.get_context("fork").Value("i", 0)
    reader, writer = multiprocessing.Pipe(duplex=False)
    pid = os.fork()
    if pid == 0:  # the helper: report and leave without the worker's cleanup
        try:
            reader.close()
            _helper(args, tasks, counter, go, writer)
        finally:
            os._exit(0)
    writer.close()
    conn.send((_claim(args, tasks, counter), warm))
    try:
        conn.send((reader.recv(), warm))
    except EOFError:  # the helper died without a word
        conn.send((("died", [], [], None, 0.0), warm))
    finally:
        reader.close()
        os.waitpid(pid, 0)
    conn.close()


class PictureWorker:
    """A process started early in a run that imports matplotlib and the plotting modules while
    the run goes on, then renders the pictures it is sent (:class:`PlotJob`) with a helper forked from
    it: the worker starts at once, the helper when the run tells it that its own core is free
    (:meth:`free`), and each takes the next picture left. It is started whatever the machine's
    load: the import and the rendering cost the same CPU time in it as in the run's own process,
    and on a busy machine it still imports while the run solves. :meth:`start` returns None
    where it cannot be used: no ``fork``, or a problem that does not pickle (its pictures are
    then rendered by children forked when they start)."""

    def __init__(self, process, conn, go, shared: dict[int, Any]):
        self.process, self.conn, self.go, self.busy, self.shared = process, conn, go, False, shared
        self.sending: threading.Thread | None = None

    @classmethod
    def start(cls, problem: pb.Problem, early: PictureWorker | None = None) -> PictureWorker | None:
        """The worker for ``problem``: ``early`` (:meth:`early`, started before the problem was
        made) when the problem pickles without local functions, else one forked now, which holds
        them (``early`` is then stopped)."""
        shared = _local_functions(problem)
        try:
            _dumps(problem, shared)
        except Exception:  # noqa: BLE001 - something else that does not pickle: children forked later instead
            shared = None
        if early is not None and shared == {} and early.process.is_alive():
            return early._laid_out(problem)  # forked already: usable even where this process can no longer fork
        if early is not None:
            early.stop(at_once=True)
        context = _fork_context()
        if context is None or shared is None:
            return None
        return cls._launch(context, shared, getattr(problem, "dim", 2) == 2)._laid_out(problem)

    def _laid_out(self, problem: pb.Problem) -> PictureWorker:
        """Send a 2D problem's field picture layout (:func:`solver.io.plots.field_layout`): the
        worker draws that picture's fixed parts while the run solves."""
        if getattr(problem, "dim", None) == 2:
            from .plots import field_layout

            layout = field_layout(problem)
            if layout is not None:
                try:
                    self.conn.send_bytes(_LAYOUT + pickle.dumps(layout))
                except OSError:  # the worker is gone: the job finds it so
                    pass
        return self

    @classmethod
    def early(cls, scene_path: str | Path) -> PictureWorker | None:
        """A worker started before the scene is loaded, when the scene file's ``[output]`` table
        asks for pictures: it imports matplotlib while the scene loads (whose checks import the
        solver) and the run solves, so that a run of a second has its pictures' processes ready
        when its solve ends. Pass it to :meth:`start` once the problem is made."""
        model = _scene_pictures(Path(scene_path))  # first: a run without pictures imports no multiprocessing
        context = _fork_context() if model is not None else None
        return cls._launch(context, {}, model != "solid") if context is not None else None

    @classmethod
    def _launch(cls, context, shared: dict[int, Any], planar: bool) -> PictureWorker:
        conn, child_end = context.Pipe()
        go_reader, go = context.Pipe(duplex=False)
        process = context.Process(target=_serve, args=(child_end, go_reader, shared, planar), daemon=True)
        process.start()
        child_end.close()
        go_reader.close()
        return cls(process, conn, go, shared)

    def submit(self, args: tuple, tasks: tuple[str, ...]) -> bool:
        """Send a job; False when it cannot be sent (it does not pickle, the worker is gone or
        already has one)."""
        if self.busy or not self.process.is_alive():
            return False
        try:
            job = _dumps((args, tasks), self.shared)
        except Exception:  # noqa: BLE001 - something in the solution that does not pickle
            return False
        if not self.process.is_alive():
            return False
        # sent by a thread: a job larger than the pipe's buffer would block this process until
        # the worker, still warming up on a short run, reads it
        self.sending = threading.Thread(target=self._send, args=(job,), daemon=True)
        self.sending.start()
        self.busy = True
        return True

    def _send(self, job: bytes) -> None:
        try:
            self.conn.send_bytes(job)
        except OSError:  # the worker is gone: result() finds its pipe closed
            pass

    def free(self) -> None:
        """Tell the helper that a core is free for it (once; nothing when it is gone)."""
        if not self.go.closed:
            try:
                self.go.send(True)
            except OSError:
                pass
            self.go.close()

    def stop(self, at_once: bool = False) -> None:
        """Let the worker go without a job (it leaves when the run ends in any case); ``at_once``:
        ended now, its imports left unfinished."""
        if at_once and not self.busy:
            self.process.terminate()
            self.process.join()
        elif not self.busy:
            try:
                self.conn.send_bytes(b"")
            except OSError:
                pass
        self.conn.close()
        self.go.close()


class PlotJob:
    """Start rendering the pictures in other processes where possible: the ``worker`` started
    earlier in the run when it takes the job (it and its helper take the pictures one at a
    time, solver.io.plots.picture_tasks), else forked children, each a group of them
    (solver.io.plots.GROUPS: the fields, the profiles); :meth:`result` waits for them.
    ``summary`` and ``outputs`` are the processes' as they are when the job starts."""

    def __init__(self, out_dir: Path, problem: pb.Problem, solution: pb.Solution, summary: Mapping[str, Any],
                 outputs: Mapping[str, Any], parallel: bool = True, worker: PictureWorker | None = None):
        from .plots import GROUPS, picture_tasks

        self.args = (Path(out_dir), problem, solution, summary, dict(outputs))
        self.children: list[tuple[Any, Any, tuple[str, ...]]] = []
        self.worker: PictureWorker | None = None
        self.warm_up_s = 0.0
        self.rendered_by = 0
        context = _fork_context() if parallel else None
        if worker is not None and parallel:
            self.tasks = picture_tasks(problem, summary)
            if worker.submit(self._job_args(), self.tasks):
                self.worker = worker
                if idle_cores() >= 2:  # a second idle core: the helper starts at once
                    worker.free()
                return
        if worker is not None:
            worker.stop()
        # one child whatever the load (it renders beside the error estimate and the VTK files,
        # the run's processes sharing the machine with the others), two with two idle cores
        children = max(1, min(len(GROUPS), idle_cores())) if context is not None else 0
        for groups in _shares(GROUPS, children):
            reader, writer = context.Pipe(duplex=False)
            process = context.Process(target=_child, args=(writer, *self.args, groups), daemon=True)
            process.start()
            writer.close()
            self.children.append((process, reader, groups))

    def _job_args(self) -> tuple:
        """The arguments sent to the worker: a 2D job whose bodies' output meshes are all made
        goes without its solution (the pictures draw those meshes), which the worker then
        neither unpickles nor imports the classes of."""
        out_dir, problem, solution, summary, outputs = self.args
        if getattr(problem, "dim", None) == 2 and all(b.name in outputs for b in problem.bodies):
            solution = None
        return out_dir, problem, solution, summary, outputs

    @property
    def parallel(self) -> bool:
        return bool(self.children) or self.worker is not None

    @property
    def processes(self) -> int:
        """The processes rendering the pictures (0: this one); with a worker, after
        :meth:`result`: those that rendered at least one."""
        return self.rendered_by if self.worker is not None else len(self.children)

    def result(self) -> tuple[list[Path], str | None, float]:
        """(files written, the reason when matplotlib is missing, the rendering's seconds: the
        longest process's). Called when the run's own writing is done: its core is then free
        for the worker's helper."""
        if self.worker is not None:
            return self._worker_result()
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

    def _worker_result(self) -> tuple[list[Path], str | None, float]:
        """The worker's and its helper's pictures; a task neither rendered (a failure, a process
        that died) is rendered here, where its error is raised with its own traceback."""
        self.worker.free()
        if self.worker.sending is not None:
            self.worker.sending.join()
        files, reasons, seconds, done = [], [], 0.0, []
        conn = self.worker.conn
        for _ in range(2):
            try:
                (status, rendered, written, missing, took), self.warm_up_s = conn.recv()
            except (EOFError, OSError):  # the worker died without a word (killed, out of memory)
                break
            files += [Path(p) for p in written]
            done += rendered
            self.rendered_by += bool(rendered)
            if status == "ok" and missing and missing not in reasons:
                reasons.append(missing)
            seconds = max(seconds, took)
        conn.close()
        self.worker.process.join()
        left = tuple(t for t in self.tasks if t not in done)
        if left:
            t0 = time.perf_counter()
            written, missing = _render(*self.args, left)
            files += written
            reasons += [missing] if missing and missing not in reasons else []
            seconds = max(seconds, time.perf_counter() - t0)
        return sorted(files), "; ".join(reasons) or None, seconds

    def _outcomes(self):
        """(groups, outcome) of every forked child, as they report them."""
        for process, reader, groups in self.children:
            yield groups, self._wait(process, reader)

    @staticmethod
    def _wait(process, reader):
        try:
            return reader.recv()
        except EOFError:  # the child died without a word (killed, out of memory)
            return "died", [], None, 0.0
        finally:
            reader.close()
            process.join()
