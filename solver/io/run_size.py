"""The size ``ibfem run --check`` prints: the cells, dofs and peak memory of the grid the run will
build (solver.model.estimate), before the run.

For most scenes that grid follows from the scene alone. Two kinds of 3D contact are solved twice,
their second pass sized by what a coarse pass finds, which depends on the load and both bodies'
compliance: only a solve knows it. For such a scene the check solves the same coarse pass (the
contact refinement two levels shallower: a grid of a few thousand dofs about the contact, a
fraction of the run) and estimates the second pass; the peak memory is the larger of the two
passes'.

- A line contact whose bodies refine around the contact (solver.contact.follow): the fine pass
  refines a band along the coarse region to the scene's level, instead of the scene's whole
  contact ball; the check estimates the band's grid.
- A large point contact (solver.contact.sizing: a candidate disc of MIN_CONTACT_DOFS contact dofs
  per body or more): the fine pass builds the scene's grid but condenses the solve on a
  candidate disc shrunk about the coarse region; the check estimates the dense arrays of that
  disc. Should the fine region reach the smaller disc's edge, the run solves the scene's disc
  once more, which the check cannot foresee (its note says which disc it counted)."""

from __future__ import annotations

from typing import Callable

import numpy as np

from ibfem.solver.model.estimate import POINT_REGION_FILL, REGION_FILL, ProblemSize, estimate_size, loaded_scene_bytes
from ibfem.solver.model.problem import Problem

__all__ = ["run_size"]


def run_size(problem: Problem, solve: Callable | None = None) -> tuple[ProblemSize, str | None]:
    """(the estimated size of the grids the run builds, a note saying how it was found or None).
    ``solve``: the solver (solver.solving.solve), called for the coarse passes of 3D line
    contacts and large 3D point contacts."""
    from ibfem.solver.contact.follow import line_contacts
    from ibfem.solver.contact.sizing import sized_contacts

    points, lines = sized_contacts(problem), line_contacts(problem)
    # what the loaded scene holds (a CAD kernel), measured before a coarse pass grows the process
    loaded = loaded_scene_bytes()
    if not points and not lines:
        return estimate_size(problem, loaded, region_fills=region_fills(problem)), None
    if solve is None:
        from ibfem.solver.solving import solve
    notes, floor = [], 0.0
    if points:
        problem, floor, note = _sized_point_contacts(problem, points, solve, loaded)
        notes.append(note)
    if lines:
        size, note = _line_contacts(problem, lines, solve, loaded)
        notes.append(note)
    else:
        size = estimate_size(problem, loaded, region_fills=region_fills(problem))
    return _at_least(size, floor), "; ".join(notes)


def region_fills(problem: Problem) -> list[float] | None:
    """Per contact of a 3D problem, the share of its candidate disc its region is taken to cover
    before a solve has found it: POINT_REGION_FILL for a point contact (the surfaces curve apart
    along both axes at the contact point: an ellipse a fraction of the disc's size), REGION_FILL
    for a line contact or a flat punch (the region grows along the disc). None in 2D."""
    if problem.dim != 3 or not problem.contacts:
        return None
    from ibfem.solver.contact.ellipse import is_flat_contact, is_line_contact
    from ibfem.solver.contact.ellipse_geometry import contact_frame_3d
    from ibfem.solver.contact.follow import finest_contact_cell

    fills = []
    for c in problem.contacts:
        fill = REGION_FILL
        if c.point is not None and len(c.bodies) == 2:
            first, second = (problem.body(n).profile for n in c.bodies)
            h = finest_contact_cell(problem, c.bodies)
            try:
                frame = contact_frame_3d(first, second, np.asarray(c.point, dtype=float), h)
            except (ValueError, FloatingPointError):  # the run reports a contact it cannot set up
                frame = None
            extent = problem.candidate_extent(c, c.options.extent_fraction)
            if frame is not None and min(frame.curvatures) > 0.0 and not is_line_contact(frame) \
                    and not is_flat_contact(frame, extent):
                fill = POINT_REGION_FILL
        fills.append(fill)
    return fills


def _sized_point_contacts(problem: Problem, points: list[int], solve: Callable,
                          loaded: float) -> tuple[Problem, float, str]:
    """(the problem with the candidate discs the run's fine pass condenses on, the coarse pass's
    estimated memory, a note)."""
    from ibfem.solver.contact.sizing import coarse_pass_problem, sized_problem

    coarse = coarse_pass_problem(problem, points)
    floor = estimate_size(coarse, loaded).memory
    try:
        coarse_solution = solve(coarse)
    except ValueError as err:  # the run reports it in its own words; the scene's disc is the bound
        return problem, floor, f"the point contact's coarse pass failed ({err}): the scene's candidate disc counted"
    fine, record = sized_problem(problem, points, coarse_solution)
    sized = [v for v in record.values() if v is not None]
    if not sized:
        return problem, floor, "the point contact's coarse pass found no elliptical region: the scene's candidate disc"
    extents = ", ".join(f"{v['extent']:.3g} m of the scene's {v['scene_extent']:.3g} m" for v in sized)
    return fine, floor, (f"point contact: its coarse pass solved ({_dofs(coarse_solution):.3g} dofs), the "
                         f"candidate disc sized about its region (radius {extents})")


def _line_contacts(problem: Problem, lines: list[int], solve: Callable, loaded: float) -> tuple[ProblemSize, str]:
    """The size of the fine pass of the line contacts ``lines`` (the band along the coarse
    region, solver.contact.follow), its memory at least the coarse passes', and a note. The
    coarse pass is the run's own: repeated one level finer while its region is unresolved."""
    from ibfem.solver.contact.follow import band_problem, coarse_pass, coarse_problem, has_region

    coarse_sizes = []

    def sized_solve(p):
        coarse_sizes.append(estimate_size(p, loaded).memory)
        return solve(p)

    try:
        coarse_solution, fewer, _ = coarse_pass(problem, lines, sized_solve)
    except ValueError as err:  # the run reports it in its own words; the scene's grid is the bound
        floor = max(coarse_sizes) if coarse_sizes else estimate_size(coarse_problem(problem, lines), loaded).memory
        return (_at_least(estimate_size(problem, loaded), floor),
                f"the line contact's coarse pass failed ({err}): the scene's whole contact ball counted")
    floor = max(coarse_sizes)
    if any(not has_region(coarse_solution.contacts[k]) for k in lines):
        return (_at_least(estimate_size(problem, loaded), floor),  # the run solves the scene's grid
                "the line contact's coarse pass found no region: the scene's own grid")
    fine, bands = band_problem(problem, lines, coarse_solution.contacts, fewer)
    widths = sorted({round(band["radius"], 9) for band in bands.values()})
    areas = [coarse_solution.contacts[k].get("area") if k in lines else None for k in range(len(problem.contacts))]
    return (_at_least(estimate_size(fine, loaded, areas), floor),
            f"line contact: its coarse pass solved ({_dofs(coarse_solution):.3g} dofs, {fewer} level"
            f"{'s' if fewer > 1 else ''} shallower), the band along its region (radius "
            f"{', '.join(f'{w:.3g}' for w in widths)} m) at the scene's levels")


def _at_least(size: ProblemSize, memory: float) -> ProblemSize:
    """``size`` with its peak memory at least ``memory`` (a coarse pass's, which the run also makes)."""
    return ProblemSize(size.cells, size.dofs, max(size.memory, memory))


def _dofs(solution) -> float:
    return float(sum(float(b.get("dofs") or 0) for b in getattr(solution, "body_info", {}).values()))
