"""The scene side: bad or unusual scene files end in one SceneError line naming the
file, the key path and the value, before anything is built (classes 2, 6, 7, 9 and 12; each
with the issue's reproducer and a variant). The truths are geometric facts of the inputs (where
the boundaries are, which point is a corner, which value is a typo), not earlier outputs."""

from __future__ import annotations

import copy
import json
import shutil
import tomllib
from pathlib import Path

import pytest

from ibfem.solver.io.scene import MAX_MAGNITUDE, SceneError, load_scene

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
CYLINDERS = tomllib.loads((EXAMPLES / "cylinder_on_cylinder_frictionless.toml").read_text())
WEDGE = tomllib.loads((EXAMPLES / "cylinder_on_wedge_frictionless.toml").read_text())
ONSHAPE = ROOT / "fixtures" / "onshape" / "half_cylinder_on_block"


def errors(data: dict, label: str = "s.toml") -> str:
    with pytest.raises(SceneError) as err:
        load_scene(data, label=label, base_dir=EXAMPLES)
    text = str(err.value)
    assert "Traceback" not in text and all(line.startswith(label + ": ") for line in text.splitlines())
    return text


def cylinders(**solver) -> dict:
    data = copy.deepcopy(CYLINDERS)
    data["solver"].update(solver)
    return data


# --- class 2: a mistyped contact point -------------------------------------------------------


@pytest.mark.parametrize("point", [[0.0, 0.5], [1.9, 0.0], [100.0, 100.0]])
def test_class2_point_off_the_boundaries(point):
    data = cylinders()
    data["contacts"][0]["point"] = point
    text = errors(data)
    assert "contacts[0].point" in text and "nearest boundary point" in text


def test_class2_point_near_a_boundary_but_not_where_the_bodies_touch():
    """Variant: the cylinder's lowest point (0, 0.0353) lies on the cylinder, 0.035 m above the
    groove (within 2 coarse elements of it), while the bodies touch at (sin 15deg, sin^2 15deg /
    cos 15deg): this point converged with N = 0 before."""
    data = copy.deepcopy(WEDGE)
    data["contacts"][0]["point"] = [0.0, 0.035276180410083]
    text = errors(data)
    assert "contacts[0].point" in text and "not where the bodies are closest" in text
    assert "[0.258819, 0.0693504]" in text  # the touching point, from the geometry above


def test_class2_the_exact_point_and_a_slightly_rounded_one_load():
    data = copy.deepcopy(WEDGE)
    data["contacts"][0]["point"] = [0.2588, 0.0694]  # 4 digits
    assert load_scene(data, label="s.toml", base_dir=EXAMPLES).problem.contacts[0].point_given


# --- class 6: grids that cannot fit ----------------------------------------------------------


@pytest.mark.parametrize("size, levels", [(1e-4, None), (1e-300, None), (None, 12)])
def test_class6_grids_beyond_memory_are_refused_with_the_need(size, levels):
    data = cylinders()
    if size:
        data["bodies"][0]["element_size"] = size
    if levels:
        data["bodies"][0]["refinement"] = [{"levels": levels, "around": "contact", "radius": 0.3}]
    text = errors(data)
    assert "the grids would need" in text and "GB" in text and "coarsen" in text and "nan" not in text


def _scaled_cache(tmp_path: Path, factor: float) -> Path:
    """The fixture's cache with every length multiplied by ``factor`` (metres -> millimetres)."""
    lengths = {"vertices", "origin", "radius", "minorRadius", "majorRadius", "facetPoints", "controlPoints",
               "point", "x", "y", "z", "start", "end", "center"}
    directions = {"normal", "normals", "axis", "direction", "xDir", "vertexNormals", "refDirection", "knots"}

    def scale(v, on=False):
        if isinstance(v, dict):
            return {k: x if k in directions else scale(x, on or k in lengths) for k, x in v.items()}
        if isinstance(v, list):
            return [scale(x, on) for x in v]
        return v * factor if on and isinstance(v, float) else v

    out = tmp_path / "mm"
    shutil.copytree(ONSHAPE, out)
    for name in ("tessellatedfaces.json", "bodydetails.json", "tessellatededges.json"):
        (out / name).write_text(json.dumps(scale(json.loads((out / name).read_text()))))
    return out


def test_class6_an_onshape_cache_in_millimetres_with_the_demos_grid(tmp_path):
    data = tomllib.loads((EXAMPLES / "onshape" / "half_cylinder_on_block.toml").read_text())
    cache = _scaled_cache(tmp_path, 1000.0)
    for body in data["bodies"]:
        body["shape"]["path"] = str(cache)
        body["shape"]["section"]["origin"] = [0.0, 0.0, 10.0]
    text = errors(data)
    assert "the grids would need" in text


def test_class6_check_prints_the_estimate(tmp_path, capsys):
    from ibfem.solver.cli import main

    assert main(["run", str(EXAMPLES / "cylinder_on_cylinder_frictionless.toml"), "--check"]) == 0
    out = capsys.readouterr().out
    assert "cells" in out and "dofs" in out and "GB" in out


# --- class 7: --check refuses what the run rejects -------------------------------------------


@pytest.mark.parametrize("key, value", [("band_fraction", 0.0), ("band_fraction", -0.25), ("consistency", -1.0),
                                        ("consistency", 2.0), ("chord_tolerance", 0.0), ("chord_tolerance", -1e-3),
                                        ("grid_offset", [2.0, 0.0]), ("grid_offset", [0.1, 0.1, 0.1]),
                                        ("load_steps", 0), ("max_iterations", 0), ("fictitious_stiffness", 1.5),
                                        # upper ends: the run converged 0.15 % off (band 1e6 cells) or not at all
                                        # (band 10 cells, chord 10 m); fictitious stiffness 0.99 moved N by 1.5 %
                                        ("band_fraction", 10.0), ("chord_fraction", 2.0), ("chord_tolerance", 10.0),
                                        ("fictitious_stiffness", 0.99)])
def test_class7_solver_options_out_of_range(key, value):
    assert f"solver.{key} = " in errors(cylinders(**{key: value}))


@pytest.mark.parametrize("key, value", [("formulation", "bnad"), ("formulation", "ellipse"), ("order", 0),
                                        ("width_update", "fast"), ("window", 0.0)])
def test_class7_contact_options_out_of_range(key, value):
    data = cylinders()
    data["contacts"][0][key] = value
    assert f"contacts[0].{key} = " in errors(data)


def test_class7_contact_point_at_a_corner():
    """The groove bottom (0, 0) is the wedge's corner between 'face' and 'symmetry': the run
    refused it ('sits at the end of edge' / 'ends inside the candidate region')."""
    data = copy.deepcopy(WEDGE)
    data["contacts"][0]["point"] = [0.0, 0.0]
    assert "contacts[0].point" in errors(data)


def test_class7_bodies_closest_at_a_corner():
    """Variant without a point: a square turned 45 degrees whose corner (0, 0) rests on a block:
    the closest points are the corner, which the run cannot take."""
    data = copy.deepcopy(CYLINDERS)
    data["bodies"][0]["shape"] = {"type": "polygon", "points": [[0.0, 0.0], [0.5, 0.5], [0.0, 1.0], [-0.5, 0.5]],
                                  "edge_names": ["lower_right", "upper_right", "flat", "lower_left"]}
    data["bodies"][1]["shape"] = {"type": "rectangle", "min": [-1.0, -1.0], "max": [1.0, 0.0]}
    data["boundary_conditions"] = [
        {"type": "displacement", "body": "upper", "edge": "upper_right", "value": [0.0, -1e-4]},
        {"type": "fixed", "body": "lower", "edge": "bottom"}]
    data["contacts"][0].pop("point")
    data["output"] = {"vtk": False}
    text = errors(data)
    assert "contacts[0]: the closest points" in text and "corner of body 'upper'" in text


# --- class 12 (and 9): values that are not what they look like ---------------------------------


def write(tmp_path: Path, text: str | bytes, name: str = "s.toml") -> Path:
    path = tmp_path / name
    path.write_bytes(text if isinstance(text, bytes) else text.encode("utf-8"))
    return path


def file_error(path: Path) -> str:
    with pytest.raises(SceneError) as err:
        load_scene(path)
    assert str(err.value).startswith(path.name + ": ")
    return str(err.value)


SOURCE = (EXAMPLES / "cylinder_on_cylinder_frictionless.toml").read_text()


@pytest.mark.parametrize("name, value", [("s.toml", "9" * 5000), ("s.json", "9" * 5000),
                                         ("s.toml", "[" * 100_000 + "]" * 100_000)])
def test_class12_huge_integers_and_deep_nesting_in_the_file(tmp_path, name, value):
    if name.endswith(".json"):
        text = '{"solver": {"load_steps": ' + value + "}}"
    else:
        text = SOURCE.replace("load_steps = 5", "load_steps = " + value)
    assert "cannot read" in file_error(write(tmp_path, text, name)) or "nested" in file_error(write(tmp_path, text, name))


def test_class12_nesting_the_parser_reads_is_refused_with_its_key():
    data = cylinders()
    deep: list = [0.0, 0.0]
    for _ in range(200):
        deep = [deep]
    data["solver"]["grid_offset"] = deep
    assert "solver.grid_offset" in errors(data) and "nested more than" in errors(data)


@pytest.mark.parametrize("where, value", [("exact_geometry", "yes"), ("exact_geometry", 1), ("load_steps", "5"),
                                          ("band_fraction", "0.25")])
def test_class12_no_coercion_of_strings_or_numbers(where, value):
    assert f"solver.{where} = " in errors(cylinders(**{where: value}))


@pytest.mark.parametrize("mutate, key", [
    (lambda d: d["bodies"][0].update(material=["steel"]), "bodies[0].material"),
    (lambda d: d["boundary_conditions"][0].update(edge=["flat"]), "boundary_conditions[0].edge"),
    (lambda d: d["bodies"][0]["shape"].update(type=["disk"]), "bodies[0].shape"),
])
def test_class12_lists_where_strings_belong(mutate, key):
    data = cylinders()
    mutate(data)
    text = errors(data)
    assert key in text and "unhashable" not in text


@pytest.mark.parametrize("steps", [10**12, 10_001])
def test_class12_load_steps_has_an_upper_bound(steps):
    assert "solver.load_steps = " in errors(cylinders(load_steps=steps))


@pytest.mark.parametrize("mutate, key", [
    (lambda d: d["bodies"][0].update(shape={"type": "half_ellipse", "center": [0, 1], "semi_axes": [1e300, 1],
                                             "side": "below"}), "bodies[0].shape.semi_axes[0]"),
    (lambda d: d["materials"][0].update(youngs_modulus=1e300), "materials[0].youngs_modulus"),
    (lambda d: d["output"].update(probes=[[1e300, 0.0]]), "output.probes[0][0]"),
    (lambda d: d.update(thickness=1e21), "thickness"),
])
def test_class12_values_beyond_the_scenes_range(mutate, key):
    data = cylinders()
    mutate(data)
    text = errors(data)
    assert f"{key} = " in text and f"{MAX_MAGNITUDE:g}" in text


def test_class12_a_utf8_bom_is_read(tmp_path):
    scene = load_scene(write(tmp_path, "\ufeff" + SOURCE))
    assert scene.problem.bodies[0].name == "upper"
    json_scene = load_scene(write(tmp_path, "\ufeff" + json.dumps(CYLINDERS), "s.json"))
    assert json_scene.problem.bodies[1].name == "lower"


def test_class9_12_a_non_utf8_file_is_named_with_the_offset(tmp_path):
    raw = SOURCE.replace("Theory", "Th\u00e9orie").encode("latin-1")
    text = file_error(write(tmp_path, raw))
    assert "not a UTF-8 text file" in text and f"offset {raw.index(0xE9)}" in text


# --- class 9, scene side: Onshape caches without a usable tessellation ---------------------------


def _first_face(faces):
    return (faces if isinstance(faces, list) else faces["bodies"])[0]["faces"][0]


def _damage(faces: dict, details: dict, how: str):
    if how == "empty":
        return [], details
    if how == "no_facets":
        for body in faces["bodies"]:
            for face in body["faces"]:
                face["facets"] = []
    if how == "no_bodies":
        faces["bodies"] = []
    if how == "no_details":
        details["bodies"] = []
    if how == "vertex":
        facet = _first_face(faces)["facets"][0]
        facet["vertices"][0] = [1e308, 0.0, 0.0]
    if how == "radius":
        face = next(f for f in details["bodies"][0]["faces"] if "radius" in (f.get("surface") or {}))
        face["surface"]["radius"] = 1e308
    return faces, details


@pytest.mark.parametrize("how", ["empty", "no_facets", "no_bodies", "no_details", "vertex", "radius", "latin1"])
def test_class9_damaged_onshape_caches_are_named(tmp_path, how):
    cache = tmp_path / "cache"
    shutil.copytree(ONSHAPE, cache)
    if how == "latin1":
        (cache / "bodydetails.json").write_bytes('{"name": "pi\u00e8ce"}'.encode("latin-1"))
    else:
        faces = json.loads((cache / "tessellatedfaces.json").read_text())
        details = json.loads((cache / "bodydetails.json").read_text())
        faces, details = _damage(faces, details, how)
        (cache / "tessellatedfaces.json").write_text(json.dumps(faces))
        (cache / "bodydetails.json").write_text(json.dumps(details))
    data = tomllib.loads((EXAMPLES / "onshape" / "half_cylinder_on_block.toml").read_text())
    for body in data["bodies"]:
        body["shape"]["path"] = str(cache)
    text = errors(data)
    assert "bodies[" in text and ("tessellatedfaces.json" in text or "bodydetails.json" in text)
    assert not any(word in text for word in ("AttributeError", "IndexError", "Overflow", "codec"))


@pytest.mark.parametrize("name", ["x\ny", "x\u2028y", "x\x1cy", "x\ry"])
def test_class12_a_line_break_in_a_name_keeps_one_line_per_problem(name):
    """Found by the fuzz campaign: an edge name with a line break split an error into lines that
    did not name the file."""
    data = cylinders()
    data["bodies"][0]["shape"] = {"type": "profile", "edges": [
        {"name": name, "type": "arc", "center": [0.0, 1.0], "radius": 1.0, "start_angle": 180.0, "end_angle": 360.0},
        {"name": "flat", "type": "line", "start": [1.0, 1.0], "end": [-1.0, 1.0]}]}
    data["boundary_conditions"][0]["edge"] = "top"
    text = errors(data)
    assert len(text.splitlines()) == len([p for p in text.split("\n")]) and "boundary_conditions[0].edge" in text


@pytest.mark.parametrize("example, bad", [
    ("step/half_cylinder_on_block.toml", ["a" * 300, "yes"]),  # make fuzz: OSError 'File name too long', exit 5
    ("step/half_cylinder_on_block.toml", "a" * 5000),
    ("solid/onshape_ball_on_block.toml", "b" * 5000),
])
def test_a_cad_path_the_system_cannot_open_is_a_scene_error(example, bad):
    import copy
    import tomllib
    from pathlib import Path

    from ibfem.solver.io.scene import SceneError, scene_from_dict

    path = Path(__file__).resolve().parents[1] / "examples" / example
    data = copy.deepcopy(tomllib.loads(path.read_text(encoding="utf-8")))
    data["bodies"][0]["shape"]["path"] = bad
    with pytest.raises(SceneError, match=r"bodies\[0\]\.shape.*path.*cannot read"):
        scene_from_dict(data, label="s.toml", base_dir=path.parent)
