"""A solid's face rules after discretisation: only the faces a boundary condition names keep
their quadrature (the others served the cells' boundary areas alone). The boundary areas still
hold every face (their sum is the exact surface area of the solid inside the grid), and a face
without a kept rule gets its points computed again when a condition asks for them."""

import numpy as np
import pytest

from ibfem.solver.fem.bodies import discretise
from ibfem.solver.fem.solid_space import located_face_rule
from ibfem.solver.model import problem as pb
from ibfem.solver.model.resolve import resolve_problem

from _solids3d import HalfBall
from _turned_box import TurnedBox


@pytest.fixture(scope="module")
def bodies():
    ball = HalfBall([0, 0, 1.0], 1.0)
    block = TurnedBox([2, 2, 1], shift=(-1, -1, -1))
    steel = pb.Material("steel", 2.0e11, 0.3)
    bodies = (pb.BodyModel("ball", ball, steel, 0.5), pb.BodyModel("block", block, steel, 0.5))
    bcs = (pb.Displacement("ball", "flat", (0.0, 0.0, -0.002)), pb.Fixed("block", "z0"))
    model = pb.ContactModel(("ball", "block"), "frictionless", point=np.zeros(3))
    problem = resolve_problem(pb.Problem("condition_faces", "solid", 1.0, bodies, bcs, (model,)))
    return discretise(problem, problem.options)


def test_only_the_faces_of_conditions_keep_their_rules(bodies):
    ball, block = bodies
    assert set(ball.face_rules) == {"flat"} and set(block.face_rules) == {"z0"}


def test_the_boundary_areas_hold_every_face(bodies):
    ball, block = bodies
    # the half ball's surface: a hemisphere 2 pi r^2 and its top disc pi r^2 (r = 1)
    assert ball.boundary_area.sum() == pytest.approx(3.0 * np.pi, rel=1e-9)
    # the block 2 x 2 x 1: every face lies inside its grid
    assert block.boundary_area.sum() == pytest.approx(2 * (4.0 + 2.0 + 2.0), rel=1e-12)


def test_a_face_without_a_kept_rule_is_computed_when_asked(bodies):
    ball = bodies[0]
    bp = ball.edge_points("dome", 2)
    points, weights, _, _ = located_face_rule(ball.boundary.faces["dome"], ball.grid)
    np.testing.assert_array_equal(bp.points, points)
    assert weights.sum() == pytest.approx(2.0 * np.pi, rel=1e-9)
