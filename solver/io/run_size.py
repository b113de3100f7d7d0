"""The size ``ibfem run --check`` prints: the cells, dofs and peak memory of the grid the run will
build (solver.model.estimate), before the run.

For most scenes that grid follows from the scene alone. A 3D line contact whose bodies refine
around the contact is solved twice (solver.contact.follow): a coarse pass finds the region, and
the fine pass refines a band along it to the scene's level, instead of the scene's whole contact
ball. The band's width is the contact's half-width, which depends on the load and both bodies'
compliance: only a solve knows it. For such a scene the check solves the same coarse pass (a
grid two levels shallower about the contact: a few seconds, a fraction of the run) and estimates
the fine pass's grid, band included; the peak memory is the larger of the two passes'."""

from __future__ import annotations

from typing import Callable

from ibfem.solver.model.estimate import ProblemSize, estimate_size
from ibfem.solver.model.problem import Problem

__all__ = ["run_size"]


def run_size(problem: Problem, solve: Callable | None = None) -> tuple[ProblemSize, str | None]:
    """(the estimated size of the grids the run builds, a note saying how it was found or None).
    ``solve``: the solver (solver.solving.solve), called for the coarse pass of 3D line
    contacts."""
    from ibfem.solver.contact.follow import band_problem, coarse_problem, line_contacts

    lines = line_contacts(problem)
    if not lines:
        return estimate_size(problem), None
    if solve is None:
        from ibfem.solver.solving import solve
    coarse = coarse_problem(problem, lines)
    coarse_size = estimate_size(coarse)
    try:
        coarse_solution = solve(coarse)
    except ValueError as err:  # the run reports it in its own words; the scene's grid is the bound
        size = estimate_size(problem)
        return (ProblemSize(size.cells, size.dofs, max(size.memory, coarse_size.memory)),
                f"the line contact's coarse pass failed ({err}): the scene's whole contact ball counted")
    if any(not coarse_solution.contacts[k].get("boundary") for k in lines):
        size = estimate_size(problem)  # the run then solves the scene's own grid
        return (ProblemSize(size.cells, size.dofs, max(size.memory, coarse_size.memory)),
                "the line contact's coarse pass found no region: the scene's own grid")
    fine, bands = band_problem(problem, lines, coarse_solution.contacts)
    size = estimate_size(fine)
    widths = sorted({round(band["radius"], 9) for band in bands.values()})
    return (ProblemSize(size.cells, size.dofs, max(size.memory, coarse_size.memory)),
            f"line contact: its coarse pass solved ({_dofs(coarse_solution):.3g} dofs), the band along "
            f"its region (radius {', '.join(f'{w:.3g}' for w in widths)} m) at the scene's levels")


def _dofs(solution) -> float:
    return float(sum(float(b.get("dofs") or 0) for b in getattr(solution, "body_info", {}).values()))
