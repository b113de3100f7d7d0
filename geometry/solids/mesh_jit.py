"""Whether a CAD body's tessellation queries run compiled: :func:`mesh_kernels` gives the
kernels of :mod:`geometry.solids._mesh_kernels` (numba, the ``fast`` extra), imported on first
use, or None where numba is missing or ``IBFEM_NO_JIT`` is set (the numpy paths then)."""

from __future__ import annotations

import os

__all__ = ["mesh_kernels"]

_MESH_KERNELS = None


def mesh_kernels():
    """The compiled tessellation kernels (:mod:`geometry.solids._mesh_kernels`), or None where
    the compiled kernels are off (numba missing or ``IBFEM_NO_JIT`` set): numpy then."""
    global _MESH_KERNELS
    if os.environ.get("IBFEM_NO_JIT", "") not in ("", "0"):
        return None
    if _MESH_KERNELS is None:
        try:
            from . import _mesh_kernels
        except ImportError:
            _MESH_KERNELS = False
        else:
            _MESH_KERNELS = _mesh_kernels
    return _MESH_KERNELS or None
