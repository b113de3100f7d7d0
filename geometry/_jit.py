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

