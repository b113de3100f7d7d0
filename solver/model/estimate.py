"""Size of a problem before anything is built: cells, dofs and memory from
the bodies' boxes, element sizes and refinement zones, so ``--check`` can refuse a grid that
cannot fit in the machine and say how much it would need.

Cells: the box's area (volume in 3D) over h0^d, plus per zone and level the disc (ball) of the
level's reach over that level's cell size (the grids refine every cell of level l closer than
R_l = radius + 2 sum of the finer sizes to the centre: solver.fem.grid.refinement_radii). Dofs:
d per cell (one node per cell on a regular grid). Memory: measured per dof on this machine's
runs (2D contact 68k dofs: 495 MB; 3D linear 880k dofs: 4.5 GB; 3D contact 32k dofs: 2.2 GB),
rounded up."""

from __future__ import annotations

import math
import os

import numpy as np

__all__ = ["ProblemSize", "estimate_size", "available_memory"]

#: bytes per dof measured (rounded up): 2D, 3D without contact, 3D with contact
BYTES_PER_DOF = {2: 8_000, 3: 6_000}
BYTES_PER_DOF_3D_CONTACT = 70_000
#: the grading reach of a refinement level in cells (solver.fem.grid.GRADING_CELLS)
GRADING_CELLS = 2


class ProblemSize:
    def __init__(self, cells: float, dofs: float, memory: float):
        # nan (inf x 0 of absurd sizes) counts as beyond every machine
        self.cells, self.dofs, self.memory = (v if v == v else math.inf for v in (cells, dofs, memory))

    def __str__(self) -> str:
        return f"about {self.cells:.3g} cells, {self.dofs:.3g} dofs, {self.memory / 2**30:.2g} GB"


def _zone_cells(radius: float, levels: int, h0: float, dim: int, centre, lo, hi) -> float:
    """New cells of a refinement zone, level by level, its disc (ball) clipped to the body's box
    axis by axis."""
    h = h0 / 2.0 ** np.arange(levels + 1)
    total = 0.0
    centre = np.zeros(dim) if centre is None else np.asarray(centre, dtype=float)
    for lv in range(levels):
        reach = radius + GRADING_CELLS * h[lv + 1:].sum() + h[lv]
        measure = math.pi * reach**2 if dim == 2 else 4.0 / 3.0 * math.pi * reach**3
        overlap = np.clip(np.minimum(centre + reach, hi) - np.maximum(centre - reach, lo), 0.0, None) / (2 * reach)
        total += float(np.prod(overlap)) * measure / h[lv + 1] ** dim * (1.0 - 0.5**dim) if measure else 0.0
    return total


def estimate_size(problem) -> ProblemSize:
    """Estimated cells, dofs and peak memory of ``problem`` (a solver.model.Problem); inf for
    sizes beyond floating point (an element size of 1e-300)."""
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        return _estimate(problem)


def _estimate(problem) -> ProblemSize:
    dim = problem.dim
    cells = 0.0
    for body in problem.bodies:
        lo, hi = (np.asarray(v, dtype=float) for v in body.profile.bounds)
        h0 = float(body.element_size)
        box = float(np.prod(np.maximum(hi - lo, h0)))
        measure = float(getattr(body.profile, "volume" if dim == 3 else "area", box) or box)
        fill = min(1.0, max(measure / box, 0.05)) if math.isfinite(measure) else 1.0
        per_axis = np.maximum(hi - lo, h0) / h0  # cells along each axis (inf for absurd sizes)
        cells += fill * float(np.prod(per_axis)) + float(np.sum(per_axis + 1.0)) ** (dim - 1)  # inside + cut
        for zone in body.refinements:
            cells += _zone_cells(float(zone.radius), int(zone.levels), h0, dim, zone.center, lo, hi)
    dofs = dim * cells
    per_dof = BYTES_PER_DOF_3D_CONTACT if dim == 3 and problem.contacts else BYTES_PER_DOF[dim]
    return ProblemSize(cells, dofs, dofs * per_dof + 200e6)


def available_memory() -> float:
    """Physical memory of the machine in bytes (inf when unknown)."""
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover - not POSIX
        return math.inf
