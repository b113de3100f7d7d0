"""Refinement that follows a line contact's region: ``around = "contact"`` refines a ball about the
contact point, which for a roller must reach its free end, so its finest cells would fill a ball as
wide as the roller is long. For every 3D line contact (solver.contact.ellipse.is_line_contact at
the contact point) whose bodies refine around the contact, the solve runs twice:

1. a coarse pass: the contact refinements two levels shallower (the ball keeps its radius, so the
   candidate region still reaches the free ends) finds the region;
2. the fine pass: the same ball at the coarse levels, and a band of balls at the scene's levels
   along the region: centred on the line through the contact point every band radius over the
   region's extent along it, of radius the region's half-width plus a margin of one coarse cell.

Point contacts (ellipses) are solved as the scene says: their ball already fits the region.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Callable

import numpy as np

from ..model.problem import Refinement
from .ellipse import is_line_contact
from .ellipse_geometry import contact_frame_3d

__all__ = ["solve_following", "line_contacts", "coarse_problem", "band_problem", "COARSER_LEVELS", "MARGIN_CELLS"]

#: levels fewer in the coarse pass's contact refinement
COARSER_LEVELS = 2
#: the band's margin beyond the region's half-width, in cells of the coarse pass (its uncertainty)
MARGIN_CELLS = 1.0


def _finest(problem, names) -> float:
    sizes = []
    for name in names:
        body = problem.body(name)
        levels = max([r.levels for r in body.refinements if r.around_contact], default=0)
        sizes.append(body.element_size / 2.0**levels)
    return min(sizes)


def line_contacts(problem) -> list[int]:
    """The indices of the 3D contacts that are line contacts at their point and whose bodies refine
    around the contact at least COARSER_LEVELS + 2 levels deep (the coarse pass keeps two)."""
    if problem.model != "solid":
        return []
    out = []
    for k, c in enumerate(problem.contacts):
        zones = [r for n in c.bodies for r in problem.body(n).refinements if r.around_contact]
        if not zones or min(r.levels for r in zones) < COARSER_LEVELS + 2:
            continue
        first, second = (problem.body(n).profile for n in c.bodies)
        frame = contact_frame_3d(first, second, np.asarray(c.point, dtype=float), _finest(problem, c.bodies))
        if is_line_contact(frame):
            out.append(k)
    return out


def _with_zones(problem, names, zones_of: Callable) -> object:
    bodies = tuple(dataclasses.replace(b, refinements=tuple(zones_of(b))) if b.name in names else b
                   for b in problem.bodies)
    return dataclasses.replace(problem, bodies=bodies)


def coarse_problem(problem, indices: list[int]):
    """The problem with the line contacts' refinements COARSER_LEVELS shallower."""
    names = {n for k in indices for n in problem.contacts[k].bodies}

    def zones(body):
        return [dataclasses.replace(r, levels=r.levels - COARSER_LEVELS) if r.around_contact else r
                for r in body.refinements]

    return _with_zones(problem, names, zones)


def band_problem(problem, indices: list[int], blocks: list[dict]):
    """The problem with a band of refinement balls along each line contact's coarse region
    (``blocks``: the coarse pass's contact blocks), the contact balls at the coarse levels; and
    a record of the bands."""
    bands = {}
    for k in indices:
        c, block = problem.contacts[k], blocks[k]
        h = _finest(coarse_problem(problem, [k]), c.bodies)
        point, axes = np.asarray(block["point"], float), np.asarray(block["axes"], float)
        edge = (np.asarray(block["boundary"]["points"], float) - point) @ axes.T
        radius = float(np.abs(edge[:, 1]).max()) + MARGIN_CELLS * h
        lo, hi = float(edge[:, 0].min()), float(edge[:, 0].max())
        count = max(2, int(math.ceil((hi - lo) / radius)) + 1)
        centres = point + np.linspace(lo, hi, count)[:, None] * axes[0]
        for name in c.bodies:
            bands.setdefault(name, []).append((centres, radius))
    record = {}

    def zones(body):
        levels = max(r.levels for r in body.refinements if r.around_contact)
        out = [dataclasses.replace(r, levels=r.levels - COARSER_LEVELS) if r.around_contact else r
               for r in body.refinements]
        for centres, radius in bands[body.name]:
            out += [Refinement(levels=levels, radius=radius, center=x) for x in centres]
            record[body.name] = {"levels": levels, "radius": radius, "centres": centres.tolist()}
        return out

    return _with_zones(problem, set(bands), zones), record


def solve_following(problem, run: Callable):
    """``run(problem)`` (a solution) once, or for line contacts twice: the coarse pass, then the
    band about its regions (summary.json: ``iterations.refinement``). Where the coarse pass finds
    no region (a contact below its grid's resolution) the scene's own grid is solved."""
    lines = line_contacts(problem)
    if not lines:
        return run(problem)
    coarse = run(coarse_problem(problem, lines))
    if any(not coarse.contacts[k].get("boundary") for k in lines):
        solution = run(problem)
        solution.iterations["refinement"] = {"band": None, "reason": "the coarse pass found no region"}
        return solution
    fine, bands = band_problem(problem, lines, coarse.contacts)
    solution = run(fine)
    solution.iterations["refinement"] = {
        "coarse_pass": {"levels_fewer": COARSER_LEVELS, "converged": bool(coarse.converged),
                        "iterations": coarse.iterations["total"],
                        "semi_axes": [coarse.contacts[k]["semi_axes"] for k in lines]},
        "band": bands}
    return solution
