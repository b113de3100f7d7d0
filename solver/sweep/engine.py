"""Where the cases run: in this process one after the other (``--serial``), or on Dask
distributed: an embedded ``LocalCluster`` of worker processes (one thread each) when no
scheduler is named, else the cluster at ``--scheduler-address`` / ``--scheduler-file`` /
``DASK_SCHEDULER_ADDRESS`` (a laptop's, or an HPC / Kubernetes cluster's started with
dask-jobqueue or dask-kubernetes). Dask does the scheduling: a case whose worker dies is given to
another worker (``distributed.scheduler.allowed-failures`` times, then it is ``killed``). The
embedded cluster's workers are forked from a warm fork server where the platform has one
(:func:`start_fork_server`)."""

from __future__ import annotations

import logging
import os
import secrets
import threading
from dataclasses import dataclass
from typing import Any, Callable

from .records import warn
from .worker import fingerprint, run_case

EXTRA_HINT = "pip install 'ibfem[sweep]'"


class EngineError(RuntimeError):
    """The engine cannot run: Dask missing, no scheduler, workers with another ibfem."""


@dataclass
class EngineOptions:
    serial: bool = False
    workers: int | None = None           # embedded cluster: worker processes (default: the cores)
    scheduler_address: str | None = None
    scheduler_file: str | None = None
    memory_limit: str | None = None      # embedded cluster: per worker ("4GB"; default Dask's "auto")
    case_timeout: float | None = None
    wait_workers_s: float = 120.0        # an existing cluster: how long to wait for a first worker

    def address(self) -> str | None:
        return self.scheduler_address or (None if self.scheduler_file else os.environ.get("DASK_SCHEDULER_ADDRESS") or None)

    @property
    def remote(self) -> bool:
        """Cases may run on other hosts (an existing cluster): their files must travel with them."""
        return not self.serial and bool(self.address() or self.scheduler_file)


def default_workers() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def run_serial(payloads: list[dict], on_result: Callable[[dict], None], runner: Callable = run_case,
               started: Callable[[int], None] | None = None) -> str:
    for p in payloads:
        if started:
            started(1)
        on_result(runner(p))
    return "serial (this process)"


def import_dask():
    try:
        import distributed  # noqa: F401
    except ImportError:
        raise EngineError(f"Dask distributed is not installed: {EXTRA_HINT} (or run with --serial)") from None
    return distributed


#: the embedded cluster's workers are forked from a warm fork server where the platform has one
#: (Linux, macOS); ``IBFEM_SWEEP_START=spawn`` keeps Dask's default (each worker a fresh interpreter)
_FORK_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1", "IBFEM_THREADS": "1"}


def start_fork_server() -> bool:
    """Start multiprocessing's fork server with the solver imported and warm (module
    :mod:`solver.sweep._forkserver`) and one BLAS thread (a worker is one case at a time; the
    variables Dask sets before spawning a worker do not reach processes forked from a server
    started earlier, so the server gets them); Dask's workers are then forked from it. False
    where there is no fork server (Windows) or ``IBFEM_SWEEP_START=spawn``."""
    import multiprocessing

    if os.environ.get("IBFEM_SWEEP_START", "") == "spawn" or "forkserver" not in multiprocessing.get_all_start_methods():
        return False
    import dask
    from distributed.utils import get_mp_context
    from multiprocessing import forkserver

    with dask.config.set({"distributed.worker.multiprocessing-method": "forkserver"}):
        ctx = get_mp_context()  # Dask's preload list, set once per process ...
    ctx.set_forkserver_preload(["ibfem.solver.sweep._forkserver"])  # ... replaced by ours before the server starts
    saved = {k: os.environ.get(k) for k in _FORK_ENV}
    os.environ.update(_FORK_ENV)
    try:
        forkserver.ensure_running()
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    return True


def _connect(opts: EngineOptions):
    """(client, cluster or None, description)."""
    distributed = import_dask()
    address = opts.address()
    try:
        if opts.scheduler_file:
            client = distributed.Client(scheduler_file=opts.scheduler_file, timeout="30s")
            return client, None, f"the cluster of {opts.scheduler_file} ({client.scheduler.address})"
        if address:
            return distributed.Client(address, timeout="30s"), None, f"the cluster at {address}"
    except (OSError, TimeoutError, ValueError) as err:
        where = opts.scheduler_file or address
        raise EngineError(f"cannot reach the Dask scheduler at {where}: {err}") from None
    n = opts.workers or default_workers()
    import dask

    try:
        # Dask starts workers with MALLOC_TRIM_THRESHOLD_=65536, which turns off glibc's adaptive
        # mmap threshold: every large numpy temporary is then mapped and faulted in afresh, and a
        # case runs 1.7x slower (example 4 at 5 levels: 2.7 -> 4.5 s). Our workers keep the default.
        # The workers' statistical profiler (a stack walk every 10 ms, for the dashboard) and the
        # system monitor's 0.5 s polls are off / slowed: a sweep's tasks are long and nobody
        # watches their profile
        method = "forkserver" if start_fork_server() else "spawn"
        with dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None,
                              "distributed.worker.multiprocessing-method": method,
                              "distributed.worker.profile.enabled": False,
                              "distributed.admin.system-monitor.interval": "5s"}):
            cluster = distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                               memory_limit=opts.memory_limit or "auto",
                                               dashboard_address=":0", silence_logs=logging.ERROR,
                                               env={"IBFEM_THREADS": "1"})
    except (RuntimeError, OSError, ValueError) as err:
        raise EngineError(f"cannot start an embedded Dask cluster of {n} workers: {err} (a script that runs a "
                          "sweep needs the `if __name__ == \"__main__\":` guard; or use --serial)") from None
    return distributed.Client(cluster), cluster, f"an embedded cluster of {n} worker processes"


def check_workers(client, wait_s: float) -> int:
    """Wait for a worker, and refuse workers with another ibfem build; returns their number."""
    try:
        client.wait_for_workers(1, timeout=wait_s)
    except (TimeoutError, OSError):
        raise EngineError(f"no Dask worker joined the scheduler within {wait_s:g} s") from None
    mine = fingerprint()
    try:
        theirs = client.run(fingerprint)
    except Exception as err:  # noqa: BLE001 - e.g. ModuleNotFoundError on a worker without ibfem
        raise EngineError(f"the Dask workers cannot run ibfem ({type(err).__name__}: {err}); install "
                          f"ibfem {mine.split('+')[0]} with its sweep extra on them") from None
    version = mine.split("+")[0]
    other = {w: v for w, v in theirs.items() if v.split("+")[0] != version}
    if other:
        listed = ", ".join(f"{w} has {v}" for w, v in sorted(other.items()))
        raise EngineError(f"workers run another ibfem version than this driver ({mine}): {listed}")
    trimmed = {v for v in client.run(os.environ.get, "MALLOC_TRIM_THRESHOLD_").values() if v}
    if trimmed:
        warn(f"the workers run with MALLOC_TRIM_THRESHOLD_={min(trimmed)} (Dask's default): cases run up to 1.7x "
             "slower; see docs/sweeps.md (distributed.nanny.pre-spawn-environ)")
    edited = sorted(w for w, v in theirs.items() if v != mine)
    if edited:
        warn(f"the ibfem sources of {len(edited)} workers differ from this driver's ({mine}; e.g. {edited[0]} has "
             f"{theirs[edited[0]]}): edited since, or another build of version {version}")
    return len(theirs)


def _failure(payload: dict, err: BaseException) -> dict[str, Any]:
    name = type(err).__name__
    if name == "KilledWorker":
        return {"hash": payload["hash"], "status": "killed",
                "message": "the workers running this case died (each time it was given to one)"}
    text = str(err).strip().splitlines()
    return {"hash": payload["hash"], "status": "error", "message": f"{name}: {text[0] if text else ''}".rstrip(": ")}


class DaskSession:
    """A connection to a Dask cluster (embedded or existing), opened in a background thread so
    that the workers start and warm up (imports, a tiny solve) while the driver prepares the
    cases; :meth:`run` waits for it."""

    def __init__(self, opts: EngineOptions, warm: bool = True):
        import_dask()
        self.opts, self.warm = opts, warm
        self.client = self.cluster = None
        self.description, self.workers = "", 0
        self.error: BaseException | None = None
        self.closing: threading.Thread | None = None
        self.thread = threading.Thread(target=self._open, name="ibfem-sweep-connect", daemon=True)
        self.thread.start()

    def _open(self) -> None:
        try:
            self.client, self.cluster, self.description = _connect(self.opts)
            self.workers = check_workers(self.client, self.opts.wait_workers_s)
            if self.warm and self.cluster is not None:
                from .worker import warm_up

                self.client.run(warm_up)
        except BaseException as err:  # noqa: BLE001 - raised again in the driver's thread by ready()
            self.error = err

    def ready(self) -> None:
        self.thread.join()
        if self.error is not None:
            raise self.error

    def run(self, payloads: list[dict], on_result: Callable[[dict], None], runner: Callable = run_case) -> str:
        """Submit every case, hand each result to ``on_result`` as it arrives (in this process)."""
        from distributed import as_completed

        self.ready()
        token = secrets.token_hex(4)
        futures, by_key = [], {}
        try:
            for p in payloads:
                fut = self.client.submit(runner, p, key=f"ibfem-case-{p['hash']}-{token}", retries=0)
                by_key[fut.key] = p
                futures.append(fut)
            for fut in as_completed(futures):
                try:
                    result = fut.result()
                except Exception as err:  # noqa: BLE001 - KilledWorker, a worker that cannot unpickle, ...
                    result = _failure(by_key[fut.key], err)
                fut.release()
                on_result(result)
        finally:
            for fut in futures:
                if not fut.done():
                    fut.cancel()
        return self.description

    def close(self) -> None:
        """Close (or finish closing, when :meth:`close_in_background` started it)."""
        self.close_in_background()
        self.closing.join()

    def close_in_background(self) -> None:
        """Start closing (workers stopped, the embedded cluster shut down: about half a second)
        while the driver writes its table and plots; :meth:`close` waits for it."""
        self.thread.join()
        if self.closing is None:
            self.closing = threading.Thread(target=self._close, name="ibfem-sweep-close", daemon=True)
            self.closing.start()

    def _close(self) -> None:
        if self.client is not None:
            self.client.close()
        if self.cluster is not None:
            self.cluster.close()
