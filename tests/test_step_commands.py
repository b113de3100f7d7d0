"""STEP/IGES import through the commands and scenes: bad files give one line naming
the file (and the entity), ``ibfem import`` caches the parsed part and reparses a changed file,
verify/info accept the file or the cache, scenes take ``{type = "step", ...}`` shapes, and
without OCP the error names the extra."""

from __future__ import annotations

import json
import math
import sys

import numpy as np
import pytest

pytest.importorskip("OCP")

import test_step_support as S  # noqa: E402
from ibfem.importers.step import StepFormatError, StepUnavailableError, load_part  # noqa: E402
from ibfem.solver.cli import main  # noqa: E402


@pytest.fixture(scope="module")
def d(tmp_path_factory):
    from ibfem.importers.step.reader import _quiet_messenger

    _quiet_messenger()
    out = tmp_path_factory.mktemp("stepcmd")
    shapes = S.primitives()
    S.write_step(shapes["cylinder"], out / "cylinder.step")
    S.write_step(shapes["sphere"], out / "sphere.step")
    S.write_step(shapes["prism"], out / "prism.step")
    S.write_iges(shapes["box"], out / "box.igs")
    return out


def _one_line(capsys, code_expected, argv):
    assert main(argv) == code_expected
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    return err


def test_bad_files_give_one_line_naming_the_file(d, capsys):
    text = (d / "cylinder.step").read_text()
    cases = {
        "truncated.step": text[: len(text) // 2],
        "empty.step": "",
        "junk.stp": "hello\n",
        "point.step": text.replace("CARTESIAN_POINT('',(", "CARTESIAN_POINT('',(zz,", 1),
    }
    for name, body in cases.items():
        (d / name).write_text(body)
    for name, want in (("truncated.step", "not a readable STEP file"), ("empty.step", "empty"),
                       ("junk.stp", "not a readable STEP file"), ("point.step", "entity"),
                       ("missing.step", "no such file")):
        err = _one_line(capsys, 2, ["info", str(d / name)])
        assert name in err and want in err, err
        with pytest.raises(StepFormatError, match=name):
            load_part(d / name)
    (d / "part.txt").write_text("x")
    with pytest.raises(StepFormatError, match="not a STEP or IGES file name"):
        load_part(d / "part.txt")


def test_a_file_without_faces_is_refused(d):
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge
    from OCP.gp import gp_Pnt

    edge = BRepBuilderAPI_MakeEdge(gp_Pnt(0, 0, 0), gp_Pnt(1, 0, 0)).Edge()
    S.write_step(edge, d / "wire.step")
    with pytest.raises(StepFormatError, match="wire.step.*(no solids or faces|no shape)"):
        load_part(d / "wire.step")


def test_import_caches_and_reparses_a_changed_file(d, tmp_path, capsys):
    src = tmp_path / "part.step"
    src.write_bytes((d / "sphere.step").read_bytes())
    out = tmp_path / "cache"
    assert main(["import", str(src), "--out", str(out), "--chord-tolerance", "1e-4"]) == 0
    assert "imported 1 bodies, 1 faces (1 SPHERE)" in capsys.readouterr().out
    cached = load_part(out)
    assert cached.faces["F1"].surface.to_dict()["radius"] == pytest.approx(S.SPHERE["radius"] * S.MM, rel=1e-12)
    assert cached.metadata["tolerance"] == 1e-4
    fresh = load_part(src, tolerance=1e-4)
    np.testing.assert_array_equal(cached.faces["F1"].mesh.vertices, fresh.faces["F1"].mesh.vertices)
    # a changed source (another radius) is parsed again and the cache rewritten
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeSphere

    S.write_step(BRepPrimAPI_MakeSphere(9.0).Shape(), src)
    again = load_part(out)
    assert again.faces["F1"].surface.to_dict()["radius"] == pytest.approx(9e-3, rel=1e-12)
    assert json.loads((out / "part.json").read_text())["source"]["sha256"] == again.metadata["source"]["sha256"]
    # verify and info accept the directory
    assert main(["verify", str(out), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert set(report) == {"faces", "max_error", "max_normal_error", "verdict", "reason"} and report["max_error"] < 1e-15
    assert report["verdict"] == "pass"
    assert main(["info", str(out)]) == 0 and "SPHERE" in capsys.readouterr().out


def test_damaged_cache_is_named(d, tmp_path, capsys):
    out = tmp_path / "c"
    assert main(["import", str(d / "cylinder.step"), "--out", str(out)]) == 0
    doc = json.loads((out / "part.json").read_text())
    doc["faces"][0]["orientation"] = "up"
    (out / "part.json").write_text(json.dumps(doc))
    err = _one_line(capsys, 2, ["verify", str(out)])
    assert "part.json" in err and "faces.0.orientation" in err


def test_verify_and_info_on_the_file(d, capsys):
    assert main(["verify", str(d / "prism.step")]) == 0
    text = capsys.readouterr().out
    assert "SWEEP" in text and text.rstrip().endswith("OK")
    # the NURBS of a revolution read from IGES projects to ~1.5e-12 m: accepted below 1e-9 of the size
    S.write_iges(S.revolved(), d / "revolved.igs")
    assert main(["verify", str(d / "revolved.igs"), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert 0 < report["max_error"] < 1e-9 * 0.02 and report["max_normal_error"] < 1e-9
    assert main(["info", str(d / "box.igs")]) == 0
    assert "PLANE              6  yes" in capsys.readouterr().out


def test_without_ocp_the_error_names_the_extra(d, monkeypatch, capsys):
    for name in [m for m in sys.modules if m == "OCP" or m.startswith("OCP.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "OCP", None)
    with pytest.raises(StepUnavailableError, match=r"pip install 'ibfem\[step\]'"):
        load_part(d / "cylinder.step")
    err = _one_line(capsys, 2, ["info", str(d / "cylinder.step")])
    assert "ibfem[step]" in err


def test_scene_with_a_step_face_profile(d):
    from ibfem.solver.io.scene import load_scene

    scene = {"name": "disk", "model": "plane_stress", "thickness": 1.0,
             "materials": [{"name": "steel", "youngs_modulus": 2e11, "poissons_ratio": 0.3}],
             "bodies": [{"name": "disk", "material": "steel", "element_size": 0.002,
                         "shape": {"type": "step", "path": "cylinder.step", "face": "F2"}}],
             "boundary_conditions": [{"body": "disk", "edge": "E1", "type": "fixed"}]}
    loaded = load_scene(scene, label="disk.json", base_dir=d)
    prof = loaded.problem.bodies[0].profile
    assert prof.area == pytest.approx(math.pi * (S.CYLINDER["radius"] * S.MM) ** 2, rel=1e-12)
    bad = {**scene, "bodies": [{**scene["bodies"][0], "shape": {"type": "step", "path": "nope.step", "face": "F2"}}]}
    with pytest.raises(ValueError, match=r"bodies\[0\].shape.path: .*nope.step: no such file"):
        load_scene(bad, label="disk.json", base_dir=d)


def test_scene_with_a_step_section_and_a_solid(d):
    from ibfem.geometry.solids import PartSolid
    from ibfem.importers.step.profile import profile_from_shape

    prof = profile_from_shape({"type": "step", "path": str(d / "prism.step"),
                               "section": {"origin": [0, 0, 0.005], "normal": [0, 0, 1]}})
    part = load_part(d / "prism.step")
    cap = [f for f in part.faces.values() if f.surface_type == "PLANE"
           and abs(abs(f.surface.to_dict()["normal"][2]) - 1) < 1e-12][0]
    from OCP.TopAbs import TopAbs_ShapeEnum
    from OCP.TopExp import TopExp_Explorer

    shape = S.prism()[0]
    explorer = TopExp_Explorer(shape, TopAbs_ShapeEnum.TopAbs_FACE)
    areas = []
    while explorer.More():
        areas.append(S.exact_area(explorer.Current()))
        explorer.Next()
    assert any(abs(prof.area - a * S.MM**2) < 1e-10 * prof.area for a in areas)  # a cap's exact area
    assert cap.loops
    solid = PartSolid(load_part(d / "sphere.step"))
    r = S.SPHERE["radius"] * S.MM
    assert solid.volume == pytest.approx(4 / 3 * math.pi * r**3, rel=1e-6)
    c = np.asarray(S.ORIGIN) * S.MM
    assert solid.signed_distance(c[None])[0] == pytest.approx(r, rel=1e-12)


def test_names_in_the_file_name_bodies_and_faces(d, tmp_path):
    """MANIFOLD_SOLID_BREP('roller', ...) names the body, ADVANCED_FACE('flat end', ...) the face;
    the scene shape takes the face by its name."""
    from ibfem.geometry.solids import PartSolid
    from ibfem.importers.step.profile import profile_from_shape

    text = (d / "cylinder.step").read_text()
    assert text.count("MANIFOLD_SOLID_BREP('',") == 1
    plain = load_part(d / "cylinder.step")
    cap_index = list(plain.faces).index("F2")
    faces = text.split("ADVANCED_FACE('',")
    assert len(faces) == 4  # three faces
    named = faces[0] + "".join(("ADVANCED_FACE('flat end'," if k == cap_index else "ADVANCED_FACE('',") + rest
                               for k, rest in enumerate(faces[1:]))
    (tmp_path / "named.step").write_text(named.replace("MANIFOLD_SOLID_BREP('',", "MANIFOLD_SOLID_BREP('roller',"))
    part = load_part(tmp_path / "named.step")
    assert [b.name for b in part.bodies.values()] == ["roller"]
    assert part.metadata["face_names"] == {"F2": "flat end"}
    assert PartSolid(part, "roller").body.id == "B1"
    a = profile_from_shape({"type": "step", "path": str(tmp_path / "named.step"), "face": "flat end"}).area
    assert a == pytest.approx(math.pi * (S.CYLINDER["radius"] * S.MM) ** 2, rel=1e-12)
