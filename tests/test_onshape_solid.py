"""A solid from an Onshape part analysed in 3D: the ball of fixtures/onshape/cone_sphere
(its exact sphere face), held on its surface under a uniform body force b. Exact solution:
u = b (R^2 - r^2) / (2 lambda + 8 mu) (Navier's equation with u = 0 on the sphere); the cut
cells' volume against 4/3 pi R^3; the support's reaction against b V."""

from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.io.scene import load_scene
from ibfem.solver.solving import solve

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "onshape" / "cone_sphere"
E, NU, B = 2.0e11, 0.3, -1.0e9


def test_onshape_ball_under_body_force():
    scene = {"model": "solid", "name": "ball",
             "materials": [{"name": "steel", "youngs_modulus": E, "poissons_ratio": NU}],
             "bodies": [{"name": "ball", "material": "steel", "element_size": 0.003,
                         "shape": {"type": "onshape", "path": str(FIXTURE), "body": "Ball"}}],
             "boundary_conditions": [{"type": "fixed", "body": "ball", "face": "JIW"},
                                     {"type": "body_force", "body": "ball", "value": [0, 0, B]}]}
    loaded = load_scene(scene, label="ball.json")
    solid = loaded.problem.bodies[0].profile
    sphere = solid.faces["JIW"].surface  # the exact sphere of the CAD face
    centre, radius = np.asarray(sphere.origin, float), float(sphere.radius)
    sol = solve(loaded.problem)
    body = sol.bodies[0]
    volume = 4.0 / 3.0 * np.pi * radius**3
    assert body.inside_volume.sum() == pytest.approx(volume, rel=1e-6)
    assert sol.reactions["ball/JIW"] == pytest.approx([0, 0, -B * volume], rel=1e-8, abs=1e-8 * abs(B) * volume)
    lam, mu = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
    pts = centre + radius * np.array([[0.0, 0.0, 0.0], [0.3, 0.0, 0.0], [0.0, 0.5, 0.2]])
    exact = B * (radius**2 - ((pts - centre) ** 2).sum(axis=1)) / (2 * lam + 8 * mu)
    np.testing.assert_allclose(sol.displacement(pts)[:, 2], exact, rtol=0.03)  # h = R / 4: 1-1.5 %


def test_turned_onshape_ball_keeps_its_volume_and_reaction():
    # the same ball turned and moved (a wrapped CAD solid, as examples/solid/onshape_ball_on_block):
    # its faces have no graded rule of their own (the solver falls back to their quadrature); the
    # volume and the support's reaction are invariants of the rigid motion
    scene = {"model": "solid", "name": "ball turned",
             "materials": [{"name": "steel", "youngs_modulus": E, "poissons_ratio": NU}],
             "bodies": [{"name": "ball", "material": "steel", "element_size": 0.004,
                         "shape": {"type": "onshape", "path": str(FIXTURE), "body": "Ball",
                                   "rotate": {"axis": [1, 2, 3], "angle_deg": 35}, "translate": [0.01, 0, 0]}}],
             "boundary_conditions": [{"type": "fixed", "body": "ball", "face": "JIW"},
                                     {"type": "body_force", "body": "ball", "value": [0, 0, B]}]}
    loaded = load_scene(scene, label="ball_turned.json")
    radius = float(loaded.problem.bodies[0].profile.faces["JIW"].surface.radius) if hasattr(
        loaded.problem.bodies[0].profile.faces["JIW"], "surface") else None
    sol = solve(loaded.problem)
    volume = float(sol.bodies[0].inside_volume.sum())
    if radius is not None:
        assert volume == pytest.approx(4.0 / 3.0 * np.pi * radius**3, rel=1e-6)
    assert sol.reactions["ball/JIW"] == pytest.approx([0, 0, -B * volume], rel=1e-8, abs=1e-8 * abs(B) * volume)
