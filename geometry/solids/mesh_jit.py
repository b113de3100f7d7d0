"""Whether a CAD body's tessellation queries run compiled: :func:`mesh_kernels` gives the
kernels of :mod:`geometry.solids._mesh_kernels` (numba, the ``fast`` extra), imported on first
use, or None where numba is missing or ``IBFEM_NO_JIT`` is set (the numpy paths then)."""

from __future__ import annotations

from .._jit import compiled_module

__all__ = ["mesh_kernels"]


def mesh_kernels():
    """The compiled tessellation kernels (:mod:`geometry.solids._mesh_kernels`), or None where
    the compiled kernels are off (numba missing or ``IBFEM_NO_JIT`` set): numpy then."""
    return compiled_module(".solids._mesh_kernels")
