"""Dundurs' beta of a pair and the warnings a frictional run gives where Cattaneo and Mindlin's
zones (one slip direction) cannot hold."""

from __future__ import annotations

import pytest

from ibfem.solver.commands import _dissimilar_friction_note, _slip_direction_note
from ibfem.solver.model.elasticity import dundurs_beta, lame_parameters

ALUMINIUM, STEEL = (7.0e10, 0.33), (2.0e11, 0.3)


@pytest.mark.parametrize("model", ["plane_strain", "plane_stress", "solid"])
def test_dundurs_beta_against_its_definition_in_moduli(model):
    """beta = (1/2) [(1 - 2 nu1) / G1 - (1 - 2 nu2) / G2] / [(1 - nu1) / G1 + (1 - nu2) / G2] in
    plane strain and 3D (Johnson 1985, eq. 5.4); plane stress replaces nu by nu / (1 + nu)."""
    (e1, n1), (e2, n2) = ALUMINIUM, STEEL
    g1, g2 = e1 / (2 * (1 + n1)), e2 / (2 * (1 + n2))
    if model == "plane_stress":
        n1, n2 = n1 / (1 + n1), n2 / (1 + n2)
    expected = 0.5 * ((1 - 2 * n1) / g1 - (1 - 2 * n2) / g2) / ((1 - n1) / g1 + (1 - n2) / g2)
    beta = dundurs_beta(lame_parameters(*ALUMINIUM, model), lame_parameters(*STEEL, model))
    assert beta == pytest.approx(expected, rel=1e-12)
    assert dundurs_beta(lame_parameters(*STEEL, model), lame_parameters(*ALUMINIUM, model)) == pytest.approx(-beta)
    assert dundurs_beta(lame_parameters(*STEEL, model), lame_parameters(*STEEL, model)) == 0.0


def test_a_rigid_indenter_on_steel_has_beta_of_the_half_space_alone():
    """A rigid body against steel: beta = (1 - 2 nu) / (2 (1 - nu)) with the sign of the order
    (-0.2857 for nu 0.3, the rigid body first)."""
    rigid = lame_parameters(2.0e20, 0.3, "plane_strain")
    assert dundurs_beta(rigid, lame_parameters(*STEEL, "plane_strain")) == pytest.approx(-0.4 / 1.4, rel=1e-8)


def test_a_3d_frictional_pair_of_two_materials_warns_and_one_material_does_not():
    block = {"type": "frictional", "friction": 0.3, "point": [0.0, 0.0, 0.0], "dundurs_beta": 0.112}
    note = _dissimilar_friction_note(block, True)
    assert note and "0.112" in note and "[[paths]]" in note
    assert _dissimilar_friction_note({**block, "dundurs_beta": 0.0}, True) is None
    assert _dissimilar_friction_note({**block, "type": "frictionless"}, True) is None
    assert _dissimilar_friction_note(block, False) is None  # 2D judges its final state instead


def test_the_2d_warning_reads_the_slip_against_the_traction():
    block = {"type": "frictional", "checks": {"slip_against_traction": 0.46}}
    assert "46 %" in _slip_direction_note(block)
    assert _slip_direction_note({"type": "frictional", "checks": {"slip_against_traction": 0.05}}) is None
    assert _slip_direction_note({"type": "frictional", "checks": {}}) is None


def _problem(tmp_path, scene):
    import json

    from ibfem.solver.io.scene import load_scene

    path = tmp_path / "scene.json"
    path.write_text(json.dumps(scene))
    return load_scene(path).problem


def test_which_runs_keep_a_friction_memory(tmp_path):
    """2D frictional contacts of bodies that slip apart (|beta| >= 0.1 mu) ramp with friction
    memory; one material, a frictionless pair, a scene with its own paths and a 3D scene do not."""
    import test_scenes_drawn_2d as drawn

    from ibfem.solver.contact.friction_memory import MEMORY_STEPS, MEMORY_STICK_ITERATIONS, with_friction_memory
    from ibfem.solver.contact.driver import load_steps

    stiff = _problem(tmp_path, drawn.crown_on_block(drawn.STIFF))
    chosen = with_friction_memory(stiff)
    assert chosen.history is not None and chosen.history.steps_per_unit == MEMORY_STEPS
    assert chosen.contacts[0].options.max_stick_iterations >= MEMORY_STICK_ITERATIONS
    steps, rule = load_steps(chosen)
    assert steps == MEMORY_STEPS and "friction with memory" in rule and "-0.28" in rule
    one = _problem(tmp_path, drawn.crown_on_block(drawn.STEEL))
    assert with_friction_memory(one) is one
    scene = drawn.crown_on_block(drawn.STIFF)
    scene["contacts"][0] = {**scene["contacts"][0], "type": "frictionless"}
    scene["contacts"][0].pop("friction")
    frictionless = _problem(tmp_path, scene)
    assert with_friction_memory(frictionless) is frictionless
    own = _problem(tmp_path, drawn.crown_on_block(drawn.STIFF, paths=True))
    assert with_friction_memory(own) is own
