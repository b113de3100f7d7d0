"""A line contact's trial regions stay within the cells prepared for the contact, and a coarse pass
whose region search ran off them is solved again one level finer.

The region of a line contact has its length A fixed (body 1's free edge along the line) and
searches its half-width B. The cells prepared for the contact are those of the candidate disc
(radius ``extent`` about the contact point) and those a quarter of the finest cell from its
points. The search's largest B is checked here against the
region's own edge, sampled independently on 20,000 rays and cut at body 1's free edges in closed
form (a roller of length 2 A, the contact point halfway: its end faces are the lines s0 = +-A):
the rectangle |s0| <= A, |s1| <= B has its corners at sqrt(A^2 + B^2), so B may not exceed
sqrt(reach^2 - A^2) (reach: the extent and that quarter cell), while B times the knots' largest radius (the former bound) reached
extent / sqrt(2), beyond it (a socket screw's head lying on a block left the prepared cells so)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from ibfem.solver.contact import follow
from ibfem.solver.contact.band import CandidateRegionExceeded
from ibfem.solver.contact.star_region import EDGE_RAYS, KNOTS, PREPARED_REACH, StarRegionContact

A, EXTENT, H = 0.0040, 0.0044, 0.0005  # the free edges' distance along the line, the disc's radius, the finest cell
ROOM = EXTENT + PREPARED_REACH * H  # the prepared cells reach this far


def _line_region(centre=(0.0, 0.0)) -> StarRegionContact:
    """A whole-turn line contact region with its first edge (the rectangle of
    configure_line_contact) and body 1's free edges, the end faces s0 = +-A, on the rays of
    free_edge_distance as far as the prepared cells reach; only what the size's bound reads is set."""
    c = object.__new__(StarRegionContact)
    knots = np.linspace(0.0, 2.0 * math.pi, KNOTS, endpoint=False)
    sin, cos = np.abs(np.sin(knots)), np.abs(np.cos(knots))
    psi = np.linspace(0.0, 2.0 * math.pi, EDGE_RAYS, endpoint=False)
    with np.errstate(divide="ignore"):
        ends = np.where(np.abs(np.cos(psi)) * ROOM > A, A / np.abs(np.cos(psi)), math.inf)
    c.__dict__.update(knots=knots, log_rho=np.log(np.minimum(1.0 / np.maximum(sin, 1e-12), 1.15 / np.maximum(cos, 1e-12))),
                      length=A, isotropic=False, extent=EXTENT, h=H, centre=np.asarray(centre, float),
                      ranges=[(0.0, 2.0 * math.pi)], _prepared_edges=(psi, ends), _spline=None)
    return c


def _farthest(c: StarRegionContact, b: float) -> float:
    """The farthest point from the contact point of the region of half-width b: its edge on
    20,000 rays from its centre, each cut at the end faces |s0| = A."""
    phi = np.linspace(0.0, 2.0 * math.pi, 20000, endpoint=False)
    edge = c.centre + c.rho(phi)[:, None] * np.stack([A * np.cos(phi), b * np.sin(phi)], axis=1)
    along = edge - c.centre
    cut = np.minimum(1.0, np.abs(A - np.sign(along[:, 0]) * c.centre[0]) / np.maximum(np.abs(along[:, 0]), 1e-300))
    return float(np.hypot(*(c.centre + cut[:, None] * along).T).max())


def test_a_line_contacts_largest_trial_stays_within_the_candidate_disc():
    c = _line_region()
    b = c.largest_size()
    former = EXTENT / float(np.exp(c.log_rho.max()))  # B rho <= extent only
    assert _farthest(c, former) > 1.1 * ROOM  # the former bound left the prepared cells
    assert _farthest(c, b) <= ROOM * (1.0 + 2e-3)  # the rays' sampling (0.5 degree) only
    assert _farthest(c, 1.02 * b) > ROOM  # and it is the largest
    assert b == pytest.approx(math.sqrt(ROOM**2 - A**2), rel=2e-2)  # the rectangle's corners


def test_the_bound_takes_the_regions_centre_off_the_contact_point():
    c = _line_region(centre=(0.0, 0.0003))
    b = c.largest_size()
    assert _farthest(c, b) <= ROOM * (1.0 + 2e-3)
    assert b < _line_region().largest_size()


def _stand_in(cells: float):
    block = {"boundary": [[0.0, 0.0]], "cells_per_semi_axis": [10.0, cells], "semi_axes": [A, 0.0005]}
    return SimpleNamespace(converged=True, contacts=[block], iterations={"total": 1})


def test_a_coarse_pass_that_ran_off_its_cells_is_solved_one_level_finer(monkeypatch):
    levels = []
    monkeypatch.setattr(follow, "coarse_problem", lambda p, lines, fewer=2: levels.append(fewer) or p)

    def run(problem):
        if len(levels) == 1:
            raise CandidateRegionExceeded(("roller", "block"), "refinement radius", "ran off the prepared cells")
        return _stand_in(2.0)

    coarse, fewer, tried = follow.coarse_pass(SimpleNamespace(), [0], run)
    assert levels == [2, 1] and fewer == 1 and coarse.converged
    assert tried[0]["converged"] is False and "ran off" in tried[0]["failed"]


def test_a_coarse_pass_at_the_last_level_or_bounded_by_a_body_still_fails(monkeypatch):
    monkeypatch.setattr(follow, "coarse_problem", lambda p, lines, fewer=2: p)

    def beyond(cause):
        def run(problem):
            raise CandidateRegionExceeded(("roller", "block"), cause, "still penetrates")
        return run

    with pytest.raises(CandidateRegionExceeded):  # fewer 2, then 1: the last level left
        follow.coarse_pass(SimpleNamespace(), [0], beyond("refinement radius"))
    with pytest.raises(CandidateRegionExceeded):  # a body's far side: no finer grid helps
        follow.coarse_pass(SimpleNamespace(), [0], beyond("far side of block"))


def test_rays_outside_the_ranges_read_the_nearest_free_edge_inside():
    """A quarter model's region has rays along its symmetry planes, whose angles may fall outside
    body 1's ranges by round-off: they take the free edge of the nearest ray inside (circularly),
    so the largest trial size is not bounded by a ray that has no edge at all."""
    from ibfem.solver.contact.star_region import _nearest_inside

    ends = np.zeros(8)
    ends[2:5] = [0.1, np.inf, 0.2]
    np.testing.assert_array_equal(_nearest_inside(ends), [0.1, 0.1, 0.1, np.inf, 0.2, 0.2, 0.2, 0.1])
    whole = np.array([0.3, 0.1, np.inf])
    np.testing.assert_array_equal(_nearest_inside(whole), whole)
