"""Bad input gives an OnshapeFormatError naming the file and the JSON path (never a
traceback from deep inside); unknown surface/curve types are kept and reported."""

from __future__ import annotations

import json

import numpy as np
import pytest

from ibfem.importers import OnshapeFormatError
from ibfem.importers.onshape import load_part
from ibfem.importers.onshape.models import CurveDesc
from ibfem.importers.onshape.parser import bcurve_control_points
from test_onshape_support import copy_studio, edit_json, registered

A = "half_cylinder_on_block"  # format A, inline vertices
B = "cylinder_on_v_groove"  # format B, index table


def _err(directory) -> str:
    with pytest.raises(OnshapeFormatError) as info:
        load_part(directory)
    return str(info.value)


def _cyl_index(data):
    return next(i for i, f in enumerate(data["bodies"][0]["faces"]) if f["surface"]["type"].upper() == "CYLINDER")


def test_truncated_json_names_the_file(tmp_path):
    d = copy_studio(A, tmp_path)
    text = (d / "bodydetails.json").read_text()
    (d / "bodydetails.json").write_text(text[: len(text) // 2])
    msg = _err(d)
    assert msg.startswith("bodydetails.json: truncated or invalid JSON at line 1")


def test_wrong_type_names_the_json_path(tmp_path):
    d = copy_studio(A, tmp_path)
    k = {}

    def bad(data):
        k["i"] = _cyl_index(data)
        data["bodies"][0]["faces"][k["i"]]["surface"]["radius"] = "abc"

    edit_json(d / "bodydetails.json", bad)
    assert _err(d) == f"bodydetails.json: bodies[0].faces[{k['i']}].surface.radius: expected a number, got 'abc'"


def test_missing_field_needed_by_an_exact_surface(tmp_path):
    d = copy_studio(B, tmp_path)
    k = {}

    def bad(data):
        k["i"] = _cyl_index(data) if any(f["surface"]["type"] == "cylinder" for f in data["bodies"][0]["faces"]) else None
        if k["i"] is None:  # the cylinder is in the second body of this studio
            k["b"] = 1
            k["i"] = next(i for i, f in enumerate(data["bodies"][1]["faces"]) if f["surface"]["type"] == "cylinder")
        else:
            k["b"] = 0
        del data["bodies"][k["b"]]["faces"][k["i"]]["surface"]["radius"]

    edit_json(d / "bodydetails.json", bad)
    assert _err(d) == (f"bodydetails.json: bodies[{k['b']}].faces[{k['i']}].surface.radius: "
                       f"missing field, needed for CYLINDER")


def test_missing_surface_and_bad_vector(tmp_path):
    d = copy_studio(A, tmp_path)
    edit_json(d / "bodydetails.json", lambda data: data["bodies"][1]["faces"][2].pop("surface"))
    assert _err(d) == "bodydetails.json: bodies[1].faces[2].surface: missing field"
    d = copy_studio(A, tmp_path / "v")
    edit_json(d / "tessellatedfaces.json",
              lambda data: data["bodies"][0]["faces"][1]["facets"][3]["vertices"][2].pop("z"))
    assert _err(d).startswith("tessellatedfaces.json: bodies[0].faces[1].facets[3].vertices[2]: "
                              "expected a vector {x, y, z}, missing z")


def test_legacy_array_paths_start_at_the_top_level_array(tmp_path):
    d = copy_studio(B, tmp_path)
    edit_json(d / "tessellatedfaces.json", lambda data: data[1]["faces"][0]["facets"][2]["normal"].__setitem__(1, True))
    assert _err(d) == "tessellatedfaces.json: [1].faces[0].facets[2].normal[1]: expected a number, got True" or \
        _err(d).startswith("tessellatedfaces.json: [1].faces[0].facets[2].normal: expected a number, got True")


def test_non_triangle_facet_and_bad_index(tmp_path):
    d = copy_studio(A, tmp_path)

    def four(data):
        f = data["bodies"][0]["faces"][0]["facets"][0]
        f["vertices"].append(f["vertices"][0])

    edit_json(d / "tessellatedfaces.json", four)
    assert _err(d) == "tessellatedfaces.json: bodies[0].faces[0].facets[0].vertices: expected 3 vertices " \
                      "(triangles only), got 4"
    d = copy_studio(B, tmp_path / "i")
    edit_json(d / "tessellatedfaces.json", lambda data: data[0]["faces"][0]["facets"][1].__setitem__("indices", [0, 1, 10**6]))
    assert "tessellatedfaces.json: [0].faces[0].facets[1].indices: index 1000000 outside the facetPoints table" in _err(d)


def test_unknown_body_type_enum_is_an_error(tmp_path):
    d = copy_studio(A, tmp_path)
    edit_json(d / "bodydetails.json", lambda data: data["bodies"][1].__setitem__("type", "GASEOUS"))
    assert _err(d).startswith("bodydetails.json: bodies[1].type: expected one of SOLID, SHEET")
    d = copy_studio(A, tmp_path / "n")
    edit_json(d / "bodydetails.json", lambda data: data["bodies"][0]["faces"][0]["surface"].__setitem__("type", 42))
    assert _err(d) == "bodydetails.json: bodies[0].faces[0].surface.type: expected a type name (string), got 42"


def test_unknown_surface_type_is_kept_as_tessellation_only(tmp_path):
    d = copy_studio(A, tmp_path)
    k = {}

    def hyper(data):
        k["i"] = _cyl_index(data)
        k["id"] = data["bodies"][0]["faces"][k["i"]]["id"]
        data["bodies"][0]["faces"][k["i"]]["surface"] = {"btType": "BTHyperboloidDescription-1", "type": "HYPERBOLOID"}

    edit_json(d / "bodydetails.json", hyper)
    part = load_part(d)
    face = part.faces[k["id"]]
    assert face.surface is None and face.surface_type == "HYPERBOLOID" and len(face.mesh.faces) > 0
    assert any("HYPERBOLOID (unknown surface type)" in w and k["id"] in w for w in part.warnings)


def test_server_error_enum_and_wrong_top_level(tmp_path):
    d = copy_studio(A, tmp_path)
    edit_json(d / "bodydetails.json", lambda data: data.__setitem__("errorEnum", "PART_NOT_FOUND"))
    assert "bodydetails.json: errorEnum: the server reported 'PART_NOT_FOUND'" in _err(d)
    d = copy_studio(A, tmp_path / "t")
    (d / "tessellatedfaces.json").write_text('"hello"')
    assert _err(d).startswith("tessellatedfaces.json: (top level): expected an object with 'bodies'")


def test_invalid_primitive_values_are_reported_with_their_path(tmp_path):
    d = copy_studio(A, tmp_path)
    k = {}

    def neg(data):
        k["i"] = _cyl_index(data)
        data["bodies"][0]["faces"][k["i"]]["surface"]["radius"] = -0.05

    edit_json(d / "bodydetails.json", neg)
    msg = _err(d)
    assert msg.startswith(f"bodydetails.json: bodies[0].faces[{k['i']}].surface: ") and "radius" in msg


def test_missing_files(tmp_path):
    d = copy_studio(A, tmp_path)
    (d / "bodydetails.json").unlink()
    assert "missing bodydetails.json" in _err(d)
    (tmp_path / "empty").mkdir()
    assert "missing tessellatedfaces.json" in _err(tmp_path / "empty")


def test_orientation_flag_disagreeing_with_facets_is_reported(tmp_path):
    d = copy_studio(A, tmp_path)
    k = {}

    def flip(data):
        k["i"] = _cyl_index(data)
        f = data["bodies"][0]["faces"][k["i"]]
        f["orientation"] = not f["orientation"]
        k["id"] = f["id"]

    edit_json(d / "bodydetails.json", flip)
    part = load_part(d)
    assert any(k["id"] in w and "disagrees with the facet normals" in w for w in part.warnings)
    # the facets win: the convex half cylinder still points away from its axis
    assert part.faces[k["id"]].orientation == 1


def test_facets_wound_against_their_normal_are_rewound(tmp_path):
    d = copy_studio(A, tmp_path)

    def rewind(data):
        f = data["bodies"][0]["faces"][0]["facets"][0]
        f["vertices"] = f["vertices"][::-1]

    edit_json(d / "tessellatedfaces.json", rewind)
    part = load_part(d)
    face = next(iter(part.faces.values()))
    assert any("re-wound" in n for n in face.notes)
    P = np.asarray(face.mesh.vertices)[np.asarray(face.mesh.faces)]
    n = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    sn = face.surface.project(P.mean(axis=1)).normals * face.orientation
    assert np.all(np.einsum("ij,ij->i", n, sn) > 0)


def test_cli_reports_bad_input_without_a_traceback(tmp_path, capsys):
    from ibfem.solver.cli import main

    d = copy_studio(A, tmp_path)
    (d / "bodydetails.json").write_text("{")
    for cmd in ("verify", "info"):
        assert main([cmd, str(d)]) == 2
        err = capsys.readouterr().err
        assert "Traceback" not in err
        assert err.startswith(f"ibfem {cmd}: bodydetails.json: truncated or invalid JSON")


# ---------------------------------------------------------------------------------------
# B-spline control point layouts
# ---------------------------------------------------------------------------------------

CTRL = np.array([[0.0, 0.0, 0.0], [1.0, 2.0, 0.5], [2.0, -1.0, 0.0], [3.0, 0.0, 1.0]])
W = np.array([1.0, 0.5, 2.0, 1.0])
KNOTS = [0, 0, 0, 0.5, 1, 1, 1]


def _desc(**kw):
    return CurveDesc.model_validate({"type": "BCURVE", "degree": 2, "knots": KNOTS, **kw})


@pytest.mark.parametrize("layout", [
    {"controlPoints": CTRL.ravel().tolist()},
    {"controlPoints": CTRL.tolist()},
    {"controlPoints": [{"btType": "BTVector3d-389", "x": p[0], "y": p[1], "z": p[2]} for p in CTRL]},
])
def test_non_rational_layouts(layout):
    (pts, w, _), = bcurve_control_points(_desc(**layout), "c")
    assert np.array_equal(pts, CTRL) and w is None


def test_rational_layouts():
    homog = np.column_stack([CTRL * W[:, None], W])
    readings = bcurve_control_points(_desc(isRational=True, controlPoints=homog.ravel().tolist()), "c")
    assert readings[0][2] == "homogeneous xyzw"
    assert np.allclose(readings[0][0], CTRL, rtol=0, atol=1e-15) and np.array_equal(readings[0][1], W)
    assert readings[1][2] == "cartesian xyzw"  # the alternative reading, tried against the data
    (pts, w, _), = bcurve_control_points(
        _desc(isRational=True, controlPoints=CTRL.ravel().tolist(), weights=W.tolist()), "c")
    assert np.array_equal(pts, CTRL) and np.array_equal(w, W)


@pytest.mark.parametrize("kw,msg", [
    ({"controlPoints": CTRL.ravel().tolist()[:-3]}, "c.controlPoints: 3 control points do not match degree 2 and 7 knots"),
    ({"controlPoints": CTRL.ravel().tolist()[:-1]}, "c.controlPoints: 11 numbers is not a whole number of control points of 3"),
    ({"controlPoints": CTRL.ravel().tolist(), "isRational": True}, "c.controlPoints: 3 control points"),  # read as xyzw
    ({"controlPoints": CTRL.ravel().tolist(), "knots": [0, 0, 0, 1, 0.5, 1, 1]}, "c.knots: knots must not decrease"),
    ({"controlPoints": CTRL.ravel().tolist(), "weights": [1, 1, 1]}, "c.weights: expected 4 weights"),
    ({"controlPoints": CTRL.ravel().tolist(), "weights": [1, 1, -1, 1]}, "c.weights: weights must be positive"),
    ({"controlPoints": [1, "x", 3]}, "c.controlPoints[1]: expected a number, got 'x'"),
])
def test_bad_bcurves(kw, msg):
    from ibfem.importers.onshape.parser import _Fail

    with pytest.raises(_Fail) as info:
        bcurve_control_points(_desc(**kw), "c")
    assert str(info.value).startswith(msg)


@pytest.mark.skipif(not registered("bspline_curve"), reason="bspline_curve not registered yet")
def test_the_cartesian_reading_is_chosen_when_the_data_says_so():
    """A rational curve sent as Cartesian (x, y, z, w): the reading that puts the edge's own
    points on the curve wins, and it is noted."""
    from ibfem.geometry import primitive_from_dict
    from ibfem.importers.onshape.parser import curve_primitive

    true = primitive_from_dict({"type": "bspline_curve", "degree": 2, "knots": KNOTS,
                                "control_points": CTRL.tolist(), "weights": W.tolist()})
    # points on the true curve: project a few nearby points onto it
    on = true.project(np.array([[0.5, 0.5, 0.1], [1.5, 0.5, 0.4], [2.5, -0.5, 0.5]])).points
    cart = np.column_stack([CTRL, W]).ravel().tolist()
    curve, kind, note = curve_primitive(_desc(isRational=True, controlPoints=cart), "c", check_points=on)
    assert note == "control points read as cartesian xyzw"
    assert np.max(np.abs(curve.project(on).distances)) < 1e-12


def test_the_2018_parts_wrapper_is_accepted(tmp_path):
    """The 2018 docs wrap legacy tessellation arrays as {"parts": [...]}; paths then start there."""
    d = copy_studio(B, tmp_path)
    for name in ("tessellatedfaces.json", "tessellatededges.json"):
        data = json.loads((d / name).read_text())
        (d / name).write_text(json.dumps({"parts": data}))
    part = load_part(d)
    assert len(part.faces) == 13 and all(f.mesh is not None for f in part.faces.values())
    assert all(len(e.polyline) >= 2 for e in part.edges.values())
    edit_json(d / "tessellatedfaces.json", lambda data: data["parts"][1]["faces"][0].pop("id"))
    assert _err(d) == "tessellatedfaces.json: parts[1].faces[0].id: missing field"


@pytest.mark.parametrize("kind", ["SPUN", "BSURFACE", "OFFSET", "BLEND", "OTHER", "UNKNOWN", "revolved"])
def test_documented_tessellation_only_surface_types(tmp_path, kind):
    d = copy_studio(A, tmp_path)
    k = {}

    def set_type(data):
        k["i"] = _cyl_index(data)
        k["id"] = data["bodies"][0]["faces"][k["i"]]["id"]
        data["bodies"][0]["faces"][k["i"]]["surface"] = {"type": kind}

    edit_json(d / "bodydetails.json", set_type)
    part = load_part(d)
    canonical = {"revolved": "SPUN"}.get(kind, kind)
    face = part.faces[k["id"]]
    assert face.surface is None and face.surface_type == canonical
    assert any(w.startswith(f"surface {canonical}: kept as tessellation-only") and k["id"] in w for w in part.warnings)
