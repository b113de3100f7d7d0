"""Frictional contact with partial slip (solver.contact.driver): the stick zone against
Cattaneo-Mindlin for the transmitted forces (c/a = sqrt(1 - |Q|/(mu N)), thesis eq. 2-29), the
shear against eqs. 2-25/2-26, Coulomb's bound |Q| <= mu N, equilibrium, gross slip, and the
thesis's variant without the slip-zone friction traction.

Fast tests use a small cylinder-on-block scene (about 10-13 cells across the contact); the
validation scenes 4-6 of examples/ run in the slow tests."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.reference import theory
from ibfem.solver.reports import validate
from ibfem.solver.solving import solve as solve_contact
from ibfem.solver.io.scene import load_scene

from _contact_scenes import cylinder_on_block

E, NU = 2.0e11, 0.3
E_STAR = theory.effective_modulus(E, NU, E, NU)
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def frictional_scene(mu=0.3, ux=2.0e-4, uy=-2.0e-3, load_steps=2, turn=0.0):
    """Cylinder R = 1 on a block; the cylinder's flat edge moved by (ux, uy) (turned by ``turn``)."""
    return cylinder_on_block("frictional", ux, uy, load_steps, turn, friction=mu)


def metrics(problem, sol):
    """ibfem.solver.reports.validate's comparison with Hertz / Cattaneo-Mindlin for the computed N and Q."""
    return validate.compare_contact(problem, sol.contacts[0], {})


@pytest.fixture(scope="module")
def partial_slip():
    problem = frictional_scene(mu=0.3, ux=4.1e-4)  # Q/N ~ 0.15: c/a ~ 0.71
    return problem, solve_contact(problem)


def test_stick_zone_follows_cattaneo_mindlin_for_the_computed_forces(partial_slip):
    problem, sol = partial_slip
    assert sol.converged, sol.iterations["messages"]
    c = sol.contacts[0]
    m = metrics(problem, sol)
    assert 0.3 < abs(m["Q_over_N"]) / 0.3 < 0.7  # a genuine partial slip
    assert abs(c["tangential_force"]) < 0.3 * c["normal_force"]  # Coulomb: |Q| < mu N
    assert m["ca_error"] < 0.02  # c/a against sqrt(1 - |Q|/(mu N)) (eq. 2-29)
    assert m["a_error"] < 0.03  # Hertz for the computed N (about 13 cells across 2a)
    assert m["shear_rms"] < 0.15  # against eqs. 2-25 / 2-26, in mu p0, inside 0.95 a
    assert m["pressure_rms"] < 0.05
    assert not c["gross_slip"]
    assert c["checks"]["slip_direction_violations"] == 0.0
    assert c["checks"]["stick_shear_above_mu_p"] == 0.0


def test_equilibrium_and_transmitted_forces(partial_slip):
    _, sol = partial_slip
    r_top, r_bottom = sol.reactions["cyl/flat"], sol.reactions["block/bottom"]
    assert np.linalg.norm(r_top + r_bottom) <= 1e-6 * np.linalg.norm(r_top)
    c = sol.contacts[0]
    # the force body 1 exerts on body 2 is the block's support reaction, reversed
    on2 = c["normal_force"] * -np.asarray(c["normal"]) + c["tangential_force"] * np.asarray(c["tangent"])
    np.testing.assert_allclose(on2, -r_bottom, rtol=0, atol=1e-3 * np.linalg.norm(r_bottom))
    # the sampled shear integrates to the tangential force
    s, q = np.asarray(c["shear"]["s"]), np.asarray(c["shear"]["value"])
    assert np.trapezoid(q, s) == pytest.approx(c["tangential_force"], rel=0.03)
    assert 0.0 < c["stick_half_width"] < c["half_width"]


def test_slip_zone_carries_mu_times_pressure():
    # in the slip zones the traction is Coulomb's mu p (eq. 5-24): compare the profiles away from
    # the zone ends (the profiles are one-cell moving averages; c/a ~ 0.4 leaves ~2 cells of slip)
    sol = solve_contact(frictional_scene(mu=0.05, ux=1.2e-4))
    c = sol.contacts[0]
    s = np.abs(np.asarray(c["shear"]["s"]))
    q, p = np.abs(np.asarray(c["shear"]["value"])), np.asarray(c["pressure"]["value"])
    w = 0.5 * c["profile_smoothing"]
    zone = (s > c["stick_half_width"] + w) & (s < c["half_width"] - w)
    assert zone.sum() >= 5
    np.testing.assert_allclose(q[zone], 0.05 * p[zone], rtol=0, atol=0.02 * 0.05 * p.max())


def test_thesis_variant_without_friction_traction_overestimates_the_shear(partial_slip):
    problem, full = partial_slip
    sol = solve_contact(problem.with_contact_options(friction_traction=False))
    assert sol.converged
    m_full, m_thesis = metrics(problem, full), metrics(problem, sol)
    assert m_thesis["ca_error"] < 0.02  # the stick ratio is still consistent with the forces
    # without the slip traction the stick zone carries all the shear (the thesis's figures 6-15, 6-27)
    assert m_thesis["shear_rms"] > 3 * m_full["shear_rms"]
    assert sol.contacts[0]["checks"]["stick_shear_above_mu_p"] > 0.0


def test_gross_slip_is_detected_and_solved_with_sliding_friction():
    problem = frictional_scene(mu=0.05, ux=5.0e-4)  # the tied solution would need Q/N ~ 0.18
    sol = solve_contact(problem)
    c = sol.contacts[0]
    assert c["gross_slip"] and c["stick_half_width"] == 0.0
    assert any("gross slip" in msg for msg in sol.iterations["messages"])
    # full sliding friction: Q = mu N up to the turn of the local normals over the region (~a/R)
    assert abs(c["tangential_force"]) == pytest.approx(0.05 * c["normal_force"], rel=5e-3)
    a_hertz = theory.hertz_half_width(c["normal_force"], 1.0, E_STAR)
    assert c["half_width"] == pytest.approx(a_hertz, rel=0.03)


@pytest.mark.parametrize(
    "mu, ux, ratio",
    [(0.05, 6.8e-6, (0.03, 0.1)), (0.05, 1.4e-4, (0.9, 0.99)), (1.0, 1.37e-4, (0.03, 0.1)), (1.0, 2.8e-3, (0.9, 0.99))],
)
def test_friction_and_load_ratio_extremes(mu, ux, ratio):
    # stress test: mu from 0.05 to 1, |beta|/mu from ~0.05 to ~0.95 (the displacement sets it)
    problem = frictional_scene(mu=mu, ux=ux)
    sol = solve_contact(problem)
    assert sol.converged, sol.iterations["messages"]
    m = metrics(problem, sol)
    assert ratio[0] < abs(m["Q_over_N"]) / mu < ratio[1]
    assert m["ca_error"] < 0.02
    assert m["a_error"] < 0.03
    assert m["shear_rms"] < 0.15
    assert abs(m["Q"]) < mu * m["N"]


def test_turned_scene_gives_the_same_partial_slip(partial_slip):
    problem, sol = partial_slip
    turned = frictional_scene(mu=0.3, ux=4.1e-4, turn=30.0)
    sol_t = solve_contact(turned)
    assert sol_t.converged
    c, ct = sol.contacts[0], sol_t.contacts[0]
    for key in ("half_width", "stick_half_width", "normal_force", "tangential_force"):
        assert ct[key] == pytest.approx(c[key], rel=0.02), key


# ------------------------------------------------------------------------------ validation


def _example(name):
    scene = load_scene(EXAMPLES / name)
    sol = solve_contact(scene.problem)
    return scene.problem, sol, metrics(scene.problem, sol)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["cylinder_on_flat_partial_slip.toml", "cylinder_on_cylinder_partial_slip.toml",
                                  "cylinder_in_concave_partial_slip.toml"])
def test_examples_4_5_6_partial_slip(name):
    # a within 2 % of Hertz and c/a within 0.02 of Cattaneo-Mindlin for the
    # computed forces, shear RMS within 15 % of mu p0 inside 0.95 a, |Q| <= mu N
    problem, sol, m = _example(name)
    assert sol.converged, sol.iterations["messages"]
    mu = sol.contacts[0]["friction"]
    assert m["a_error"] < 0.02
    assert m["ca_error"] < 0.02
    assert m["shear_rms"] < 0.15
    assert abs(m["Q"]) <= mu * m["N"]
    assert 0.0 < m["ca"] < 1.0


def test_stick_ratio_does_not_depend_on_the_load_steps():
    # near gross slip the early load steps of a proportional displacement path may slip grossly
    # (Q/N is larger at small loads); the discrete problem has no history, so the final state
    # must be the one-step answer (a step after gross slip restarts from tied, not from c = 0)
    one = solve_contact(frictional_scene(mu=0.05, ux=1.4e-4, load_steps=1)).contacts[0]
    many = solve_contact(frictional_scene(mu=0.05, ux=1.4e-4, load_steps=8)).contacts[0]
    assert not one["gross_slip"] and not many["gross_slip"]
    assert many["stick_half_width"] / many["half_width"] == pytest.approx(
        one["stick_half_width"] / one["half_width"], abs=0.01)
    assert many["tangential_force"] == pytest.approx(one["tangential_force"], rel=0.01)
