"""A 3D scene's user mistakes end with one line naming the key and its value, from ``--check``
on (before, a grid of 5 m cells on bodies of 0.01 m and a contact point 2.5 m off both bodies
passed validation and failed in the contact's set-up naming no key); bodies apart or overlapping at
their contact are warned of with the gap's size."""

from __future__ import annotations

import copy

import pytest

from ibfem.solver.io.scene import SceneError, load_scene

BALL_ON_BLOCK = {
    "name": "ball_on_block", "model": "solid",
    "materials": [{"name": "steel", "youngs_modulus": 2.0e11, "poissons_ratio": 0.3}],
    "bodies": [
        {"name": "ball", "material": "steel", "element_size": 0.1,
         "shape": {"type": "half_sphere", "center": [0.0, 0.0, 0.5], "radius": 0.5, "side": "below"}},
        {"name": "block", "material": "steel", "element_size": 0.1,
         "shape": {"type": "box", "min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.0]}},
    ],
    "boundary_conditions": [
        {"type": "displacement", "body": "ball", "face": "flat", "value": [0.0, 0.0, -0.004]},
        {"type": "fixed", "body": "block", "face": "z_min"},
    ],
    "contacts": [{"bodies": ["ball", "block"], "type": "frictionless", "point": [0.0, 0.0, 0.0]}],
}


def _scene(**changes):
    data = copy.deepcopy(BALL_ON_BLOCK)
    for path, value in changes.items():
        *keys, last = path.split("__")
        target = data
        for key in keys:
            target = target[int(key)] if key.isdigit() else target[key]
        target[int(last) if last.isdigit() else last] = value
    return data


def _errors(data) -> str:
    with pytest.raises(SceneError) as err:
        load_scene(data, label="scene.toml")
    return str(err.value)


def test_the_touching_scene_loads_without_warnings():
    assert load_scene(_scene(), label="scene.toml").warnings == ()


def test_a_grid_coarser_than_the_bodies_is_named():
    """Bodies of 0.01 m with cells of 5 m (millimetres meant)."""
    text = _errors(_scene(bodies__0__element_size=5.0, bodies__1__element_size=5.0,
                          bodies__0__shape={"type": "half_sphere", "center": [0, 0, 0.005], "radius": 0.005},
                          bodies__1__shape={"type": "box", "min": [-0.01, -0.01, -0.01], "max": [0.01, 0.01, 0.0]}))
    assert "bodies[0].element_size = 5.0" in text and "bodies[1].element_size = 5.0" in text
    assert "smallest bounding-box dimension is 0.005 m" in text


def test_a_contact_point_off_both_bodies_is_named():
    text = _errors(_scene(contacts__0__point=[3.0, 0.0, 0.0]))
    assert "contacts[0].point = [3.0, 0.0, 0.0]" in text
    # the distances are exact: the block's corner x = 0.5 is 2.5 m away, the ball's equator 2.5 m + ...
    assert "2.5 m from the surface of body 'block'" in text
    assert "from the surface of body 'ball'" in text


def test_a_displacement_larger_than_the_body_is_named():
    text = _errors(_scene(boundary_conditions__0__value=[0.0, 0.0, -4.0]))
    assert "boundary_conditions[0]: a prescribed displacement of 4 m" in text


def test_a_probe_outside_every_body_is_named():
    data = _scene()
    data["output"] = {"probes": [[0.0, 0.0, -0.1], [2.0, 0.0, 0.0]]}
    text = _errors(data)
    assert "output.probes[1] = [2.0, 0.0, 0.0]: outside every body" in text
    assert "probes[0]" not in text


@pytest.mark.parametrize("lift, words", [(0.001, "do not touch: 0.001 m apart"), (-0.005, "overlap by 0.005 m")])
def test_a_gap_or_an_interference_is_warned_of_with_its_size(lift, words):
    """The ball lifted by 1 mm, or sunk 5 mm into the block: the gap is the exact distance of the
    sphere's lowest point from the plane."""
    data = _scene(bodies__0__shape={"type": "half_sphere", "center": [0.0, 0.0, 0.5 + lift], "radius": 0.5})
    warnings = load_scene(data, label="scene.toml").warnings
    assert len(warnings) == 1 and "contacts[0] ('ball' on 'block')" in warnings[0] and words in warnings[0]


def test_a_ball_free_along_x_on_a_frictionless_contact_is_refused_naming_the_motion():
    """The ball's flat face held in y and z only: a frictionless contact holds it along z, so the
    x translation is free (the run's assembly found it, after ``--check`` had passed)."""
    text = _errors(_scene(boundary_conditions__0__value=["free", 0.0, -0.004]))
    assert "bodies[0].name = 'ball': rigid-body motion not prevented (a translation along [1.0, 0.0, 0.0])" \
        in text.replace("-1.0", "1.0")
    assert "bodies[1]" not in text  # the block is fixed


def test_a_frictional_contact_holds_the_ball_free_along_x():
    """The same ball held through a frictional contact: the stick patch holds the x translation."""
    data = _scene(boundary_conditions__0__value=["free", 0.0, -0.004])
    data["contacts"][0].update(type="frictional", friction=0.3)
    assert load_scene(data, label="scene.toml").warnings == ()


def test_a_quarter_ball_held_by_its_symmetry_planes_and_the_contact_passes():
    """A quarter ball loaded by a force: its symmetry planes slide, the contact holds it along z."""
    data = _scene(bodies__0__shape={"type": "revolution", "axis_origin": [0, 0, 0.5], "axis": [0, 0, 1],
                                    "angle_deg": 90, "profile": {"type": "profile", "edges": [
                                        {"type": "line", "start": [0, 0], "end": [0.5, 0], "name": "flat"},
                                        {"type": "arc", "center": [0, 0], "radius": 0.5, "start_angle": 0,
                                         "end_angle": -90, "name": "dome"},
                                        {"type": "line", "start": [0, -0.5], "end": [0, 0], "name": "axis"}]}},
                  boundary_conditions__0={"type": "pressure", "body": "ball", "face": "flat", "value": 1.0e6})
    data["boundary_conditions"] += [{"type": "sliding", "body": "ball", "face": "start"},
                                    {"type": "sliding", "body": "ball", "face": "end"}]
    load_scene(data, label="scene.toml")
    del data["boundary_conditions"][-1]  # the plane x = 0 free: the ball moves along x
    assert "rigid-body motion not prevented" in _errors(data)


def test_a_contact_without_force_has_no_empty_error_estimate_in_its_line():
    """A gap the loads never close: the contact carries no force and has no estimate; its line
    ended in "estimated error " with nothing after it."""
    from ibfem.solver.io.result_line import contact_line

    line = contact_line({"type": "frictionless", "semi_axes": [0.0, 0.0], "normal_force": 0.0, "estimated_error": {}})
    assert line == "semi_axes = [0, 0] m, normal_force = 0 N"
