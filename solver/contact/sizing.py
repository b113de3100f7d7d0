"""The candidate region of a large 3D point contact sized from a coarse pass.

A 3D contact condenses the solve on the dofs of the cells its candidate disc touches: a disc of
``extent_fraction`` (0.8) of the contact refinement radius about the contact point. The region is
not known before the solve, so the disc is sized to the refinement, and a region of half its
radius leaves three quarters of the disc's dofs outside it. Those dofs cost the factorisation
most: its dense work grows with the cube of a body's contact dofs (their root block) and its
square (the fronts whose rows reach them), its memory with their square.

For a point contact whose candidate disc would hold MIN_CONTACT_DOFS contact dofs per body or
more, the solve runs twice:

1. a coarse pass: the contact refinements COARSER_LEVELS levels shallower, the same radii, the
   final load in one step, finds the region (its semi-axes and centre);
2. the scene as written, with the candidate disc shrunk to reach beyond the coarse region (its
   largest semi-axis plus its centre's offset) by MARGIN of that reach plus MARGIN_CELLS of the
   coarse pass's finest cells (the coarse region's uncertainty), never wider than the scene's.

The answer does not depend on the disc once it holds the region (the condensation is exact on
any set of dofs that holds the contact terms): only the cost changes. Should the fine region
still reach the smaller disc's edge, the scene is solved again with its own disc. Smaller
contacts, line contacts and flat contacts (a region of general shape, which their own passes
size), and runs with load paths (whose largest region need not be the last) are solved as
written. The summary's ``iterations.candidate_region`` records the passes.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Callable

import numpy as np

from ..model.estimate import contact_dofs_per_body
from .band import CandidateRegionExceeded
from .follow import finest_contact_cell, line_contacts

__all__ = ["COARSER_LEVELS", "MARGIN", "MARGIN_CELLS", "MIN_CONTACT_DOFS", "coarse_pass_problem", "sized_contacts",
           "sized_problem", "solve_sized"]

#: levels fewer in the coarse pass's contact refinement
COARSER_LEVELS = 2
#: the fine disc reaches beyond the coarse region by this fraction of the region's reach ...
MARGIN = 0.15
#: ... and by this many of the coarse pass's finest cells
MARGIN_CELLS = 1.0
#: contact dofs per body (estimated) from which the coarse pass pays for itself: the dense work of
#: a body's contact block grows with their cube, the coarse pass's cost with the grid's dofs
MIN_CONTACT_DOFS = 5000.0


def _contact_zones(problem, contact) -> list:
    return [r for n in contact.bodies for r in problem.body(n).refinements if r.around_contact]


def sized_contacts(problem) -> list[int]:
    """The indices of the 3D point contacts whose candidate disc is sized by a coarse pass: contact
    refinement at least COARSER_LEVELS + 2 levels deep, MIN_CONTACT_DOFS contact dofs per body or
    more, not a line contact, no load paths."""
    if problem.model != "solid" or getattr(problem, "history", None) is not None:
        return []
    out = []
    for k, c in enumerate(problem.contacts):
        zones = _contact_zones(problem, c)
        if not zones or min(r.levels for r in zones) < COARSER_LEVELS + 2:
            continue
        if contact_dofs_per_body(problem, c)[1] >= MIN_CONTACT_DOFS:
            out.append(k)
    lines = set(line_contacts(problem)) if out else set()
    return [k for k in out if k not in lines]


def _with_contact_zones(problem, names, levels_fewer: int):
    def zones(body):
        return tuple(dataclasses.replace(r, levels=r.levels - levels_fewer) if r.around_contact else r
                     for r in body.refinements)

    bodies = tuple(dataclasses.replace(b, refinements=zones(b)) if b.name in names else b for b in problem.bodies)
    return dataclasses.replace(problem, bodies=bodies)


def region_reach(block: dict) -> float | None:
    """How far from the contact point an elliptical region of a contact block reaches: its largest
    semi-axis plus its centre's offset (None for a region of general shape or none)."""
    if "boundary" in block or "semi_axes" not in block:
        return None
    reach = max(float(v) for v in block["semi_axes"]) + float(np.hypot(*block.get("region_centre", (0.0, 0.0))))
    return reach if reach > 0.0 and math.isfinite(reach) else None


def coarse_pass_problem(problem, indices: list[int]):
    """The coarse pass of contacts ``indices``: their bodies' contact refinements COARSER_LEVELS
    levels shallower, the final load in one step (only the final region's size is read from it;
    the load steps of a frictional contact start each step's search where the last ended and
    change the final state only within the searches' tolerances)."""
    coarse = _with_contact_zones(problem, {n for k in indices for n in problem.contacts[k].bodies}, COARSER_LEVELS)
    return dataclasses.replace(coarse, options=dataclasses.replace(coarse.options, load_steps=1))


def sized_problem(problem, indices: list[int], coarse) -> tuple[object, dict]:
    """The problem with the candidate discs of contacts ``indices`` sized from the coarse pass's
    regions, and a record of each (None where the coarse region gives no size)."""
    contacts, record = list(problem.contacts), {}
    for k in indices:
        c = problem.contacts[k]
        reach = region_reach(coarse.contacts[k])
        if reach is None:
            record[k] = None
            continue
        cell = finest_contact_cell(_with_contact_zones(problem, c.bodies, COARSER_LEVELS), c.bodies)
        radius = min(r.radius for r in _contact_zones(problem, c))
        fraction = min(((1.0 + MARGIN) * reach + MARGIN_CELLS * cell) / radius, c.options.extent_fraction)
        contacts[k] = dataclasses.replace(c, options=dataclasses.replace(c.options, extent_fraction=fraction))
        record[k] = {"coarse_reach": reach, "extent": fraction * radius,
                     "scene_extent": c.options.extent_fraction * radius}
    return dataclasses.replace(problem, contacts=tuple(contacts)), record


def solve_sized(problem, run: Callable):
    """``run(problem)`` (a solution) once, or for large point contacts a coarse pass and the scene
    with its candidate discs sized from the coarse regions (and the scene as written should a
    region still reach its smaller disc's edge)."""
    indices = sized_contacts(problem)
    if not indices:
        return run(problem)
    coarse = run(coarse_pass_problem(problem, indices))
    fine, record = sized_problem(problem, indices, coarse)
    passes = {"coarse_pass": {"levels_fewer": COARSER_LEVELS, "converged": bool(coarse.converged),
                              "iterations": coarse.iterations["total"]},
              "contacts": {str(k): v for k, v in record.items()}}
    if all(v is None for v in record.values()):
        solution = run(problem)
        passes["reason"] = "the coarse pass found no elliptical region: the scene's candidate disc"
    else:
        try:
            solution = run(fine)
        except CandidateRegionExceeded:
            solution = run(problem)
            passes["reason"] = "the region reached the sized disc's edge: solved again with the scene's disc"
    solution.iterations["candidate_region"] = passes
    solution.timings["coarse_pass_s"] = float(coarse.timings.get("total_s", math.nan))
    return solution
