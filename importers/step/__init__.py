"""STEP and IGES import: ``load_part(path) -> geometry.Part`` with every face's
exact surface and orientation, every edge's exact curve, the loops and a tessellation, lengths
in metres; ``profile_from_shape`` builds the 2D profile of a ``{type = "step", ...}`` scene shape.

OpenCascade's Python bindings (OCP, the ``step`` extra: ``pip install 'ibfem[step]'``) are
imported only when a file is read; a cached import (``write_cache``) is read without them.

Modules: ``reader`` (file -> shape in metres, errors naming the file and entity), ``surfaces``
and ``curves`` (OpenCascade geometry -> geometry dicts), ``tessellation`` (the mesher),
``part`` (shape -> Part), ``cache`` (Part <-> directory), ``profile`` (scene shapes).
"""

from __future__ import annotations

from .errors import StepFormatError, StepUnavailableError
from .loader import load_part, parse_file

__all__ = ["load_part", "parse_file", "profile_from_shape", "write_cache", "StepFormatError",
           "StepUnavailableError"]


def profile_from_shape(shape: dict, where: str = "shape"):
    """The 2D profile of a ``step`` scene shape (see :mod:`importers.step.profile`)."""
    from .profile import profile_from_shape as build

    return build(shape, where=where)


def write_cache(part, directory):
    """Write a Part read from a STEP/IGES file into ``directory`` (see :mod:`importers.step.cache`)."""
    from .cache import write_cache as write

    return write(part, directory)
