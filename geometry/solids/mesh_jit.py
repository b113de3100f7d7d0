"""Whether a CAD body's tessellation queries run compiled: :func:`mesh_kernels` gives the
kernels of :mod:`geometry.solids._mesh_kernels` (numba, the ``fast`` extra), imported on first
use, or None where numba is missing or ``IBFEM_NO_JIT`` is set (the numpy paths then); and
:func:`box_gaps`, the distances of points to boxes either way."""

from __future__ import annotations

import numpy as np

from .._jit import compiled_module

__all__ = ["mesh_kernels", "box_gaps"]


def mesh_kernels():
    """The compiled tessellation kernels (:mod:`geometry.solids._mesh_kernels`), or None where
    the compiled kernels are off (numba missing or ``IBFEM_NO_JIT`` set): numpy then."""
    return compiled_module(".solids._mesh_kernels")


def box_gaps(points: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """(m, n): the distance from each of the points (n, 3) to each of the boxes [lo, hi] (m, 3),
    0 inside; the same numbers compiled or not (np.linalg.norm(p - np.clip(p, lo, hi)), which a
    search over a part's faces and edges asked box by box: a third of the signed distance's time
    on the M8 socket screw's cut cells went to these temporaries)."""
    p = np.ascontiguousarray(points, dtype=float).reshape(-1, 3)
    lo = np.ascontiguousarray(lo, dtype=float).reshape(-1, 3)
    hi = np.ascontiguousarray(hi, dtype=float).reshape(-1, 3)
    kernels = mesh_kernels()
    if kernels is None:
        return np.linalg.norm(p[None] - np.clip(p[None], lo[:, None], hi[:, None]), axis=2).reshape(len(lo), len(p))
    out = np.empty((len(lo), len(p)))
    kernels.box_gaps(p, lo, hi, out)
    return out
