"""Compiled per-point kernels of B-spline projection (optional: numba, the ``fast`` extra).

The projection of :mod:`geometry.bspline` runs a branch and bound over Bezier cells with a
Newton solve per candidate cell. Vectorised with numpy it is bound by memory traffic:
every step gathers per-pair table rows and makes array temporaries (measured on the
2-core benchmark machine: ~1 ns per element and 3-8 ns per gathered element). These
kernels run the same algorithm point by point in compiled loops (one core, no threads),
with the bound tightened as soon as a cell gives a closer point. Without numba (or with
``IBFEM_NO_JIT=1`` in the environment) :mod:`geometry.bspline` uses its numpy path; the
two are tested against each other.

The kernels live in :mod:`geometry._kernels` (module level, so numba's on-disk cache keeps
them compiled between processes); this module decides whether they are used and imports
them (and numba) on the first B-spline projection only.

Tables (built once per spline in :mod:`geometry.bspline`):

* ``nodes`` (n_nodes, 21): per node of the box hierarchy (all levels, top first) its
  frame rows R (9), frame centre ``R origin + box centre`` (3), half widths (3), and for
  leaf cells the box of a tangent field's numerator in the same frame (lo 3, hi 3);
  ``level_start`` (levels + 1,): the first node of each level; node i of level l has the
  children ``level_start[l + 1] + branch i + c``; padding nodes have half widths -1e150;
* curves: ``coef`` (n_cells, (k + 1) D) Taylor coefficients of each cell's piece about
  its middle (row i D + d: coefficient of x^i of homogeneous component d), ``mids``,
  ``edges`` (n_cells + 1), ``ends`` (n_cells, 6): the cell's first and last point.
"""

from __future__ import annotations

import os
from typing import Any

_KERNELS: Any = None


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

