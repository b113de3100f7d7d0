"""Compiled per-point kernels of B-spline projection (optional: numba, the ``fast`` extra).

The projection of :mod:`geometry.bspline` runs a branch and bound over Bezier cells with a
Newton solve per candidate cell. Vectorised with numpy it is bound by memory traffic:
every step gathers per-pair table rows and makes array temporaries (measured on the
2-core benchmark machine: ~1 ns per element and 3-8 ns per gathered element). These
kernels run the same algorithm point by point in compiled loops (on the threads of :func:`run_ranges`),
with the bound tightened as soon as a cell gives a closer point. Without numba (or with
``IBFEM_NO_JIT=1`` in the environment) :mod:`geometry.bspline` uses its numpy path; the
two are tested against each other.

The kernels live in :mod:`geometry._kernels` (module level, so numba's on-disk cache keeps
them compiled between processes); this module decides whether they are used and imports
them (and numba) on the first B-spline projection only. The closed forms and the ellipse
have their own compiled kernel (:mod:`geometry._closed_kernels`, :func:`closed_kernel`),
imported on their first projection.

Threads: every kernel releases the GIL, and :func:`run_ranges` runs one over ranges of the
points on a pool of threads (``IBFEM_THREADS``, default: the machine's cores), each range
written into the caller's result arrays, so one call uses every core (no numba
``parallel=True``: its threading layers are not safe for calls from several threads or
after a fork, and its compilation is slower).

Tables (built once per spline in :mod:`geometry.bspline`):

* ``nodes`` (n_nodes, 15 + 6 fields): per node of the box hierarchy (all levels, top first)
  its frame rows R (9), frame centre ``R origin + box centre`` (3), half widths (3), and for
  leaf cells the boxes of the tangent fields' numerators in the same frame (lo 3, hi 3
  each: C' for curves, S_u and S_v for surfaces); ``level_start`` (levels + 1,): the first
  node of each level; node i of level l has the children ``level_start[l + 1] + branch i +
  c``; padding nodes have half widths -1e150; ``rep`` (n_nodes, 3) a point of the spline in
  every node (the middle of cell ``rep_cell``), an upper bound of the answer;
* curve cells (also the edges of surface cells, prefixed ``ue_`` along u and ``ve_``
  along v, edge 2 c + s of cell c at its lower (s = 0) or upper bound): ``coef``
  (n_cells, (k + 1) D) Taylor coefficients of each cell's piece about its middle (column
  i D + d: coefficient of x^i of homogeneous component d), ``ends`` (n_cells, 6) its first
  and last point, ``stat`` (n_cells, 4 (M + 1)) the Bernstein coefficients G0, G1x, G1y,
  G1z of a positive multiple of ``C'.(C - p) = G0 - p.G1`` over the cell, ``fnet``
  (surface edges, n_cells, 5 (2k + 1)) those of the squared distance
  (:func:`geometry._bernstein.distance_nets`); curves also ``mids`` and ``edges`` (n_cells
  + 1);
* surfaces: ``coef`` (n_cells, (ku + 1) (kv + 1) D) Taylor coefficients of each patch
  about its middle (column (a (kv + 1) + b) D + d: coefficient of x^a y^b), the grid
  ``su``, ``sv``, and ``leaf_cell``: the cell (i cv + j) of every leaf (Morton order).
"""

from __future__ import annotations

import importlib
import os
from typing import Any

_KERNELS: Any = None
_MODULES: dict[str, Any] = {}  # compiled_module's imports (None: not importable)
_POOL: Any = None
_POOL_SIZE = 0
# a range is never shorter than this many points (the cost of handing it to a thread is
# about that of projecting a few hundred points)
MIN_RANGE = 8192


def enabled() -> bool:
    """Whether the compiled kernels are used: numba importable and ``IBFEM_NO_JIT`` unset."""
    global _KERNELS
    if os.environ.get("IBFEM_NO_JIT", "") not in ("", "0"):
        return False
    if _KERNELS is None:
        try:
            from . import _kernels
        except ImportError:
            _KERNELS = False
        else:
            _KERNELS = vars(_kernels)
    return _KERNELS is not False


def kernels() -> dict[str, Any]:
    """The compiled kernels by name (``curve_project``, ``surface_project``, ...)."""
    if not enabled():
        raise RuntimeError("the compiled kernels are not available (numba missing or IBFEM_NO_JIT set)")
    return _KERNELS



def compiled_module(name: str) -> Any:
    """The module of compiled kernels ``name`` (relative to the geometry package, e.g.
    ``"._closed_kernels"``), imported on first use, or None where the compiled kernels are off
    (numba missing or ``IBFEM_NO_JIT`` set): the callers' numpy paths then."""
    if os.environ.get("IBFEM_NO_JIT", "") not in ("", "0"):
        return None
    if name not in _MODULES:
        try:
            _MODULES[name] = importlib.import_module(name, __package__)
        except ImportError:
            _MODULES[name] = None
    return _MODULES[name]


def closed_kernel() -> Any:
    """The compiled kernel of the closed forms and the ellipse (``project_range``) and its
    module, or None where the compiled kernels are off (numba missing or ``IBFEM_NO_JIT``)."""
    return compiled_module("._closed_kernels")


def threads() -> int:
    """Threads a projection runs on: ``IBFEM_THREADS`` if set (>= 1), else the cores."""
    value = os.environ.get("IBFEM_THREADS", "")
    if value:
        try:
            return max(1, int(value))
        except ValueError:
            raise ValueError(f"IBFEM_THREADS must be a whole number >= 1, got {value!r}") from None
    return os.cpu_count() or 1


def release_threads() -> None:
    """Stop the projections' thread pool, waiting for its threads to end (the next projection
    that needs it makes it again). A process that is about to fork calls this: ``fork`` copies
    the calling thread only, so a child of a process with other threads alive may inherit a lock
    one of them held."""
    global _POOL, _POOL_SIZE
    if _POOL is not None:
        _POOL.shutdown(wait=True)
        _POOL, _POOL_SIZE = None, 0


def run_ranges(fn: Any, n: int, per_thread: int = 4) -> None:
    """Calls ``fn(lo, hi)`` on ranges covering ``range(n)``: directly for few points or one
    thread, else about ``per_thread`` ranges per thread (so a thread slowed by other work on
    the machine takes fewer) on a shared pool, waiting for all; an exception in a range is
    raised here."""
    global _POOL, _POOL_SIZE
    workers = 1 if n < 2 * MIN_RANGE else threads()  # few points: not even the cores are asked
    if workers == 1:
        fn(0, n)
        return
    if _POOL is None or _POOL_SIZE != workers:
        from concurrent.futures import ThreadPoolExecutor

        _POOL = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="geometry")
        _POOL_SIZE = workers
    count = max(1, min(workers * per_thread, n // MIN_RANGE))
    edges = [n * j // count for j in range(count + 1)]
    futures = [_POOL.submit(fn, lo, hi) for lo, hi in zip(edges[:-1], edges[1:])]
    for f in futures:
        f.result()
