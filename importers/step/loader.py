"""``load_part``: a STEP / IGES file (or a cached import directory) -> ``geometry.Part``."""

from __future__ import annotations

import math
import time
from pathlib import Path

from ibfem.geometry import Part

from .errors import StepFormatError

__all__ = ["load_part", "parse_file"]


def _positive(value, name: str) -> float | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
        raise ValueError(f"{name} must be a positive number, got {value!r}")
    return float(value)


def parse_file(path: str | Path, *, tolerance: float | None = None, angular_tolerance: float | None = None) -> Part:
    """Read and mesh a STEP/IGES file (always parses; see :func:`load_part`)."""
    from .cache import file_hash
    from .part import build_part
    from .reader import read_shape
    from .tessellation import DEFAULT_ANGULAR_TOLERANCE, default_tolerance, mesh_shape

    tolerance = _positive(tolerance, "tolerance")
    angular = _positive(angular_tolerance, "angular_tolerance") or DEFAULT_ANGULAR_TOLERANCE
    path = Path(path)
    t0 = time.perf_counter()
    shape, info = read_shape(path)
    t1 = time.perf_counter()
    chord = tolerance or default_tolerance(shape)
    meshes, mesh_warnings = mesh_shape(shape, chord, angular)
    t2 = time.perf_counter()
    part = build_part(shape, path, names=info["names"], deflection=chord, meshes=meshes)
    if not part.faces:
        raise StepFormatError(f"{path}: the {info['format'].upper()} file holds no solids or faces "
                              "(only wires or points): nothing to import")
    t3 = time.perf_counter()
    part.warnings[:0] = info["warnings"] + mesh_warnings
    part.metadata.update({
        "source": {"file": str(path.resolve()), "format": info["format"], "sha256": file_hash(path),
                   "length_unit": "m (converted from the file's unit by OpenCascade)"},
        "tolerance": chord, "angular_tolerance": angular,
        "timing": {"read_s": round(t1 - t0, 4), "mesh_s": round(t2 - t1, 4), "build_s": round(t3 - t2, 4)},
    })
    return part


def load_part(path: str | Path, *, tolerance: float | None = None, angular_tolerance: float | None = None) -> Part:
    """The ``geometry.Part`` of a ``.step/.stp/.iges/.igs`` file, or of a directory written by
    ``ibfem import PART.step --out DIR`` (reparsed when its source file has changed).

    ``tolerance``: the mesher's chord tolerance in metres (default 1e-3 of the bounding-box
    diagonal); ``angular_tolerance`` in radians (default 0.25). Raises
    :class:`~importers.step.StepFormatError` (a ValueError) naming the file, and
    :class:`~importers.step.StepUnavailableError` when OCP is missing.
    """
    from .cache import file_hash, is_cache, read_cache, write_cache

    p = Path(path)
    if p.is_dir():
        if not is_cache(p):
            raise StepFormatError(f"{p}: a directory without a STEP/IGES import (part.json): give the .step/.iges "
                                  "file or the directory of 'ibfem import PART.step --out DIR'")
        part = read_cache(p)
        src = part.metadata.get("source", {})
        source = Path(src.get("file", ""))
        if tolerance is None and angular_tolerance is None and not (source.is_file()
                                                                    and file_hash(source) != src.get("sha256")):
            return part
        if not source.is_file():
            return part
        fresh = parse_file(source, tolerance=tolerance or part.metadata["tolerance"],
                           angular_tolerance=angular_tolerance or part.metadata["angular_tolerance"])
        write_cache(fresh, p)
        fresh.metadata["directory"] = str(p)
        return fresh
    return parse_file(p, tolerance=tolerance, angular_tolerance=angular_tolerance)
