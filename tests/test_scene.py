"""Scene files: loading TOML and JSON into a Problem, defaults, the error
messages (file, key path, value), and the rigid-body check against hand-derived answers."""

import copy
import sys
import json
import math
from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.model import problem as pb
from ibfem.solver.io.scene import SceneError, load_scene, rigid_body_modes, scene_from_dict

ROOT = Path(__file__).resolve().parents[1]

# the scene format's own example, verbatim
SPEC_EXAMPLE = """
name = "cylinder on flat, partial slip"
model = "plane_strain"             # or "plane_stress"
thickness = 1.0

[solver]
load_steps = 10
tolerance = 1e-10                  # residual-work ratio
max_iterations = 100
exact_geometry = true              # false: boundary integrals on the tessellation only

[[materials]]
name = "steel"
youngs_modulus = 2.0e11
poissons_ratio = 0.3

[[bodies]]
name = "cylinder"
material = "steel"
element_size = 0.05                # background grid spacing
refinement = [{ levels = 4, around = "contact", radius = 0.3 }]
shape = { type = "half_disk", center = [0.0, 1.0], radius = 1.0, side = "below" }

[[bodies]]
name = "block"
material = "steel"
element_size = 0.05
refinement = [{ levels = 4, around = "contact", radius = 0.3 }]
shape = { type = "rectangle", min = [-2.0, -2.0], max = [2.0, 0.0] }

[[boundary_conditions]]
body = "cylinder"
edge = "flat"
type = "displacement"
value = [2.0e-4, -1.0e-3]          # a component may be the string "free"

[[boundary_conditions]]
body = "block"
edge = "bottom"
type = "fixed"

[[contacts]]
bodies = ["cylinder", "block"]
type = "frictional"                # "tied", "frictionless" or "frictional"
friction = 0.3
point = [0.0, 0.0]                 # optional: found as the closest points when omitted

[output]
vtk = true
plots = true
probes = [[0.0, -0.05]]
lines = [{ name = "subsurface", start = [0.0, 0.0], end = [0.0, -0.3], n = 200 }]
"""

STEEL = {"name": "steel", "youngs_modulus": 2e11, "poissons_ratio": 0.3}


def plate(rotate=0.0, conditions=None):
    """A 2 x 1 plate (turned by ``rotate`` degrees), sliding on bottom and left, pulled on the right."""
    return {
        "materials": [dict(STEEL)],
        "bodies": [{"name": "plate", "material": "steel", "element_size": 0.1,
                    "shape": {"type": "rectangle", "min": [0, 0], "max": [2, 1], "rotate_deg": rotate}}],
        "boundary_conditions": conditions if conditions is not None else [
            {"body": "plate", "edge": "bottom", "type": "sliding"},
            {"body": "plate", "edge": "left", "type": "sliding"},
            {"body": "plate", "edge": "right", "type": "traction", "value": [1e6, 0.0]},
        ],
    }


def quarter_annulus(rotate):
    """Lame quarter annulus as a `profile` shape: symmetry edges x0 (on the x axis) and y0."""
    return {"type": "profile", "rotate_deg": rotate, "edges": [
        {"name": "x0", "type": "line", "start": [1, 0], "end": [2, 0]},
        {"name": "outer", "type": "arc", "center": [0, 0], "radius": 2, "start_angle": 0, "end_angle": 90},
        {"name": "y0", "type": "line", "start": [0, 2], "end": [0, 1]},
        {"name": "inner", "type": "arc", "center": [0, 0], "radius": 1, "start_angle": 90, "end_angle": 0},
    ]}


def errors_of(data, label="scene.toml"):
    with pytest.raises(SceneError) as info:
        scene_from_dict(data, label=label)
    return info.value.problems


def test_spec_example_loads_into_problem(tmp_path):
    path = tmp_path / "spec_example.toml"
    path.write_text(SPEC_EXAMPLE)
    scene = load_scene(path)
    p = scene.problem
    assert p.name == "cylinder on flat, partial slip" and p.model == "plane_strain" and p.thickness == 1.0
    assert [b.name for b in p.bodies] == ["cylinder", "block"]
    cyl = p.body("cylinder")
    assert cyl.material == pb.Material("steel", 2.0e11, 0.3) and cyl.element_size == 0.05
    # around = "contact": resolved once, at the contact point the solver will use
    (ref,) = cyl.refinements
    assert (ref.levels, ref.radius, ref.around_contact) == (4, 0.3, True)
    assert np.array_equal(ref.center, [0.0, 0.0])
    assert set(cyl.profile.edge_names) == {"arc", "flat"}
    assert p.boundary_conditions == (
        pb.Displacement("cylinder", "flat", (2.0e-4, -1.0e-3)),
        pb.Fixed("block", "bottom"),
    )
    (c,) = p.contacts
    assert c.bodies == ("cylinder", "block") and c.type == "frictional" and c.friction == 0.3
    assert np.array_equal(c.point, [0.0, 0.0])
    assert p.options == pb.SolverOptions(10, 1e-10, 100, True)
    out = scene.output
    assert out.vtk and out.plots and out.probes == [(0.0, -0.05)]
    assert out.lines[0].name == "subsurface" and out.lines[0].n == 200


def test_json_with_the_same_structure_gives_the_same_problem(tmp_path):
    import tomllib

    data = tomllib.loads(SPEC_EXAMPLE)
    (tmp_path / "a.toml").write_text(SPEC_EXAMPLE)
    (tmp_path / "a.json").write_text(json.dumps(data))
    a, b = load_scene(tmp_path / "a.toml"), load_scene(tmp_path / "a.json")
    assert a.spec == b.spec
    assert a.problem.boundary_conditions == b.problem.boundary_conditions
    assert a.problem.options == b.problem.options


def test_defaults_follow_the_spec():
    scene = scene_from_dict(plate(), label="plain.toml")
    p = scene.problem
    assert p.options == pb.SolverOptions(load_steps=10, tolerance=1e-10, max_iterations=100, exact_geometry=True)
    assert p.thickness == 1.0 and p.model == "plane_strain"
    assert p.name == "plain"  # the file name when the scene has no name
    assert scene.output.vtk is True and scene.output.plots is False
    assert p.body("plate").refinements == ()


def test_refinement_as_single_table_and_point():
    data = plate()
    data["bodies"][0]["refinement"] = {"levels": 3, "around": [1.0, 0.5], "radius": 0.2}
    (r,) = scene_from_dict(data).problem.body("plate").refinements
    assert r.levels == 3 and r.radius == 0.2 and np.array_equal(r.center, [1.0, 0.5])


def test_free_components_become_none():
    data = plate(conditions=[
        {"body": "plate", "edge": "bottom", "type": "displacement", "value": ["free", 0.0]},
        {"body": "plate", "edge": "left", "type": "displacement", "value": [0.0, "free"]},
    ])
    bcs = scene_from_dict(data).problem.boundary_conditions
    assert bcs == (pb.Displacement("plate", "bottom", (None, 0.0)), pb.Displacement("plate", "left", (0.0, None)))


def _set(path, value):
    def mutate(d):
        *head, last = path
        for k in head:
            d = d[k]
        d[last] = value
    return mutate


@pytest.mark.parametrize(
    "mutate, expected",
    [
        (_set(("bodies", 0, "material"), "stel"), 'bodies[0].material = "stel": unknown material (known: steel)'),
        (_set(("materials", 0, "poissons_ratio"), 0.5), "materials[0].poissons_ratio = 0.5: must lie in (-1, 0.5)"),
        (_set(("materials", 0, "poissons_ratio"), -1.0), "materials[0].poissons_ratio = -1.0: must lie in (-1, 0.5)"),
        (_set(("materials", 0, "youngs_modulus"), 0), "materials[0].youngs_modulus = 0: must be positive"),
        (_set(("materials", 0, "youngs_modulus"), "2e11 Pa"), 'materials[0].youngs_modulus = "2e11 Pa"'),
        (_set(("bodies", 0, "elemnt_size"), 0.1), "bodies[0].elemnt_size = 0.1: unknown key (known: name, material, element_size, refinement, shape)"),
        (_set(("bodies", 0, "element_size"), -0.1), "bodies[0].element_size = -0.1: input should be greater than 0"),
        (_set(("bodies", 0, "element_size"), 0.6), "bodies[0].element_size = 0.6: grid coarser than the body"),
        (_set(("boundary_conditions", 0, "edge"), "bttom"), 'boundary_conditions[0].edge = "bttom": body "plate" has no such edge (known: bottom, right, top, left)'),
        (_set(("boundary_conditions", 0, "body"), "plat"), 'boundary_conditions[0].body = "plat": unknown body (known: plate)'),
        (_set(("boundary_conditions", 0, "type"), "slip"), 'boundary_conditions[0].type = "slip": unknown type (known: fixed, displacement, sliding, traction, pressure, body_force, reference_point)'),
        (_set(("boundary_conditions", 2, "value"), [1e6]), "boundary_conditions[2].value = [1000000.0]: too few components"),
        (_set(("boundary_conditions", 2, "vale"), 1), "boundary_conditions[2].vale = 1: unknown key (known: type, body, edge, value, path, axes)"),
        (_set(("boundary_conditions", 0), {"body": "plate", "edge": "bottom", "type": "displacement", "value": ["fre", 0]}),
         'boundary_conditions[0].value[0] = "fre": must be a number or "free"'),
        (_set(("boundary_conditions", 0), {"body": "plate", "edge": "bottom", "type": "displacement", "value": ["free", "free"]}),
         'boundary_conditions[0].value = ["free", "free"]: both components free'),
        (_set(("boundary_conditions", 2), {"body": "plate", "edge": "left", "type": "fixed"}),
         'boundary_conditions[2].edge = "left": edge plate/left already has an essential condition (boundary_conditions[1])'),
        (_set(("bodies", 0, "refinement"), [{"levels": 0, "around": [0, 0], "radius": 1}]), "bodies[0].refinement[0].levels = 0"),
        (_set(("bodies", 0, "refinement"), [{"levels": 2, "around": [0, 0], "radius": 0}]), "bodies[0].refinement[0].radius = 0"),
        (_set(("bodies", 0, "refinement"), [{"levels": 2, "around": "contacts", "radius": 1}]),
         'bodies[0].refinement[0].around = "contacts": must be "contact" or a point [x, y]'),
        (_set(("bodies", 0, "refinement"), [{"levels": 2, "around": "contact", "radius": 1}]),
         'bodies[0].refinement[0].around = "contact": body "plate" has no contact'),
        (_set(("bodies", 0, "shape"), {"type": "rectangle", "min": [0, 0], "max": [0, 1]}), "bodies[0].shape.max must exceed"),
        (_set(("bodies", 0, "shape"), {"type": "square", "min": [0, 0]}), "bodies[0].shape.type must be one of onshape, "),
        (_set(("model",), "plane"), "model = \"plane\": input should be 'plane_strain', 'plane_stress', 'solid'"),
        (_set(("thickness",), 0), "thickness = 0: input should be greater than 0"),
        (_set(("solver",), {"load_steps": 0}), "solver.load_steps = 0"),
        (_set(("solver",), {"tolerance": float("nan")}), "solver.tolerance = NaN: input should be a finite number"),
        (_set(("output",), {"probes": [[5.0, 5.0]]}), "output.probes[0] = [5.0, 5.0]: outside every body"),
        (_set(("output",), {"lines": [{"name": "a", "start": [0, 0], "end": [0, 0]}]}), "output.lines[0].end = [0, 0]: start and end coincide"),
        (_set(("output",), {"lines": [{"name": "a", "start": [0, 0], "end": [1, 0], "n": 1}]}), "output.lines[0].n = 1"),
        (_set(("materials",), [dict(STEEL), dict(STEEL)]), 'materials[1].name = "steel": duplicate name (also materials[0])'),
        (_set(("colour",), "red"), 'colour = "red": unknown key (known: name, description, model,'),
    ],
)
def test_errors_name_file_key_path_and_value(mutate, expected):
    data = plate()
    mutate(data)
    problems = errors_of(data, label="scene.toml")
    assert any(p.startswith("scene.toml: ") and expected in p for p in problems), problems
    assert all("\n" not in p for p in problems)


def test_contact_errors():
    data = plate()
    data["bodies"].append({"name": "pin", "material": "steel", "element_size": 0.05,
                           "shape": {"type": "disk", "center": [1.0, 1.5], "radius": 0.5}})
    data["boundary_conditions"].append({"body": "pin", "edge": "boundary", "type": "fixed"})
    data["contacts"] = [{"bodies": ["pin", "plate"], "type": "frictional"}]
    assert any('contacts[0].friction: type = "frictional" needs friction > 0' in p for p in errors_of(data))
    data["contacts"] = [{"bodies": ["pin", "plate"], "type": "frictional", "friction": -0.1}]
    assert any("contacts[0].friction = -0.1: input should be greater than or equal to 0" in p for p in errors_of(data))
    data["contacts"] = [{"bodies": ["pin", "plate"], "type": "frictionless", "friction": 0.3}]
    assert any('contacts[0].friction = 0.3: only used by type = "frictional"' in p for p in errors_of(data))
    data["contacts"] = [{"bodies": ["pin", "plates"], "type": "tied"}]
    assert any('contacts[0].bodies[1] = "plates": unknown body (known: plate, pin)' in p for p in errors_of(data))
    data["contacts"] = [{"bodies": ["pin", "pin"], "type": "tied"}]
    assert any("contacts[0].bodies = [\"pin\", \"pin\"]: a contact needs two different bodies" in p for p in errors_of(data))
    data["contacts"] = [{"bodies": ["pin", "plate"], "type": "tied"}, {"bodies": ["plate", "pin"], "type": "tied"}]
    assert any("contacts[0].point: missing" in p and "have 2 contacts" in p for p in errors_of(data))


def test_file_errors(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("name = \n")
    with pytest.raises(SceneError, match=r"^bad.toml: invalid TOML"):
        load_scene(bad)
    with pytest.raises(SceneError, match="cannot read scene file"):
        load_scene(tmp_path / "missing.toml")
    (tmp_path / "bad.json").write_text("{")
    with pytest.raises(SceneError, match=r"^bad.json: invalid JSON"):
        load_scene(tmp_path / "bad.json")


def test_onshape_shape_errors_name_the_key(monkeypatch):
    data = plate()
    data["bodies"][0]["shape"] = {"type": "onshape", "path": "fixtures/onshape/none", "face": "JHD"}
    (msg,) = errors_of(data)
    assert msg.startswith("scene.toml: bodies[0].shape.path: ") and "none" in msg
    # without the importer: one clear line, no traceback
    import ibfem.importers.onshape
    from ibfem import importers

    monkeypatch.setitem(sys.modules, "ibfem.importers.onshape.profile", None)
    monkeypatch.delattr(importers.onshape, "profile", raising=False)
    (msg,) = errors_of(data)
    assert msg.startswith("scene.toml: bodies[0].shape") and "needs the Onshape importer" in msg


# --- rigid-body motion -------------------------------------------------------------------


def rigid_error(data):
    try:
        scene_from_dict(data, label="scene.toml")
    except SceneError as err:
        hits = [p for p in err.problems if "rigid-body motion" in p]
        assert hits == err.problems, err.problems
        return hits
    return []


@pytest.mark.parametrize("angle", [0.0, 37.0, -120.0])
def test_sliding_on_two_perpendicular_edges_holds_a_turned_plate(angle):
    assert rigid_error(plate(angle)) == []


@pytest.mark.parametrize("angle", [0.0, 37.0])
def test_sliding_on_one_edge_leaves_the_translation_along_it(angle):
    data = plate(angle, conditions=[{"body": "plate", "edge": "bottom", "type": "sliding"}])
    (msg,) = rigid_error(data)
    assert msg.startswith('scene.toml: bodies[0].name = "plate": rigid-body motion not prevented')
    d = [math.cos(math.radians(angle)), math.sin(math.radians(angle))]
    got = [float(v) for v in msg.split("translation along [")[1].split("]")[0].split(",")]
    assert abs(abs(np.dot(got, d)) - 1.0) < 1e-3  # along the (turned) bottom edge


def test_sliding_all_round_a_disk_leaves_the_rotation_about_its_centre():
    data = {"materials": [dict(STEEL)],
            "bodies": [{"name": "disk", "material": "steel", "element_size": 0.1,
                        "shape": {"type": "disk", "center": [0.3, -0.7], "radius": 1.0}}],
            "boundary_conditions": [{"body": "disk", "edge": "boundary", "type": "sliding"}]}
    (msg,) = rigid_error(data)
    assert "free rotation about [0.3, -0.7]" in msg


@pytest.mark.parametrize("angle", [0.0, 23.0, 200.0])
def test_lame_quarter_annulus_with_inclined_symmetry_edges_is_held(angle):
    data = {"materials": [dict(STEEL)],
            "bodies": [{"name": "ring", "material": "steel", "element_size": 0.02, "shape": quarter_annulus(angle)}],
            "boundary_conditions": [
                {"body": "ring", "edge": "x0", "type": "sliding"},
                {"body": "ring", "edge": "y0", "type": "sliding"},
                {"body": "ring", "edge": "inner", "type": "pressure", "value": 1e8}]}
    assert rigid_error(data) == []
    # one symmetry edge only: the ring may slide along it
    data["boundary_conditions"].pop(1)
    (msg,) = rigid_error(data)
    d = [math.cos(math.radians(angle)), math.sin(math.radians(angle))]
    got = [float(v) for v in msg.split("translation along [")[1].split("]")[0].split(",")]
    assert abs(abs(np.dot(got, d)) - 1.0) < 1e-3


def test_one_held_component_on_one_straight_edge_is_not_enough():
    data = plate(conditions=[{"body": "plate", "edge": "bottom", "type": "displacement", "value": ["free", -1e-4]}])
    (msg,) = rigid_error(data)
    assert "translation along [1, 0]" in msg or "translation along [-1, -0]" in msg or "translation along [-1, 0]" in msg
    data = plate(conditions=[{"body": "plate", "edge": "bottom", "type": "displacement", "value": [0.0, -1e-4]}])
    assert rigid_error(data) == []


def two_cylinders(contact_type, top_conditions, friction=None):
    """The third validation scene's arrangement: R1 = R2 = 1, top half disk on a bottom half disk."""
    contact = {"bodies": ["top", "bottom"], "type": contact_type}
    if friction is not None:
        contact["friction"] = friction
    return {"materials": [dict(STEEL)],
            "bodies": [{"name": "top", "material": "steel", "element_size": 0.05,
                        "shape": {"type": "half_disk", "center": [0, 1], "radius": 1, "side": "below"}},
                       {"name": "bottom", "material": "steel", "element_size": 0.05,
                        "shape": {"type": "half_disk", "center": [0, -1], "radius": 1, "side": "above"}}],
            "boundary_conditions": top_conditions + [{"body": "bottom", "edge": "flat", "type": "fixed"}],
            "contacts": [contact]}


def test_scene3_cylinder_on_cylinder_frictionless_is_held():
    top = [{"body": "top", "edge": "flat", "type": "displacement", "value": [1e-4, -1e-3]}]
    assert rigid_error(two_cylinders("frictionless", top)) == []


def test_body_held_only_through_contacts():
    # a tied top body with no supports of its own is held by the fixed bottom body
    assert rigid_error(two_cylinders("tied", [])) == []
    # frictionless: it can still slide along the contact and roll: reported by name
    (msg,) = rigid_error(two_cylinders("frictionless", []))
    assert 'bodies[0].name = "top"' in msg and "together with the bodies it touches" in msg
    # frictional contact and a vertical push: held (normal and tangential at the point, plus
    # the push along the flat edge)
    top = [{"body": "top", "edge": "flat", "type": "displacement", "value": ["free", -1e-3]}]
    assert rigid_error(two_cylinders("frictional", top, friction=0.3)) == []
    assert len(rigid_error(two_cylinders("frictionless", top))) == 1


def test_contact_point_found_as_closest_points_with_a_gap():
    from ibfem.solver.model.resolve import contact_frame as _contact_frame

    data = two_cylinders("frictionless", [{"body": "top", "edge": "flat", "type": "fixed"}])
    data["bodies"][0]["shape"]["center"] = [0.2, 1.01]  # a gap of 0.01 at x = 0.1
    problem = scene_from_dict(data).problem
    point, normal = _contact_frame(problem, problem.contacts[0])
    # closest points of two unit circles with centres (0.2, 1.01) and (0, -1)
    c1, c2 = np.array([0.2, 1.01]), np.array([0.0, -1.0])
    u = (c1 - c2) / np.linalg.norm(c1 - c2)
    expected = 0.5 * ((c1 - u) + (c2 + u))
    assert np.allclose(point, expected, atol=1e-9)
    assert np.allclose(normal, u, atol=1e-9)  # outward normal of the second (bottom) body


def test_rigid_body_modes_agree_with_the_null_space_of_a_hand_built_matrix():
    # plate sliding on its bottom only, fixed nowhere else: the free motions are x translation;
    # with a displacement [free, v] on the right edge added the rotation is also stopped, still
    # leaving x translation -> one mode each time
    data = plate(conditions=[{"body": "plate", "edge": "bottom", "type": "sliding"},
                             {"body": "plate", "edge": "right", "type": "displacement", "value": ["free", 0.0]}])
    with pytest.raises(SceneError):
        scene_from_dict(data)
    data["boundary_conditions"][1]["value"] = [0.0, "free"]
    problem = scene_from_dict(data).problem
    assert rigid_body_modes(problem) == {}


def test_examples_load():
    """Every example scene (the validation scenes and the single-body ones) validates as it is."""
    paths = sorted((ROOT / "examples").glob("*.toml")) + sorted((ROOT / "examples" / "single_body").glob("*.toml"))
    assert len(paths) >= 4
    for path in paths:
        scene = load_scene(path)
        assert scene.problem.bodies and scene.warnings == (), path


def test_solver_section_accepts_options_the_solver_adds(monkeypatch):
    import dataclasses

    from ibfem.solver.io import scene as sc

    @dataclasses.dataclass(frozen=True)
    class Options(pb.SolverOptions):
        future_option: float = 0.25

    spec_cls = sc._fields_of(Options, sc._SolverBase, "SolverSpec")
    assert spec_cls.model_validate({"future_option": 0.1}).future_option == 0.1
    assert spec_cls.model_validate({}).future_option == 0.25 and spec_cls.model_validate({}).load_steps == 10
    with pytest.raises(Exception, match="future_option"):
        spec_cls.model_validate({"future_option": "wide"})


def test_modulus_that_looks_like_gpa_is_a_warning_not_an_error():
    data = plate()
    data["materials"][0]["youngs_modulus"] = 200.0
    scene = scene_from_dict(data, label="scene.toml")
    assert scene.warnings == ("scene.toml: materials[0].youngs_modulus = 200.0: very small for Pa (units are SI: steel is 2.0e11)",)


@pytest.mark.parametrize("order", [("pin", "block"), ("block", "pin")])
@pytest.mark.parametrize("shape", [
    {"type": "half_disk", "center": [0.3, 1.0], "radius": 1.0, "side": "below"},
    {"type": "half_ellipse", "center": [0.3, 0.5], "semi_axes": [1.0, 0.5], "side": "below"},
])
def test_contact_point_on_long_straight_edges(order, shape):
    """A curved body touching a long flat one at (0.3, 0): the finder must not be fooled by
    the flat edge having no interior tessellation vertices, whichever body comes first."""
    from ibfem.solver.model.resolve import contact_frame as _contact_frame

    data = {"materials": [dict(STEEL)],
            "bodies": [{"name": "pin", "material": "steel", "element_size": 0.05, "shape": shape},
                       {"name": "block", "material": "steel", "element_size": 0.05,
                        "shape": {"type": "rectangle", "min": [-3, -2], "max": [3, 0]}}],
            "boundary_conditions": [{"body": "pin", "edge": "flat", "type": "fixed"},
                                    {"body": "block", "edge": "bottom", "type": "fixed"}],
            "contacts": [{"bodies": list(order), "type": "frictionless"}]}
    problem = scene_from_dict(data).problem
    point, normal = _contact_frame(problem, problem.contacts[0])
    assert np.allclose(point, [0.3, 0.0], atol=1e-7)
    assert np.allclose(normal, [0.0, 1.0] if order[1] == "block" else [0.0, -1.0], atol=1e-6)


def test_onshape_shape_goes_to_the_importer_with_its_path_resolved(tmp_path, monkeypatch):
    import types

    from ibfem.geometry.shapes import profile_from_shape

    seen = {}

    def fake_profile_from_shape(shape, where="shape"):
        seen.update(shape=dict(shape), where=where)
        return profile_from_shape({"type": "rectangle", "min": [0, 0], "max": [2, 1]})

    fake = types.ModuleType("ibfem.importers.onshape.profile")
    fake.profile_from_shape = fake_profile_from_shape
    monkeypatch.setitem(sys.modules, "ibfem.importers.onshape.profile", fake)
    import ibfem.importers.onshape
    from ibfem import importers

    monkeypatch.setattr(importers.onshape, "profile", fake, raising=False)
    data = plate()
    data["bodies"][0]["shape"] = {"type": "onshape", "path": "cache/block", "face": "JHD"}
    (tmp_path / "scene.toml").write_text("")
    scene = scene_from_dict(data, label="scene.toml", base_dir=tmp_path)
    assert seen["shape"] == {"type": "onshape", "path": str(tmp_path / "cache" / "block"), "face": "JHD"}
    assert seen["where"] == "bodies[0].shape"
    assert scene.problem.body("plate").profile.edge_names == ("bottom", "right", "top", "left")


def test_onshape_fixture_scene_with_a_relative_path(tmp_path):
    """The `onshape` shape end to end on the cached half-cylinder-on-block part (thesis
    contact example): the path is relative to the scene file, edges are Onshape ids, and the
    contact point found from the exact section curves is the touching point (0, 0)."""
    import os

    from ibfem.solver.model.resolve import contact_frame as _contact_frame

    fixture = ROOT / "fixtures" / "onshape" / "half_cylinder_on_block"
    if not (fixture / "bodydetails.json").exists():
        pytest.skip("fixture not present")
    rel = os.path.relpath(fixture, tmp_path)
    section = {"origin": [0, 0, 0.01], "normal": [0, 0, 1]}

    def shape(body):
        return {"type": "onshape", "path": rel, "section": section, "body": body}

    data = {"materials": [dict(STEEL)],
            "bodies": [{"name": "cylinder", "material": "steel", "element_size": 0.005, "shape": shape("Half cylinder")},
                       {"name": "block", "material": "steel", "element_size": 0.005, "shape": shape("Block")}],
            "contacts": [{"bodies": ["cylinder", "block"], "type": "frictionless"}]}
    # find the edges by geometry: the cylinder's flat top and the block's bottom
    from ibfem.importers.onshape.profile import profile_from_shape as onshape_profile

    cyl = onshape_profile({**shape("Half cylinder"), "path": str(fixture)})
    block = onshape_profile({**shape("Block"), "path": str(fixture)})

    def edge_at(profile, pick):
        mids = {n: profile.edges[n].evaluate(np.array([0.5 * (profile.edges[n].t_start + profile.edges[n].t_end)]))[0]
                for n in profile.edge_names}
        return pick(mids, key=lambda n: mids[n][1])

    flat, bottom = edge_at(cyl, max), edge_at(block, min)
    data["boundary_conditions"] = [{"body": "cylinder", "edge": flat, "type": "displacement", "value": [0.0, -1e-5]},
                                   {"body": "block", "edge": bottom, "type": "fixed"}]
    scene = scene_from_dict(data, label="scene.toml", base_dir=tmp_path)
    point, normal = _contact_frame(scene.problem, scene.problem.contacts[0])
    assert np.allclose(point, [0.0, 0.0], atol=1e-8) and np.allclose(normal, [0.0, 1.0], atol=1e-8)
    # the cylinder alone with its flat edge held only vertically can slide: caught
    data["boundary_conditions"][0]["value"] = ["free", -1e-5]
    with pytest.raises(SceneError) as info:
        scene_from_dict(data, label="scene.toml", base_dir=tmp_path)
    (msg,) = info.value.problems
    assert msg.startswith('scene.toml: bodies[0].name = "cylinder": rigid-body motion not prevented')


def test_numerical_solver_options_reach_the_problem():
    from ibfem.solver.model.options import SolverOptions

    data = plate()
    data["solver"] = {"consistency": 0.5, "band_fraction": 0.05, "chord_tolerance": 1e-3}
    options = scene_from_dict(data, label="scene.toml").problem.options
    assert (options.consistency, options.band_fraction, options.chord_tolerance) == (0.5, 0.05, 1e-3)
    assert scene_from_dict(plate(), label="scene.toml").problem.options == SolverOptions()
    data["solver"] = {"chord_tolerance": -1.0}
    with pytest.raises(SceneError, match=r"solver\.chord_tolerance = -1\.0: must be a positive number"):
        scene_from_dict(data, label="scene.toml")




def test_nearly_incompressible_material_is_warned_of_locking_except_in_plane_stress():
    data = plate()
    data["materials"][0]["poissons_ratio"] = 0.49
    (note,) = scene_from_dict(data, label="scene.toml").warnings
    assert note.startswith("scene.toml: materials[0].poissons_ratio = 0.49: nearly incompressible")
    data["materials"][0]["poissons_ratio"] = 0.3
    assert scene_from_dict(data, label="scene.toml").warnings == ()
    data["materials"][0]["poissons_ratio"] = 0.49
    data["model"] = "plane_stress"
    assert scene_from_dict(data, label="scene.toml").warnings == ()


def test_nearly_incompressible_solid_is_warned_too():
    from pathlib import Path

    import tomllib

    path = Path(__file__).resolve().parents[1] / "examples" / "solid" / "spherical_cavity.toml"
    data = tomllib.loads(path.read_text())
    for m in data["materials"]:
        m["poissons_ratio"] = 0.495
    warnings = scene_from_dict(data, label="cavity.toml", base_dir=path.parent).warnings
    assert any("poissons_ratio = 0.495: nearly incompressible" in w for w in warnings)
