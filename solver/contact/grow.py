"""Refinement that follows a growing 2D contact region. An ``around = "contact"`` refinement is a
disk about the contact point, and the candidate region reaches ``extent_fraction`` of its radius:
a region that grows beyond it (a conformal pin under a larger load, a punch pressed deeper) used
to be refused with "enlarge the refinement radius". Instead, when a plane contact's region runs
off a candidate region bounded by the refinement radius, the solve

1. runs coarse passes: that contact's refinement disks GROWTH times wider and COARSER_LEVELS
   levels shallower (about the same number of cells), widened again while the region still
   runs off them (at most MAX_COARSE_PASSES times);
2. solves the scene again with the disks at the scene's levels, all scaled by one factor so that
   the candidate region reaches beyond the region found on the coarse pass by MARGIN of its
   reach plus MARGIN_CELLS of its cells.

A region that runs off a candidate region bounded by anything else (a body's far side: the
bodies are too small for the load) is refused as before, with its cause; so is one that still
runs off after the last coarse pass. The summary's ``iterations.refinement`` records the passes.
"""

from __future__ import annotations

import dataclasses
from typing import Callable

import numpy as np

from .band import CandidateRegionExceeded

__all__ = ["GROWTH", "COARSER_LEVELS", "MAX_COARSE_PASSES", "MARGIN", "MARGIN_CELLS", "solve_growing"]

#: the coarse passes' disks are this many times wider than the previous pass's
GROWTH = 2.0
#: the coarse passes' disks are this many levels shallower than the scene's
COARSER_LEVELS = 2
#: coarse passes at most (the disks up to GROWTH^MAX_COARSE_PASSES times the scene's radius)
MAX_COARSE_PASSES = 4
#: the fine pass's candidate region reaches beyond the coarse region by this fraction of its reach
MARGIN = 0.1
#: ... and by this many of the coarse pass's finest cells (its region's uncertainty)
MARGIN_CELLS = 2.0

GROWABLE = "refinement radius"


def _contact_index(problem, bodies, point=None) -> int:
    """The contact of ``bodies`` (of several, the one whose point is nearest ``point``)."""
    ks = [k for k, c in enumerate(problem.contacts) if tuple(c.bodies) == tuple(bodies)]
    if not ks:
        raise LookupError(f"no contact between {bodies}")
    if point is None or len(ks) == 1:
        return ks[0]
    return min(ks, key=lambda k: float(np.linalg.norm(np.asarray(problem.contacts[k].point, float) - point)))


def _scaled(problem, names, factor: float, levels_fewer: int):
    """The problem with the ``around = "contact"`` disks of the bodies ``names`` ``factor`` times
    wider and ``levels_fewer`` levels shallower (at least 0)."""
    def zones(body):
        return tuple(dataclasses.replace(r, radius=r.radius * factor, levels=max(r.levels - levels_fewer, 0))
                     if r.around_contact else r for r in body.refinements)

    bodies = tuple(dataclasses.replace(b, refinements=zones(b)) if b.name in names else b for b in problem.bodies)
    return dataclasses.replace(problem, bodies=bodies)


def _finest(problem, names) -> tuple[float, float]:
    """The smallest ``around = "contact"`` radius of the bodies ``names`` and the finest cell
    their refinement makes."""
    radius = min(r.radius for n in names for r in problem.body(n).refinements if r.around_contact)
    cell = min(problem.body(n).element_size / 2.0 ** max([r.levels for r in problem.body(n).refinements
                                                          if r.around_contact], default=0) for n in names)
    return radius, cell


def _coarse_passes(problem, run: Callable, k: int, names):
    """The coarse passes of contact ``k``: (its solution, the radius factor, the passes' record)."""
    factor, record = 1.0, []
    for _ in range(MAX_COARSE_PASSES):
        factor *= GROWTH
        try:
            coarse = run(_scaled(problem, names, factor, COARSER_LEVELS))
        except CandidateRegionExceeded as err:
            if err.cause != GROWABLE:
                raise
            record.append({"radius_factor": factor, "levels_fewer": COARSER_LEVELS, "region": None})
            last = err
            continue
        record.append({"radius_factor": factor, "levels_fewer": COARSER_LEVELS,
                       "region": coarse.contacts[k]["region"], "converged": bool(coarse.converged)})
        return coarse, factor, record
    raise CandidateRegionExceeded(last.bodies, last.cause, (
        f"{last} (still after widening the contact refinement {factor:g} times on a coarse pass)"), point=last.point)


def solve_growing(problem, run: Callable):
    """``run(problem)`` (a solution); for a plane contact whose region runs off a candidate region
    bounded by the refinement radius, the coarse passes and the fine pass about their region."""
    try:
        return run(problem)
    except CandidateRegionExceeded as err:
        if err.cause != GROWABLE or problem.model == "solid":
            raise
        bodies, point = err.bodies, err.point
    k = _contact_index(problem, bodies, point)
    coarse, factor, record = _coarse_passes(problem, run, k, bodies)
    radius, _ = _finest(problem, bodies)
    _, coarse_cell = _finest(_scaled(problem, bodies, factor, COARSER_LEVELS), bodies)
    reach = max(abs(v) for v in coarse.contacts[k]["region"])
    needed = (reach * (1.0 + MARGIN) + MARGIN_CELLS * coarse_cell) / problem.contacts[k].options.extent_fraction
    fine_factor = max(needed / radius, 1.0)
    solution = run(_scaled(problem, bodies, fine_factor, 0))
    solution.iterations["refinement"] = {
        "reason": "the contact region ran off the refinement radius's candidate region",
        "coarse_passes": record, "radius_factor": fine_factor}
    return solution
