"""Acceptance of ``ibfem verify`` on a STEP/IGES part: analytic faces at round-off
(the command's absolute tolerance), free-form faces (B-spline, NURBS of revolution, sweeps of
B-splines) whose projection is iterative below 1e-9 of the part's size."""

from __future__ import annotations

import numpy as np

__all__ = ["position_tolerances", "FREEFORM_TYPES", "RELATIVE_TOLERANCE"]

FREEFORM_TYPES = ("BSURFACE", "SPUN", "SWEEP")
RELATIVE_TOLERANCE = 1e-9


def part_size(part) -> float:
    """Diagonal (m) of the box around every face's tessellation."""
    pts = [np.asarray(f.mesh.vertices, float) for f in part.faces.values() if f.mesh is not None and len(f.mesh.vertices)]
    if not pts:
        return 0.0
    allv = np.concatenate(pts)
    return float(np.linalg.norm(allv.max(axis=0) - allv.min(axis=0)))


def position_tolerances(part, absolute: float) -> dict[str, float]:
    """{surface type: largest accepted position error (m)} for the free-form types."""
    rel = RELATIVE_TOLERANCE * part_size(part)
    return {t: max(absolute, rel) for t in FREEFORM_TYPES}
