"""Faces by geometry: the face table against closed forms (areas, centroids, normals, radii), face
selectors in a scene picking the same faces as their ids (so the scene gives the same result),
ambiguous or empty selectors as errors listing the candidates, and ``ibfem info --faces`` on a
shipped CAD part."""

import copy
import math
from pathlib import Path

import numpy as np
import pytest

from ibfem.geometry.solids.face_summary import face_summaries
from ibfem.solver.io.scene import SceneError, load_scene, scene_from_dict

ROOT = Path(__file__).resolve().parents[1]


def _scene(faces):
    """A coarse block pressed on its top, held on its bottom, sliding on two sides."""
    bottom, top, x0, y0 = faces
    return {
        "name": "block", "model": "solid",
        "materials": [{"name": "steel", "youngs_modulus": 2e11, "poissons_ratio": 0.3}],
        "bodies": [{"name": "b", "material": "steel", "element_size": 0.5,
                    "shape": {"type": "box", "min": [0, 0, 0], "max": [1, 1, 1]}}],
        "boundary_conditions": [
            {"body": "b", "face": bottom, "type": "sliding"},
            {"body": "b", "face": x0, "type": "sliding"},
            {"body": "b", "face": y0, "type": "sliding"},
            {"body": "b", "face": top, "type": "pressure", "value": 1e6},
        ],
    }


def test_the_face_table_of_a_half_cylinder_and_a_box():
    scene = scene_from_dict(_scene(["z_min", "z_max", "x_min", "y_min"]))
    table = {f["id"]: f for f in face_summaries(scene.problem.bodies[0].profile)}
    assert table["z_max"]["type"] == "plane" and table["z_max"]["area"] == pytest.approx(1.0)
    assert np.allclose(table["z_max"]["normal"], [0, 0, 1]) and np.allclose(table["z_max"]["centroid"], [0.5, 0.5, 1])
    from ibfem.geometry.solids.build import solid_from_dict

    half = solid_from_dict({"type": "half_cylinder", "center": [0, 0, 1], "axis": [1, 0, 0], "radius": 0.5,
                            "length": 2.0, "side": "below"})
    table = {f["id"]: f for f in face_summaries(half)}
    arc = table["arc"]
    assert arc["type"] == "cylinder" and arc["radius"] == pytest.approx(0.5)
    assert abs(np.dot(arc["axis"], [1, 0, 0])) == pytest.approx(1.0)
    assert arc["area"] == pytest.approx(math.pi * 0.5 * 2.0, rel=1e-9)
    # the centroid of a half-cylinder's arc lies 2 R / pi below the axis
    assert np.allclose(arc["centroid"], [0, 0, 1 - 2 * 0.5 / math.pi], atol=1e-9)
    assert np.allclose(table["flat"]["normal"], [0, 0, 1]) and table["flat"]["area"] == pytest.approx(2.0)


def test_a_scene_with_selectors_is_the_scene_with_ids():
    by_id = scene_from_dict(_scene(["z_min", "z_max", "x_min", "y_min"]))
    selectors = [{"normal": [0, 0, -1]}, {"nearest": [0.5, 0.5, 1.2]}, {"type": "plane", "normal": [-1, 0, 0]},
                 {"nearest": [0.3, -0.1, 0.5]}]
    by_geometry = scene_from_dict(_scene(selectors))
    assert by_geometry.problem.boundary_conditions == by_id.problem.boundary_conditions
    from ibfem.solver.solving import solve

    a, b = solve(by_id.problem), solve(by_geometry.problem)
    for key in a.reactions:
        assert np.array_equal(a.reactions[key], b.reactions[key])
    # the sliding bottom carries the pressure's resultant: 1e6 Pa on 1 m^2
    assert a.reactions["b/z_min"][2] == pytest.approx(1e6, rel=1e-9)


def test_ambiguous_and_unmatched_selectors_list_the_candidates():
    data = _scene([{"type": "plane"}, "z_max", "x_min", "y_min"])
    with pytest.raises(SceneError) as err:
        scene_from_dict(data)
    text = str(err.value)
    assert "boundary_conditions[0].face" in text and "6 faces match it" in text and "z_min (plane" in text
    data = _scene([{"type": "cylinder", "radius": 0.01}, "z_max", "x_min", "y_min"])
    with pytest.raises(SceneError) as err:
        scene_from_dict(data)
    assert "no face matches it" in str(err.value) and "x_max (plane, area 1 m^2" in str(err.value)
    data = _scene([{"radius": -1.0}, "z_max", "x_min", "y_min"])
    with pytest.raises(SceneError) as err:
        scene_from_dict(data)
    assert "radius" in str(err.value)


def test_selectors_on_a_cad_part():
    from ibfem.geometry.solids.part_solid import PartSolid
    from ibfem.importers.onshape import load_part
    from ibfem.solver.io.face_selectors import select_face

    part = PartSolid(load_part(ROOT / "fixtures" / "onshape" / "cone_sphere"), "JIP")  # a cone with a spherical cap
    table = {f["id"]: f for f in face_summaries(part)}
    cap = select_face(part, {"type": "sphere", "radius": 0.02}, list(table.values()))
    assert table[cap]["type"] == "sphere" and table[cap]["radius"] == pytest.approx(0.02)
    # the cap's sphere is centred at [0, -0.04, 0.02]: its pole along -y is the part's end
    assert select_face(part, {"nearest": [0.0, -0.061, 0.02]}, list(table.values())) == cap
    flat = select_face(part, {"normal": [0, 1, 0]}, list(table.values()))
    assert table[flat]["type"] == "plane" and np.allclose(table[flat]["normal"], [0, 1, 0])


def test_info_lists_every_face_with_its_geometry(capsys):
    from ibfem.solver.cli import main

    assert main(["info", str(ROOT / "fixtures" / "onshape" / "cone_sphere"), "--faces"]) == 0
    out = capsys.readouterr().out
    header = next(line for line in out.splitlines() if line.startswith("body") and "centroid" in line)
    assert "normal / axis" in header and "radius" in header
    rows = [line.split() for line in out.splitlines()[out.splitlines().index(header) + 1:] if line.strip()]
    assert {r[2] for r in rows} >= {"sphere", "cone", "plane"}
    assert all(float(r[3]) > 0 for r in rows)  # every face has its area
