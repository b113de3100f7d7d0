"""Every solver option is reachable from a scene file: ``[solver]`` for the global ones, the keys of
a ``[[contacts]]`` table for the contact's formulation; out-of-range values are refused before
anything is solved, naming the key; the options change what the solver does."""

from __future__ import annotations

import dataclasses
import tomllib

import pytest

from ibfem.solver.io.scene import SceneError, scene_from_dict
from ibfem.solver.model.options import ContactOptions, SolverOptions
from ibfem.solver.solving import solve

SCENE = """
name = "small cylinder on block"
[solver]
{solver}
[[materials]]
name = "steel"
youngs_modulus = 2.0e11
poissons_ratio = 0.3
[[bodies]]
name = "cyl"
material = "steel"
element_size = 0.1
refinement = [{{ levels = 2, around = "contact", radius = 0.4 }}, {{ levels = 4, around = "contact", radius = 0.12 }}]
shape = {{ type = "half_disk", center = [0, 1], radius = 1.0, side = "below" }}
[[bodies]]
name = "block"
material = "steel"
element_size = 0.1
refinement = [{{ levels = 2, around = "contact", radius = 0.4 }}, {{ levels = 4, around = "contact", radius = 0.12 }}]
shape = {{ type = "rectangle", min = [-1.5, -1.0], max = [1.5, 0.0] }}
[[boundary_conditions]]
body = "cyl"
edge = "flat"
type = "displacement"
value = [0.0, -2.0e-3]
[[boundary_conditions]]
body = "block"
edge = "bottom"
type = "fixed"
[[contacts]]
bodies = ["cyl", "block"]
type = "frictionless"
point = [0, 0]
{contact}
"""


def scene(solver: str = "", contact: str = ""):
    if "load_steps" not in solver:
        solver = "load_steps = 1\n" + solver
    return scene_from_dict(tomllib.loads(SCENE.format(solver=solver, contact=contact)), label="scene.toml")


def test_every_option_has_a_scene_key():
    base = scene()
    assert base.problem.options == SolverOptions(load_steps=1)
    assert base.problem.contacts[0].options == ContactOptions()
    solver_keys = set(type(base.spec.solver).model_fields)
    contact_keys = set(type(base.spec.contacts[0]).model_fields)
    assert {f.name for f in dataclasses.fields(SolverOptions)} <= solver_keys
    assert {f.name for f in dataclasses.fields(ContactOptions)} <= contact_keys


def test_contact_options_from_toml_reach_the_contact():
    s = scene(contact='width_update = "bracket"\nflux = "body1"\nsliver_fraction = 0.0\ngap_tolerance = 2e-3')
    opts = s.problem.contacts[0].options
    assert (opts.width_update, opts.flux, opts.sliver_fraction, opts.gap_tolerance) == ("bracket", "body1", 0.0, 2e-3)


def test_a_contact_option_from_toml_takes_effect():
    """max_width_iterations = 2 on the contact: the width search is cut after two solves and the
    run says so (not converged), where the default settles in more."""
    free = solve(scene().problem)
    assert free.converged and free.iterations["total"] > 2
    capped = solve(scene(contact="max_width_iterations = 2").problem)
    assert not capped.converged
    assert capped.iterations["per_step"] == [2]
    assert any("did not settle" in m for m in capped.iterations["messages"])


def test_width_update_from_toml_changes_the_search():
    sol = solve(scene(contact='width_update = "thesis"').problem)
    assert sol.iterations["width_update"] == "thesis"


def test_solver_tolerance_is_the_residual_work_of_the_final_state():
    loose = solve(scene(solver="tolerance = 0.5").problem)
    assert loose.converged and loose.iterations["residual_work"] <= 0.5
    strict = solve(scene(solver="tolerance = 1e-300").problem)
    assert not strict.converged
    assert any("solver.tolerance" in m for m in strict.iterations["messages"])
    # the state itself does not depend on the criterion that judges it
    assert strict.contacts[0]["half_width"] == loose.contacts[0]["half_width"]


@pytest.mark.parametrize(
    "solver, contact, expected",
    [
        ("band_fraction = 0.0", "", r"solver\.band_fraction = 0\.0: must be a positive number"),
        ("consistency = 1.5", "", r"solver\.consistency = 1\.5: must lie in \[0, 1\]"),
        ("chord_tolerance = -1e-3", "", r"solver\.chord_tolerance = -0\.001"),
        ("load_steps = 1000000000000", "", r"solver\.load_steps = 1000000000000: must be an integer in \[1, 10000\]"),
        ("accuracy = 0.0", "", r"solver\.accuracy = 0\.0: must lie in \[1e-5, 1\)"),
        ('accuracy = "fine"', "", r"solver\.accuracy"),
        ("", "window = 0.0", r"contacts\[0\]\.window = 0\.0: must be a positive number"),
        ("", 'width_update = "newton"', r"contacts\[0\]\.width_update = \"newton\": must be one of"),
        ("", "sliver_fraction = 1.5", r"contacts\[0\]\.sliver_fraction = 1\.5: must lie in \[0, 1\)"),
    ],
)
def test_out_of_range_options_are_scene_errors(solver, contact, expected):
    with pytest.raises(SceneError, match=expected):
        scene(solver=solver, contact=contact)
