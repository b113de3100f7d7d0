"""Preloaded by the embedded cluster's fork server (see :func:`solver.sweep.engine.start_fork_server`):
importing this module imports Dask's worker, the solver and its kernels and solves a tiny scene
once, so that every worker process forked from the server starts with all of that done (each
worker spawned afresh paid its own imports and first calls: about 0.8 s of CPU each, on the
cores the cases run on). Nothing here may raise: the fork server would die with it."""

from __future__ import annotations

try:
    import distributed.nanny  # noqa: F401  (what the forked worker process runs)

    from .worker import warm_up

    warm_up()
except Exception:  # noqa: BLE001 - a worker that is not warm still works
    pass
