"""The size ``ibfem run --check`` prints for a large 3D point contact (solver.io.run_size): the
run solves a coarse pass and condenses its fine pass on a candidate disc shrunk about the coarse
region (solver.contact.sizing), so the check solves the same coarse pass and counts the dense
arrays of the smaller disc. Checked against the run itself: the check finds the disc the run
condenses on, its estimated contact dofs are within 30 % of those the run condenses (the
acceptance of the check's estimates), the grid is the scene's (the disc changes what is
condensed, not what is built), and the memory falls below the scene disc's estimate. A small
sphere on a flat stands in for the full models (the threshold lowered, the coarse pass one level
shallower), so the test solves in seconds."""

import dataclasses

import numpy as np
import pytest

from ibfem.solver.contact import sizing
from ibfem.solver.io.run_size import run_size
from ibfem.solver.model import problem as pb
from ibfem.solver.model.estimate import estimate_contact_dofs, estimate_size
from ibfem.solver.solving import solve

from _solids3d import HalfBall
from _turned_box import TurnedBox

RADIUS = 0.2  # the contact refinement's


def _sphere_on_flat():
    ball = HalfBall([0, 0, 1.0], 1.0)
    block = TurnedBox([2, 2, 1], shift=(-1, -1, -1))
    steel = pb.Material("steel", 2.0e11, 0.3)
    zone = (pb.Refinement(3, RADIUS),)
    bodies = (pb.BodyModel("ball", ball, steel, 0.25, zone), pb.BodyModel("block", block, steel, 0.25, zone))
    bcs = (pb.Displacement("ball", "flat", (0.0, 0.0, -0.002)), pb.Fixed("block", "z0"))
    contact = pb.ContactModel(("ball", "block"), "frictionless", point=np.zeros(3))
    return pb.Problem("sphere_on_flat", "solid", 1.0, bodies, bcs, (contact,))


def test_the_check_of_a_sized_point_contact_follows_the_disc_its_run_condenses_on(monkeypatch):
    problem = _sphere_on_flat()
    scene_size = estimate_size(problem)
    monkeypatch.setattr(sizing, "MIN_CONTACT_DOFS", 0.0)
    monkeypatch.setattr(sizing, "COARSER_LEVELS", 1)
    assert sizing.sized_contacts(problem) == [0]
    asked = []
    size, note = run_size(problem, lambda p: asked.append(p) or solve(p))
    assert len(asked) == 1 and "coarse pass" in note and "candidate disc" in note
    assert {z.levels for b in asked[0].bodies for z in b.refinements} == {2}  # one level shallower
    run = solve(problem)
    disc = run.iterations["candidate_region"]["contacts"]["0"]
    assert disc["extent"] < disc["scene_extent"]
    assert f"{disc['extent']:.3g} m of the scene's {disc['scene_extent']:.3g} m" in note
    c = problem.contacts[0]
    sized = dataclasses.replace(c, options=dataclasses.replace(c.options, extent_fraction=disc["extent"] / RADIUS))
    assert estimate_contact_dofs(dataclasses.replace(problem, contacts=(sized,))) == pytest.approx(run.iterations["contact_dofs"], rel=0.3)
    assert size.dofs == scene_size.dofs  # the scene's grid
    assert size.memory < scene_size.memory
