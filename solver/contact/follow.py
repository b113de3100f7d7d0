"""Refinement that follows a line contact's region: ``around = "contact"`` refines a ball about the
contact point, which for a roller must reach its free end, so its finest cells would fill a ball as
wide as the roller is long. For every 3D line contact (solver.contact.ellipse.is_line_contact at
the contact point) whose bodies refine around the contact, the solve runs twice:

1. a coarse pass: the contact refinements two levels shallower (the ball keeps its radius, so the
   candidate region still reaches the free ends) finds the region; where that region is not
   resolved (the pass did not converge, or its half-width spans fewer than MIN_COARSE_CELLS of its
   cells) and a level is left to spare, the pass is repeated one level finer;
2. the fine pass: the same ball at the coarse pass's levels, a band of balls at the scene's levels
   along the region (solver.contact.region_band: centred on the line through the contact point
   every band radius over the region's extent along it, of radius the region's half-width plus a
   margin of one coarse cell), and balls one level finer about the region's smooth edge where it
   turns away from the line (its half-width changes fastest: a crowned roller's ends) and about
   the coarse pass's pressure peak next to them (PEAK_BALLS), and thinner balls one level finer
   along the rest of the smooth edge (the straight sides) where the band's cells resolve the
   half-width with fewer than SIDE_MIN_CELLS.

Point contacts (ellipses) are solved as the scene says where their ball fits the region. An
elongated ellipse (the smaller relative curvature at most ELONGATED_ELLIPSE_RATIO of the larger:
Hertz's b / a below about 0.22, a ball in a bearing race's groove, a thin rod across a thick one)
takes the same two passes: its ball would need the short semi-axis's cells over the long one's
radius. The fine pass's band runs along the coarse ellipse's long axis through its centre, of
radius its short semi-axis plus the margin (region_band.ellipse_band_balls).
"""

from __future__ import annotations

import dataclasses
from typing import Callable

import numpy as np

from ..model.problem import MAX_REFINEMENT_LEVELS, Refinement
from .band import CandidateRegionExceeded
from .ellipse import is_line_contact
from .ellipse_geometry import ContactFrame3D, contact_frame_3d, sectors, surface_point
from .region_band import band_balls, ellipse_band_balls, peak_balls, side_balls, turning_balls
from .star_region import EDGE_WINDOW_CELLS, ELONGATED_RATIO, reaches_free_end

__all__ = ["solve_following", "line_contacts", "finest_contact_cell", "coarse_problem", "coarse_pass",
           "band_problem", "has_region", "COARSER_LEVELS", "MARGIN_CELLS", "TURNING_REACH_CELLS", "MIN_COARSE_CELLS"]

#: levels fewer in the coarse pass's contact refinement
COARSER_LEVELS = 2
#: the band's margin beyond the region's half-width, in cells of the coarse pass (its uncertainty)
MARGIN_CELLS = 1.0
#: how far beyond the coarse region's edge the balls one level finer where it turns reach (besides
#: the edge condition's window), in cells of the coarse pass: where the edge may lie. Half a cell:
#: the final regions' semi-axes lie within 0.14 of a coarse cell of the coarse pass's on the
#: crowned and tilted rollers; the ball about the end's pressure peak (PEAK_BALLS) keeps the
#: finer cells' border off the peak (without it, at half a cell, the tilted roller's end peak
#: read 6.4 % high: docs/contact-3d.md). The tilted roller's fine pass needs 3.0 GB with a whole
#: cell, 2.77 GB with half a cell and the peak's balls
TURNING_REACH_CELLS = 0.5
#: balls one level finer along the straight sides too (outside the stretches where the edge
#: turns), where the band's cells resolve the coarse region's half-width with fewer than
#: SIDE_MIN_CELLS (the plane-strain section's width is 2.8 % short on 3.6 cells per half-width,
#: 1.0 % on 7.4: docs/contact-3d.md): how far beyond the coarse edge they reach, in coarse cells,
#: and how far inside it, in the finer cells; SIDE_REACH_CELLS None: no such balls
SIDE_REACH_CELLS: float | None = 0.25
SIDE_WINDOW_CELLS = 2.0
SIDE_MIN_CELLS = 6.0
#: balls one level finer about the coarse pass's pressure peaks next to where the edge turns
#: (region_band.peak_balls), of the turning balls' radius: False leaves them out (the rule before)
PEAK_BALLS = True
#: a coarse region whose half-width spans fewer of its cells is not resolved: its edge, and so the
#: band, is not where the region is (a crowned roller on cells as wide as its half-width ended with
#: its region at the end face, not converged)
MIN_COARSE_CELLS = 1.5
#: a point contact whose smaller relative curvature is at most this share of the larger is an
#: elongated ellipse (Hertz's b / a 0.22 at 0.1, 0.10 at 0.028): its grid follows the region too
ELONGATED_ELLIPSE_RATIO = 0.1
#: an elongated ellipse's fine pass keeps its ball this many levels below the coarse pass's (the
#: band at the scene's levels holds the region; the ball's cells only carry the trials beyond it)
ELLIPSE_BALL_FEWER = 1


def finest_contact_cell(problem, names) -> float:
    """The smallest cell the bodies ``names`` refine to around their contacts (each body's element
    size halved per level of its deepest contact zone)."""
    return min(problem.body(n).element_size / 2.0 ** max([r.levels for r in problem.body(n).refinements
                                                          if r.around_contact], default=0) for n in names)


def line_contacts(problem) -> list[int]:
    """The indices of the 3D contacts that are line contacts at their point, or elongated
    contacts on a body 1 that ends along the line within the candidate region (a crowned
    roller: solver.contact.star_region.reaches_free_end), and whose bodies refine around the
    contact at least COARSER_LEVELS + 2 levels deep (the coarse pass keeps two)."""
    if problem.model != "solid":
        return []
    out = []
    for k, c in enumerate(problem.contacts):
        zones = [r for n in c.bodies for r in problem.body(n).refinements if r.around_contact]
        if not zones or min(r.levels for r in zones) < COARSER_LEVELS + 2:
            continue
        first, second = (problem.body(n).profile for n in c.bodies)
        h = finest_contact_cell(problem, c.bodies)
        frame = contact_frame_3d(first, second, np.asarray(c.point, dtype=float), h)
        if is_line_contact(frame) or _elongated(problem, c, first, frame, h) or _elongated_ellipse(frame):
            out.append(k)
    return out


def _elongated_ellipse(frame) -> bool:
    k0, k1 = (float(k) for k in frame.curvatures)
    return k1 > 0.0 and 0.0 < k0 <= ELONGATED_ELLIPSE_RATIO * k1


def has_region(block: dict) -> bool:
    """Whether a coarse pass's contact block found a region: a line contact's boundary, or an
    ellipse's semi-axes."""
    return bool(block.get("boundary")) or ("boundary" not in block and (block.get("semi_axes") or [0.0])[0] > 0.0)


def _elongated(problem, contact, solid1, frame, h: float) -> bool:
    """An elongated contact (reaches_free_end) on the candidate region the contact will use."""
    k0, k1 = (float(k) for k in frame.curvatures)
    if not (k1 > 0.0 and 0.0 < k0 <= ELONGATED_RATIO * k1):
        return False
    extent = problem.candidate_extent(contact, contact.options.extent_fraction)
    ranges = sectors(solid1, frame, 0.5 * h, 0.5 * extent)
    return reaches_free_end(solid1, frame, ranges, 0.5 * extent, extent, h)


def _with_zones(problem, names, zones_of: Callable) -> object:
    bodies = tuple(dataclasses.replace(b, refinements=tuple(zones_of(b))) if b.name in names else b
                   for b in problem.bodies)
    return dataclasses.replace(problem, bodies=bodies)


def coarse_problem(problem, indices: list[int], levels_fewer: int = COARSER_LEVELS):
    """The problem with the line contacts' refinements ``levels_fewer`` shallower."""
    names = {n for k in indices for n in problem.contacts[k].bodies}

    def zones(body):
        return [dataclasses.replace(r, levels=r.levels - levels_fewer) if r.around_contact else r
                for r in body.refinements]

    return _with_zones(problem, names, zones)


def band_problem(problem, indices: list[int], blocks: list[dict], levels_fewer: int = COARSER_LEVELS):
    """The problem with a band of refinement balls along each line contact's coarse region
    (``blocks``: the coarse pass's contact blocks, solved ``levels_fewer`` levels shallower) at the
    scene's levels and balls one level finer where the region's edge turns
    (solver.contact.region_band), the contact balls at the coarse levels; and a record of both."""
    bands, ellipse_only = {}, {}
    for k in indices:
        c, block = problem.contacts[k], blocks[k]
        for name in c.bodies:
            ellipse_only[name] = ellipse_only.get(name, True) and "boundary" not in block
        margin = MARGIN_CELLS * finest_contact_cell(coarse_problem(problem, [k], levels_fewer), c.bodies)
        point, axis = np.asarray(block["point"], float), np.asarray(block["axes"], float)[0]
        if "boundary" not in block:  # an elongated ellipse: the band alone, on body 1's surface
            centres, radius = _on_surface(problem.body(c.bodies[0]).profile, block,
                                          *ellipse_band_balls(block, margin))
            for name in c.bodies:
                bands.setdefault(name, []).append((centres, radius, []))
            continue
        along, radius = band_balls(block, margin)
        axes = np.asarray(block["axes"], float)[:2]
        cell = finest_contact_cell(problem, c.bodies)
        fine = 0.5 * cell  # the cells one level finer
        window = EDGE_WINDOW_CELLS * fine
        reach = TURNING_REACH_CELLS * margin / MARGIN_CELLS
        turning = turning_balls(block, margin, window, reach)
        finer = [(point + s @ axes, r) for s, r in turning]
        if PEAK_BALLS and turning:
            peaks = peak_balls(block, margin, reach + window)
            if len(peaks):
                finer.append((point + peaks @ axes, reach + window))
        if SIDE_REACH_CELLS is not None and radius - margin < SIDE_MIN_CELLS * cell:
            s, r = side_balls(block, margin, SIDE_REACH_CELLS * margin / MARGIN_CELLS + SIDE_WINDOW_CELLS * fine)
            if len(s):
                finer.append((point + s @ axes, r))
        for name in c.bodies:
            bands.setdefault(name, []).append((point + along[:, None] * axis, radius, finer))
    record = {}

    def zones(body):
        levels = max(r.levels for r in body.refinements if r.around_contact)
        # a body whose followed contacts are all ellipses: the band holds the region, the ball only
        # its trials' candidate disc, ELLIPSE_BALL_FEWER levels below the coarse pass's
        fewer = levels_fewer + (ELLIPSE_BALL_FEWER if ellipse_only[body.name] else 0)
        out = [dataclasses.replace(r, levels=max(r.levels - fewer, 0)) if r.around_contact else r
               for r in body.refinements]
        for centres, radius, finer in bands[body.name]:
            out += [Refinement(levels=levels, radius=radius, center=x) for x in centres]
            out += [Refinement(levels=min(levels + 1, MAX_REFINEMENT_LEVELS), radius=r, center=x)
                    for xs, r in finer for x in xs]
            record[body.name] = {"levels": levels, "radius": radius, "centres": centres.tolist(),
                                 "finer": [{"levels": min(levels + 1, MAX_REFINEMENT_LEVELS), "radius": r,
                                            "centres": xs.tolist()} for xs, r in finer]}
        return out

    return _with_zones(problem, set(bands), zones), record


def _on_surface(solid1, block: dict, s: np.ndarray, radius: float) -> tuple[np.ndarray, float]:
    """The band's centres (tangent-plane coordinates ``s``) moved along the normal onto body 1's
    surface: an ellipse's bodies curve away from the tangent plane along its long axis (a ball in
    a race's groove by s^2 / 2R, more than the band's radius at its ends), though not from each
    other. Where the surface is not found above a centre, the plane's point."""
    frame = ContactFrame3D(point=np.asarray(block["point"], float), normal=np.asarray(block["normal"], float),
                           axes=np.asarray(block["axes"], float)[:2],
                           curvatures=np.asarray(block["relative_curvatures"], float))
    plane = frame.point + s @ frame.axes
    reach = 2.0 * float(np.abs(s).max()) + radius
    x1, found = surface_point(solid1, frame, s, reach)
    return np.where(found[:, None], x1, plane), radius


def coarse_pass(problem, lines: list[int], run: Callable):
    """(the coarse pass's solution, the levels it was solved shallower, a record of the passes
    tried): COARSER_LEVELS shallower, or one level finer at a time while its region is not
    resolved (not converged, no region, fewer than MIN_COARSE_CELLS across its half-width, or its
    region search ran off the candidate region, as a search on a region about a cell wide can) and
    the pass stays at least a level shallower than the scene."""
    fewer = COARSER_LEVELS
    tried = []
    while True:
        try:
            coarse = run(coarse_problem(problem, lines, fewer))
        except CandidateRegionExceeded as err:  # the search lost a region its cells do not resolve
            if err.cause != "refinement radius" or fewer <= 1:
                raise
            tried.append({"levels_fewer": fewer, "converged": False, "failed": str(err)})
            fewer -= 1
            continue
        blocks = [coarse.contacts[k] for k in lines]
        resolved = bool(coarse.converged) and all(
            has_region(b) and (b.get("cells_per_semi_axis") or [0.0, 0.0])[1] >= MIN_COARSE_CELLS for b in blocks)
        tried.append({"levels_fewer": fewer, "converged": bool(coarse.converged),
                      "cells_per_semi_axis": [b.get("cells_per_semi_axis") for b in blocks]})
        if resolved or fewer <= 1:
            return coarse, fewer, tried
        fewer -= 1


def solve_following(problem, run: Callable):
    """``run(problem)`` (a solution) once, or for line contacts twice: the coarse pass, then the
    band about its regions (summary.json: ``iterations.refinement``). Where the coarse pass finds
    no region (a contact below its grid's resolution) the scene's own grid is solved."""
    lines = line_contacts(problem)
    if not lines:
        return run(problem)
    coarse, fewer, tried = coarse_pass(problem, lines, run)
    if any(not has_region(coarse.contacts[k]) for k in lines):
        solution = run(problem)
        solution.iterations["refinement"] = {"band": None, "reason": "the coarse pass found no region"}
        return solution
    fine, bands = band_problem(problem, lines, coarse.contacts, fewer)
    solution = run(fine)
    solution.iterations["refinement"] = {
        "coarse_pass": {"levels_fewer": fewer, "converged": bool(coarse.converged),
                        "iterations": coarse.iterations["total"],
                        "semi_axes": [coarse.contacts[k]["semi_axes"] for k in lines], "tried": tried},
        "band": bands}
    return solution
