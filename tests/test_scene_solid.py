"""3D scene files (model = "solid"): validation with key paths, boundary
conditions on faces, a contact, and a run through `ibfem run` writing summary.json, VTU and
pictures. The solids come from a stand-in of geometry.solids (test-local exact solids), so the
scene layer is tested on its own."""

import json
import sys
import types

import numpy as np
import pytest

from ibfem.solver.io.scene import SceneError, load_scene

from _solids3d import HalfBall
from _turned_box import TurnedBox


@pytest.fixture
def solids(monkeypatch):
    def solid_from_dict(shape, where="shape", load_part=None):
        if shape["type"] == "half_sphere":
            return HalfBall(shape["center"], shape["radius"])
        if shape["type"] == "box":
            lo, hi = np.asarray(shape["min"], float), np.asarray(shape["max"], float)
            return TurnedBox(hi - lo, shift=lo)
        raise ValueError(f"{where}.type = {shape['type']!r}: unknown")

    fake = types.ModuleType("ibfem.geometry.solids")
    fake.solid_from_dict = solid_from_dict
    monkeypatch.setitem(sys.modules, "ibfem.geometry.solids", fake)


def _scene(levels=3):
    return {
        "model": "solid",
        "name": "ball_on_block",
        "materials": [{"name": "steel", "youngs_modulus": 2e11, "poissons_ratio": 0.3}],
        "bodies": [
            {"name": "ball", "material": "steel", "element_size": 0.25,
             "refinement": {"levels": levels, "around": "contact", "radius": 0.1},
             "shape": {"type": "half_sphere", "center": [0, 0, 1], "radius": 1.0}},
            {"name": "block", "material": "steel", "element_size": 0.25,
             "refinement": {"levels": levels, "around": "contact", "radius": 0.1},
             "shape": {"type": "box", "min": [-1, -1, -1], "max": [1, 1, 0]}},
        ],
        "boundary_conditions": [
            {"type": "displacement", "body": "ball", "face": "flat", "value": [0, 0, -0.002]},
            {"type": "fixed", "body": "block", "face": "z0"},
        ],
        "contacts": [{"bodies": ["ball", "block"], "type": "frictionless"}],
        "output": {"vtk": True, "plots": True, "probes": [[0, 0, -0.03]]},
    }


def test_errors_name_the_key_path(solids):
    bad = _scene()
    bad["boundary_conditions"][0]["value"] = [0, 0]
    bad["boundary_conditions"][1]["face"] = "bottom"
    bad["thickness"] = 1.0
    with pytest.raises(SceneError) as err:
        load_scene(bad, label="s.toml")
    assert "thickness" in str(err.value)
    del bad["thickness"]
    with pytest.raises(SceneError) as err:
        load_scene(bad, label="s.toml")
    assert "boundary_conditions[0].value" in str(err.value)
    bad["boundary_conditions"][0]["value"] = [0, 0, -0.002]
    with pytest.raises(SceneError) as err:
        load_scene(bad, label="s.toml")
    assert "boundary_conditions[1].face = 'bottom'" in str(err.value) and "z0" in str(err.value)


def test_output_lines_and_switches_are_checked_as_in_2d(solids):
    """A 3D scene's ``[output]`` table: a line's name used twice, a line whose ends coincide and
    a switch that is not true or false are named with their key path, as in a 2D scene."""
    line = {"name": "axis", "start": [0, 0, 0], "end": [0, 0, -0.5], "n": 20}
    for output, message in (({"lines": [line, line]}, 'line name "axis" used twice'),
                            ({"lines": [dict(line, end=[0, 0, 0])]}, "output.lines[0].end"),
                            ({"vtk": "yes"}, "output.vtk")):
        bad = _scene()
        bad["output"] = output
        with pytest.raises(SceneError) as err:
            load_scene(bad, label="s.toml")
        assert message in str(err.value), str(err.value)


def test_contact_point_found_as_the_closest_points(solids):
    scene = load_scene(_scene(), label="s.toml")
    assert scene.problem.model == "solid" and scene.problem.dim == 3
    np.testing.assert_allclose(scene.problem.contacts[0].point, [0, 0, 0], atol=1e-9)
    zones = scene.problem.body("ball").refinements
    np.testing.assert_allclose(zones[0].center, [0, 0, 0], atol=1e-9)


def test_ibfem_run_writes_the_section_7_summary(solids, tmp_path):
    from ibfem.solver.cli import main

    path = tmp_path / "ball.json"
    path.write_text(json.dumps(_scene()))
    code = main(["run", str(path), "--out", str(tmp_path / "out"), "--no-estimate"])
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    c = summary["contacts"][0]
    assert code in (0, 1)  # converged or not, the summary is written
    assert set(["axes", "semi_axes", "stick_semi_axes", "tangential_force"]) <= set(c)
    assert c["semi_axes"][0] > 0 and len(c["pressure"]["axis0"]["s"]) > 0
    assert len(summary["probes"][0]["stress"]) == 6
    np.testing.assert_allclose(summary["reactions"]["block/z0"], [0, 0, c["normal_force"]], rtol=1e-9, atol=1.0)
    assert {"ball.vtu", "block.vtu", "sections.png", "contact_0.png"} <= set(summary["files"])


def test_the_onshape_ball_on_block_example_touches_at_the_caps_pole():
    # examples/solid/onshape_ball_on_block.toml turns the CAD part cap down about the cap's pole:
    # the contact point found as the closest points of the two exact solids must be that pole, the
    # origin on the block's top, and the part's spherical face must pass through it (R = 20 mm)
    from pathlib import Path

    scene = load_scene(Path(__file__).resolve().parents[1] / "examples" / "solid" / "onshape_ball_on_block.toml")
    np.testing.assert_allclose(scene.problem.contacts[0].point, [0, 0, 0], atol=1e-9)
    part = scene.problem.body("part").profile
    probe = np.array([[0.0, 0.0, 1e-4], [0.0, 0.0, -1e-4]])  # just above / below the pole
    phi = np.asarray(part.signed_distance(probe), float)
    assert phi[0] == pytest.approx(1e-4, abs=1e-9) and phi[1] == pytest.approx(-1e-4, abs=1e-9)
