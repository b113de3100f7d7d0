"""Two-body contact (solver.contact.driver): Hertz half-width for the computed force,
equilibrium of the supports and the contact, symmetry, frictionless transmission, and errors.

Fast tests use a small cylinder-on-block scene (about 10 cells across the contact); the
validation scenes of examples/ run in the slow tests."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.reference import theory
from ibfem.solver.model.options import ContactOptions
from ibfem.solver.solving import solve as solve_contact
from ibfem.solver.io.scene import load_scene, scene_from_dict

from _contact_scenes import cylinder_on_block

E, NU = 2.0e11, 0.3
E_STAR = theory.effective_modulus(E, NU, E, NU)
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def small_scene(kind="frictionless", ux=0.0, uy=-2.0e-3, load_steps=2, turn=0.0):
    return cylinder_on_block(kind, ux, uy, load_steps, turn)


@pytest.fixture(scope="module")
def frictionless():
    return solve_contact(small_scene("frictionless"))


@pytest.fixture(scope="module")
def tied_sideways():
    return solve_contact(small_scene("tied", ux=2.0e-4))


def test_half_width_against_hertz_for_computed_force(frictionless):
    c = frictionless.contacts[0]
    assert frictionless.converged
    a_hertz = theory.hertz_half_width(c["normal_force"], 1.0, E_STAR)
    # about 10 cells across 2a: the width is resolved to a fraction of a cell (h / a ~ 0.2)
    assert c["half_width"] == pytest.approx(a_hertz, rel=0.04)
    lo, hi = c["checks"]["half_width_bracket"]
    assert lo <= c["half_width"] <= hi


def test_equilibrium_and_contact_force_equal_reactions(frictionless):
    r_top = frictionless.reactions["cyl/flat"]
    r_bottom = frictionless.reactions["block/bottom"]
    scale = np.linalg.norm(r_top)
    # the two bodies' supports balance (the contact passes the force through)
    assert np.linalg.norm(r_top + r_bottom) <= 1e-6 * scale
    c = frictionless.contacts[0]
    # the cylinder pushes the block down: N equals the support reaction of either body
    assert c["normal_force"] == pytest.approx(-r_top[1], rel=1e-2)
    assert c["normal_force"] == pytest.approx(r_bottom[1], rel=1e-2)
    # frictionless and symmetric: no tangential force
    assert abs(c["tangential_force"]) <= 1e-8 * c["normal_force"]


def test_pressure_profile_is_hertzian_and_symmetric(frictionless):
    c = frictionless.contacts[0]
    s = np.asarray(c["pressure"]["s"])
    p = np.asarray(c["pressure"]["value"])
    a, n = c["half_width"], c["normal_force"]
    p0 = 2 * n / (math.pi * a)
    np.testing.assert_allclose(p, p[::-1], atol=0.02 * p0)  # symmetric about the contact point
    inner = np.abs(s) <= 0.9 * a
    rms = np.sqrt(np.mean((p[inner] - theory.hertz_pressure(s[inner], a, p0)) ** 2))
    assert rms <= 0.05 * p0
    # zero outside the region widened by the half-cell reach of the recovery's moving average
    # (plus a sample spacing of the fine samples it is interpolated from)
    assert np.all(p[np.abs(s) > a + 0.6 * c["profile_smoothing"]] == 0.0)
    # the sampled pressure integrates to the transmitted force
    assert np.trapezoid(p, s) == pytest.approx(n, rel=0.02)


def test_summary_block_follows_spec(frictionless):
    c = frictionless.contacts[0]
    for key in ("bodies", "type", "friction", "point", "normal", "tangent", "half_width", "stick_half_width",
                "normal_force", "tangential_force", "pressure", "shear"):
        assert key in c
    np.testing.assert_allclose(c["normal"], [0.0, 1.0], atol=1e-12)
    np.testing.assert_allclose(c["tangent"], [-1.0, 0.0], atol=1e-12)
    assert c["stick_half_width"] == 0.0
    # frictionless under proportional loading is path-independent: the final load solved directly
    steps = frictionless.iterations["load_steps"]
    assert (steps["requested"], steps["solved"]) == (2, 1)
    assert len(frictionless.iterations["per_step"]) == 1


def test_tied_contact_transmits_the_tangential_reaction(tied_sideways):
    sol = tied_sideways
    c = sol.contacts[0]
    r_top = sol.reactions["cyl/flat"]
    r_bottom = sol.reactions["block/bottom"]
    assert np.linalg.norm(r_top + r_bottom) <= 1e-6 * np.linalg.norm(r_top)
    # the force the cylinder exerts on the block balances the block's support reaction
    assert c["tangential_force"] == pytest.approx(-r_bottom @ np.asarray(c["tangent"]), rel=1e-2)
    assert abs(c["tangential_force"]) > 1e-3 * c["normal_force"]
    assert c["stick_half_width"] == c["half_width"]
    # the shear integrates to the tangential force
    s, q = np.asarray(c["shear"]["s"]), np.asarray(c["shear"]["value"])
    assert np.trapezoid(q, s) == pytest.approx(c["tangential_force"], rel=0.03)


def test_body_held_only_by_a_tied_contact():
    """A pressure on the cylinder's flat and nothing else holding it: K0 is singular for the
    cylinder and the solver keeps a fixed contact patch in it; the contact passes exactly the
    applied force to the block's support."""
    import dataclasses

    from ibfem.solver.model.problem import Pressure

    base = small_scene("tied")
    problem = dataclasses.replace(base, boundary_conditions=(Pressure("cyl", "flat", 4.0e7), base.boundary_conditions[1]))
    sol = solve_contact(problem)
    c = sol.contacts[0]
    applied = 4.0e7 * 2.0  # the flat edge is 2 m long
    assert sol.converged
    assert c["normal_force"] == pytest.approx(applied, rel=1e-9)
    np.testing.assert_allclose(sol.reactions["block/bottom"], [0.0, applied], atol=1e-9 * applied)
    assert c["half_width"] == pytest.approx(theory.hertz_half_width(applied, 1.0, E_STAR), rel=0.04)


def test_initial_gap_and_contact_point_found_from_the_geometry():
    """The cylinder starts 0.2 mm above the block and no contact point is given: the point is
    the midpoint of the closest points, Delta carries the gap, and the force drops to what the
    remaining approach gives (checked through Hertz for the computed force)."""
    import dataclasses

    from ibfem.geometry.shapes import profile_from_shape

    base = small_scene("frictionless")
    lifted = profile_from_shape({"type": "half_disk", "center": [0, 1.0002], "radius": 1.0, "side": "below"})
    problem = dataclasses.replace(
        base,
        bodies=(dataclasses.replace(base.bodies[0], profile=lifted), base.bodies[1]),
        contacts=(dataclasses.replace(base.contacts[0], point=None),),
    )
    sol = solve_contact(problem)
    c = sol.contacts[0]
    assert sol.converged
    np.testing.assert_allclose(c["point"], [0.0, 1e-4], atol=1e-8)
    assert c["half_width"] == pytest.approx(theory.hertz_half_width(c["normal_force"], 1.0, E_STAR), rel=0.04)
    assert c["normal_force"] == pytest.approx(sol.reactions["block/bottom"][1], rel=1e-6)


def test_turned_scene_gives_the_same_contact(frictionless):
    """The whole scene turned by 35 degrees: same force and frame turned with it; the width
    agrees to the grid-position resolution (the grid does not turn)."""
    sol = solve_contact(small_scene("frictionless", turn=35.0))
    c, c0 = sol.contacts[0], frictionless.contacts[0]
    t = math.radians(35.0)
    assert sol.converged
    np.testing.assert_allclose(c["normal"], [-math.sin(t), math.cos(t)], atol=1e-12)
    assert c["normal_force"] == pytest.approx(c0["normal_force"], rel=5e-3)
    # frictionless: the shear is zero pointwise; the resultant leans off the central normal only
    # through the asymmetry of the pressure on the curved surface, which the turned grid breaks
    assert abs(c["tangential_force"]) <= 1e-4 * c["normal_force"]
    assert c["half_width"] == pytest.approx(theory.hertz_half_width(c["normal_force"], 1.0, E_STAR), rel=0.04)


def test_thesis_width_update_reaches_a_consistent_state():
    sol = solve_contact(small_scene("frictionless", load_steps=2).with_contact_options(width_update="thesis"))
    c = sol.contacts[0]
    a_hertz = theory.hertz_half_width(c["normal_force"], 1.0, E_STAR)
    assert sol.converged
    assert c["half_width"] == pytest.approx(a_hertz, rel=0.08)


def test_unsettled_width_is_not_reported_as_converged():
    import dataclasses

    problem = small_scene("frictionless", load_steps=1)
    problem = dataclasses.replace(problem, options=dataclasses.replace(problem.options, max_iterations=2))
    sol = solve_contact(problem)
    assert not sol.converged
    assert sol.iterations["per_step"] == [2]
    assert any("did not settle" in m for m in sol.iterations["messages"])


def test_errors_name_the_field():
    problem = small_scene("frictionless")
    import dataclasses

    bad = dataclasses.replace(problem, contacts=(dataclasses.replace(problem.contacts[0], type="frictional", friction=0.0),))
    with pytest.raises(ValueError, match=r"contacts\[0\]\.friction"):
        solve_contact(bad)
    bad = dataclasses.replace(problem, contacts=(dataclasses.replace(problem.contacts[0], type="glued"),))
    with pytest.raises(ValueError, match=r"contacts\[0\]\.type"):
        solve_contact(bad)
    with pytest.raises(ValueError, match="sliver_fraction"):
        ContactOptions(sliver_fraction=1.5)
    with pytest.raises(ValueError, match="width_update"):
        ContactOptions(width_update="newton")
    with pytest.raises(ValueError, match="window"):
        ContactOptions(window=0.0)
    with pytest.raises(ValueError, match="formulation must be one of .*got 'mortar'"):
        solve_contact(problem.with_contact_options(formulation="mortar"))


# ------------------------------------------------------------------------------ validation


def _run(name):
    scene = load_scene(EXAMPLES / name)
    return scene, solve_contact(scene.problem)


@pytest.mark.slow
def test_example3_cylinder_on_cylinder_frictionless():
    _, sol = _run("cylinder_on_cylinder_frictionless.toml")
    c = sol.contacts[0]
    assert sol.converged
    a_hertz = theory.hertz_half_width(c["normal_force"], 0.5, E_STAR)
    assert c["half_width"] == pytest.approx(a_hertz, rel=0.02)  # within 2 % of Hertz
    assert abs(c["tangential_force"]) < 1e-3  # N: nothing tangential passes
    r = sol.reactions
    assert np.linalg.norm(r["upper/flat"] + r["lower/flat"]) <= 1e-6 * np.linalg.norm(r["upper/flat"])
    # subsurface von Mises on the load axis against McEwen: 0.5575 p0 at 0.704 a
    a, p0 = c["half_width"], 2 * c["normal_force"] / (math.pi * c["half_width"])
    z = np.linspace(0.05, 2.0, 400) * a_hertz
    vm = sol.von_mises(np.stack([np.zeros_like(z), -z], axis=1), body="lower")
    k = int(np.argmax(vm))
    peak, depth = theory.axis_peak(NU)
    p0_hertz = 2 * c["normal_force"] / (math.pi * a_hertz)
    assert vm[k] == pytest.approx(peak * p0_hertz, rel=0.03)
    assert z[k] == pytest.approx(depth * a_hertz, rel=0.1)


@pytest.mark.slow
def test_example2_mesh_convergence_tied():
    _, sol = _run("mesh_convergence.toml")
    c = sol.contacts[0]
    assert sol.converged
    a_hertz = theory.hertz_half_width(c["normal_force"], 1.0, E_STAR)
    assert c["half_width"] == pytest.approx(a_hertz, rel=0.02)  # within 2 % of Hertz
    assert c["normal_force"] == pytest.approx(-sol.reactions["cylinder/flat"][1], rel=1e-2)


@pytest.mark.slow
def test_example7_cylinder_on_wedge_frictionless():
    scene, sol = _run("cylinder_on_wedge_frictionless.toml")
    c = sol.contacts[0]
    assert sol.converged
    # the contact normal is the face's: (-sin 15, cos 15)
    np.testing.assert_allclose(c["normal"], [-math.sin(math.radians(15)), math.cos(math.radians(15))], atol=1e-12)
    a_hertz = theory.hertz_half_width(c["normal_force"], 1.0, E_STAR)
    assert c["half_width"] == pytest.approx(a_hertz, rel=0.02)  # within 2 % of Hertz
    # frictionless on the face: the vertical reaction of the top is N cos 15 (thesis eq. 6-5)
    assert -sol.reactions["cylinder/top"][1] == pytest.approx(c["normal_force"] * math.cos(math.radians(15)), rel=1e-2)
    assert abs(c["tangential_force"]) < 1e-3  # frictionless |Q| < 1e-3 N


def test_frictionless_contact_passes_no_tangential_force_when_pushed_sideways():
    sol = solve_contact(small_scene("frictionless", ux=3.0e-4, turn=17.0))
    c = sol.contacts[0]
    assert sol.converged and c["normal_force"] > 0
    assert abs(c["tangential_force"]) < 1e-3  # N/m, against N of order 1e8
    # the supports take the whole load: the two bodies' reactions balance
    total = sum(np.asarray(r) for r in sol.reactions.values())
    assert np.linalg.norm(total) < 1e-6 * c["normal_force"]


@pytest.mark.slow
def test_example1_ellipse_exact_against_tessellated_geometry():
    _, exact = _run("ellipse_on_block.toml")
    _, facets = _run("ellipse_on_block_tessellated.toml")
    errors = []
    for sol in (exact, facets):
        c = sol.contacts[0]
        errors.append(abs(c["half_width"] / theory.hertz_half_width(c["normal_force"], 0.1, E_STAR) - 1.0))
    assert errors[0] < 0.03
    # the thesis's degradation without exact geometry (31 % there; here the default chord
    # tolerance of 1 mm flattens the 2 mm contact much more)
    assert errors[1] > 10 * errors[0]


# ------------------------------------------------------------------ width independent of the grid


def _scene_data(name):
    import tomllib

    data = tomllib.loads((EXAMPLES / name).read_text())
    data.pop("output", None)
    return data


def _turned(data, deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    for b in data["bodies"]:
        b["shape"]["rotate_deg"] = deg
    for bc in data["boundary_conditions"]:
        if bc["type"] == "displacement":
            x, y = bc["value"]
            bc["value"] = [c * x - s * y, s * x + c * y]
    for cm in data["contacts"]:
        x, y = cm["point"]
        cm["point"] = [c * x - s * y, s * x + c * y]
    return data


def _hertz_error(data, offset=(0.0, 0.0), r_star=0.5, e_star=E_STAR):

    problem = scene_from_dict(data, label="test", base_dir=EXAMPLES).problem
    sol = solve_contact(problem.with_options(grid_offset=tuple(offset)))
    c = sol.contacts[0]
    assert sol.converged, sol.iterations["messages"]
    return c["half_width"] / theory.hertz_half_width(c["normal_force"], r_star, e_star) - 1.0


def test_half_width_does_not_depend_on_where_the_grid_starts():
    # the small scene (h / a ~ 0.2) at three grid positions (fractions of the coarsest cell):
    # the width is the root of a continuous function of a, not a one-cell verdict

    errors = []
    for off in [(0.0, 0.0), (0.013, 0.021), (0.37, 0.26)]:
        sol = solve_contact(small_scene("frictionless").with_options(grid_offset=off))
        c = sol.contacts[0]
        assert sol.converged, sol.iterations["messages"]
        errors.append(c["half_width"] / theory.hertz_half_width(c["normal_force"], 1.0, E_STAR) - 1.0)
    assert max(abs(e) for e in errors) < 0.02, errors


@pytest.mark.slow
def test_example3_half_width_within_2_percent_at_any_grid_position():
    rng = np.random.default_rng(5)
    # grid origin shifts in fractions of the coarsest cell (Settings.grid_offset)
    offsets = [(0.0, 0.0)] + [tuple(o) for o in rng.uniform(0.0, 1.0, (5, 2))]
    errors = [_hertz_error(_scene_data("cylinder_on_cylinder_frictionless.toml"), off) for off in offsets]
    assert max(abs(e) for e in errors) < 0.02, errors


@pytest.mark.slow
def test_example3_half_width_stiffness_ratio_10_and_turned_scene():
    stiff = _scene_data("cylinder_on_cylinder_frictionless.toml")
    stiff["materials"].append({"name": "stiff", "youngs_modulus": 10 * E, "poissons_ratio": NU})
    stiff["bodies"][0]["material"] = "stiff"
    e_stiff = theory.effective_modulus(10 * E, NU, E, NU)
    assert abs(_hertz_error(stiff, e_star=e_stiff)) < 0.02
    assert abs(_hertz_error(_turned(_scene_data("cylinder_on_cylinder_frictionless.toml"), 30.0))) < 0.02
