"""The candidate disc of a 3D point contact sized from a coarse pass (solver.contact.sizing).

The condensation onto the candidate disc's dofs is exact on any set of dofs that holds the
contact terms, so the answer must not depend on the disc once the disc holds the region: a run
on the sized (smaller) disc and a run on the scene's disc give the same region and force, with
fewer contact dofs; a disc sized too small is caught at its edge and the scene's disc solved."""

import numpy as np
import pytest

from ibfem.solver.contact import sizing
from ibfem.solver.model import problem as pb
from ibfem.solver.model.options import ContactOptions
from ibfem.solver.solving import solve

from _solids3d import HalfBall
from _turned_box import TurnedBox

E, NU = 2.0e11, 0.3


def _sphere_on_flat():
    ball = HalfBall([0, 0, 1.0], 1.0)
    block = TurnedBox([2, 2, 1], shift=(-1, -1, -1))
    steel = pb.Material("steel", E, NU)
    zone = (pb.Refinement(3, 0.2),)
    bodies = (pb.BodyModel("ball", ball, steel, 0.25, zone), pb.BodyModel("block", block, steel, 0.25, zone))
    bcs = (pb.Displacement("ball", "flat", (0.0, 0.0, -0.002)), pb.Fixed("block", "z0"))
    contact = pb.ContactModel(("ball", "block"), "frictionless", point=np.zeros(3))
    return pb.Problem("sphere_on_flat", "solid", 1.0, bodies, bcs, (contact,))


@pytest.fixture(scope="module")
def runs():
    problem = _sphere_on_flat()
    assert sizing.sized_contacts(problem) == []  # a small contact: solved as written
    scene = solve(problem)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(sizing, "MIN_CONTACT_DOFS", 0.0)  # a small scene: a coarse pass one level shallower
        mp.setattr(sizing, "COARSER_LEVELS", 1)
        assert sizing.sized_contacts(problem) == [0]
        sized = solve(problem)
        mp.setattr(sizing, "MARGIN", -0.6)  # a disc inside the region: its edge is reached
        mp.setattr(sizing, "MARGIN_CELLS", 0.0)
        too_small = solve(problem)
    return scene, sized, too_small


def test_the_sized_disc_gives_the_scene_discs_answer_on_fewer_dofs(runs):
    scene, sized, _ = runs
    record = sized.iterations["candidate_region"]
    disc = record["contacts"]["0"]
    assert disc["extent"] < disc["scene_extent"] and "reason" not in record
    assert sized.iterations["contact_dofs"] < 0.8 * scene.iterations["contact_dofs"]
    assert sized.contacts[0]["normal_force"] == pytest.approx(scene.contacts[0]["normal_force"], rel=1e-6)
    # the region search closes its bracket to edge_tolerance finest cells: the two runs' trials
    # differ in round-off, so each lands somewhere within it (measured 1.7e-6 of a apart, 7e-8 m)
    settled = ContactOptions().edge_tolerance * 0.25 / 2**3  # finest cell: element 0.25, 3 levels
    np.testing.assert_allclose(sized.contacts[0]["semi_axes"], scene.contacts[0]["semi_axes"], rtol=0, atol=settled)
    assert disc["extent"] > max(sized.contacts[0]["semi_axes"])


def test_a_disc_sized_too_small_falls_back_to_the_scenes_disc(runs):
    scene, _, too_small = runs
    assert "scene's disc" in too_small.iterations["candidate_region"]["reason"]
    assert too_small.iterations["contact_dofs"] == scene.iterations["contact_dofs"]
    np.testing.assert_allclose(too_small.contacts[0]["semi_axes"], scene.contacts[0]["semi_axes"], rtol=1e-12)
