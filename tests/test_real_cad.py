"""What real exporters write, reproduced with parts OpenCascade writes inside the test and then
edits the way other CAD systems write them: presentation and unit entities OpenCascade's parser
refuses (warnings named by #n label; geometry failures stay errors), a mesher that stalls on a face
(the guard's fallbacks and its error), faces trimmed beyond their B-spline surface or extrusion
profile (extended exactly), non-ASCII and product names, open shells, solids oriented inward, and
bodies sharing a name. Each test checks the import against what the part was built with."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

pytest.importorskip("OCP")

import test_step_support as S  # noqa: E402
from ibfem.importers.step import StepFormatError, load_part  # noqa: E402

DEGREE = math.pi / 180.0


@pytest.fixture(scope="module")
def shapes():
    from ibfem.importers.step.reader import _quiet_messenger

    _quiet_messenger()
    return S.primitives()


def _cone_in_degrees(text: str) -> str:
    """The STEP text of OpenCascade's cone with its angle unit changed to a DEGREE conversion written
    as AP242 exporters do (``NAMED_UNIT(*)``, which OpenCascade's parser refuses as not an entity), the
    cone's semi-angle converted to degrees, and a presentation style whose marker has an illegal type."""
    unit = re.search(r"#(\d+) = \( NAMED_UNIT\(\*\) PLANE_ANGLE_UNIT\(\) SI_UNIT\(\$,\.RADIAN\.\) \);", text)
    assert unit, "OpenCascade's file has no radian unit to replace"
    n = unit.group(1)
    text = text.replace(unit.group(0), f"#{n} = ( CONVERSION_BASED_UNIT('DEGREE',#9001) NAMED_UNIT(*) "
                                       "PLANE_ANGLE_UNIT() );")

    def in_degrees(m):
        return f"{m.group(1)}{float(m.group(2)) / DEGREE!r});"

    text, count = re.subn(r"(CONICAL_SURFACE\('',#\d+,[^,]+,)([^)]+)\);", in_degrees, text)
    assert count == 1
    extra = ("#9001 = PLANE_ANGLE_MEASURE_WITH_UNIT(PLANE_ANGLE_MEASURE(0.0174532925199433),#9002);\n"
             "#9002 = ( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) );\n"
             "#9003 = POINT_STYLE('',#9004,POSITIVE_LENGTH_MEASURE(3.),#9005);\n"
             "#9004 = CARTESIAN_POINT('',(0.,0.,0.));\n"
             "#9005 = COLOUR_RGB('',1.,0.,0.);\n")
    head, tail = text.rsplit("ENDSEC;", 1)
    return head + extra + "ENDSEC;" + tail


def test_failed_checks_outside_the_geometry_are_warnings_named_by_label(shapes, tmp_path):
    path = S.write_step(shapes["cone"], tmp_path / "cone.step")
    path.write_text(_cone_in_degrees(path.read_text()))
    part = load_part(path)
    cone = [f.surface.to_dict() for f in part.faces.values() if f.surface_type == "CONE"]
    assert len(cone) == 1
    # the degree unit is still applied: the semi-angle is the one the cone was built with
    expected = math.atan((S.CONE["r1"] - S.CONE["r2"]) / S.CONE["height"])
    assert cone[0]["half_angle"] == pytest.approx(expected, rel=1e-9)
    warning = " ".join(part.warnings)
    assert "#9003 (PointStyle)" in warning and "(ConversionBasedUnitAndPlaneAngleUnit)" in warning, warning
    assert "in file order" not in warning


def test_a_failed_check_on_the_geometry_is_an_error_naming_the_label(shapes, tmp_path):
    path = S.write_step(shapes["cone"], tmp_path / "cone.step")
    text = path.read_text()
    m = re.search(r"#(\d+) = CARTESIAN_POINT\('',\(", text)
    path.write_text(text.replace(m.group(0), m.group(0) + "zz,", 1))
    with pytest.raises(StepFormatError, match=rf"cone\.step: .*#{m.group(1)} \(CartesianPoint\)"):
        load_part(path)


def _slow_on(tessellation, monkeypatch, stalls):
    """Make the mesher stall (sleep far past the guard's limit) whenever ``stalls(face number,
    chord, angle)`` is true; the guard runs the mesher in a forked child, which sees the patch."""
    import time

    real, faces = tessellation.mesh_face, {}

    def mesh_face(face, chord, angle):
        number = next(k for k, f in faces.items() if f.IsSame(face))
        if stalls(number, chord, angle):
            time.sleep(30.0)
        return real(face, chord, angle)

    monkeypatch.setattr(tessellation, "mesh_face", mesh_face)
    return faces


def test_a_face_that_stalls_the_mesher_is_meshed_again_coarser(shapes, monkeypatch):
    from ibfem.importers.step import tessellation as T

    shape = shapes["fillet"]
    faces = _slow_on(T, monkeypatch, lambda n, chord, angle: n == 3 and angle < 0.5)
    faces.update({k + 1: f for k, f in enumerate(T._faces(shape))})
    meshes, warnings = T.mesh_shape(shape, 0.05, 0.25, time_limit=0.5)
    assert sorted(meshes) == list(range(1, len(faces) + 1))
    assert all(m is not None and len(m[1]) for m in meshes.values())
    assert len(warnings) == 1 and warnings[0].startswith("face F3 ") and "0.5 rad" in warnings[0], warnings


def test_a_face_the_mesher_never_finishes_is_an_error_naming_it(shapes, monkeypatch):
    from ibfem.importers.step import tessellation as T

    shape = shapes["cylinder"]
    faces = _slow_on(T, monkeypatch, lambda n, chord, angle: n == 1)
    faces.update({k + 1: f for k, f in enumerate(T._faces(shape))})
    with pytest.raises(StepFormatError, match=r"face F1 \(Cylinder\).*no triangles within 0.5 s"):
        T.mesh_shape(shape, 0.05, 0.25, time_limit=0.5)


def _parabolic_sheet(length: float):
    """The B-spline surface z = x^2 / 10 (mm) over x in [0, 10 length], y in [0, 10]: degree 2
    in u = x / 10 on one span [0, length], degree 1 in v."""
    from OCP.collections import Array1_double, Array1_int, Array2_gp_Pnt
    from OCP.Geom import Geom_BSplineSurface
    from OCP.gp import gp_Pnt

    poles = Array2_gp_Pnt(1, 3, 1, 2)
    for i, (x, z) in enumerate(((0.0, 0.0), (length / 2, 0.0), (length, length**2)), 1):
        for j, y in enumerate((0.0, 1.0), 1):
            poles.SetValue(i, j, gp_Pnt(10 * x, 10 * y, 10 * z))
    knots_u, knots_v, mult_u, mult_v = Array1_double(1, 2), Array1_double(1, 2), Array1_int(1, 2), Array1_int(1, 2)
    for arr, values in ((knots_u, (0.0, length)), (knots_v, (0.0, 1.0)), (mult_u, (3, 3)), (mult_v, (2, 2))):
        for k, value in enumerate(values, 1):
            arr.SetValue(k, value)
    return Geom_BSplineSurface(poles, knots_u, knots_v, mult_u, mult_v, 2, 1)


def _shrink_surface(text: str, length: float) -> str:
    """The STEP text with the face's surface replaced by the same polynomial on u in [0, length]
    only (its control points and knots), its trimming curves (3D and parameter curves) unchanged:
    the face then runs beyond the surface's parameter domain, as some exporters write."""
    m = re.search(r"B_SPLINE_SURFACE_WITH_KNOTS\('',2,1,\(\s*(.*?)\),\.UNSPECIFIED\.,\.F\.,\.F\.,\.F\.,"
                  r"\(3,3\),\(2,2\),\(0\.,([0-9.]+)\)", text, re.S)
    refs = re.findall(r"#(\d+)", m.group(1))
    rows = [(0.0, 0.0), (length / 2, 0.0), (length, length**2)]
    for k, ref in enumerate(refs):
        x, z = rows[k // 2]
        y = float(k % 2)
        text = re.sub(rf"#{ref} = CARTESIAN_POINT\('',\([^)]*\)\);",
                      f"#{ref} = CARTESIAN_POINT('',({10 * x!r},{10 * y!r},{10 * z!r}));", text)
    return text.replace(m.group(0), m.group(0).replace(f"(0.,{m.group(2)})", f"(0.,{length!r})"))


def test_a_face_trimmed_beyond_its_surface_gets_the_surface_extended(tmp_path):
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from ibfem.geometry import primitive_from_dict
    from ibfem.geometry.verify import verify_projection

    face = BRepBuilderAPI_MakeFace(_parabolic_sheet(1.2), 0.0, 1.2, 0.0, 1.0, 1e-7).Face()
    path = S.write_step(face, tmp_path / "sheet.step")
    path.write_text(_shrink_surface(path.read_text(), 1.0))
    part = load_part(path)
    (f,) = part.faces.values()
    assert any("extended beyond its parameter domain" in n for n in f.notes), f.notes
    V = np.asarray(f.mesh.vertices)
    assert V[:, 0].max() == pytest.approx(0.012, rel=1e-9)  # the face reaches x = 12 mm
    parabola = np.column_stack([np.linspace(0.0, 0.012, 41), np.full(41, 0.004), np.zeros(41)])
    parabola[:, 2] = 100.0 * parabola[:, 0] ** 2  # z = x^2 / 10 in mm
    assert np.abs(f.surface.project(parabola).distances).max() < 1e-12
    # the surface as the file gives it, clamped to u <= 1, misses the face's far part
    clamped = primitive_from_dict(dict(f.surface.to_dict(), knots_u=[0.0] * 3 + [1.0] * 3,
                                       control_points=[[[0, 0, 0], [0, 0.01, 0]], [[0.005, 0, 0], [0.005, 0.01, 0]],
                                                       [[0.01, 0, 0.01], [0.01, 0.01, 0.01]]]))
    assert np.abs(clamped.project(parabola).distances).max() > 1e-4
    report = verify_projection(part)
    assert report["verdict"] == "pass", report["reason"]


def test_step_string_escapes_decode():
    from ibfem.importers.step.step_text import decode_step_string

    # ISO 10303-21 escapes: \S\ shifts by 128, \X\ one ISO 8859-1 byte, \X2\ UTF-16, '' a quote
    assert decode_step_string(b"caf\\S\\i") == "caf\u00e9"
    assert decode_step_string(b"\\X\\C4hre") == "\u00c4hre"
    assert decode_step_string(b"\\X2\\041F0440043804300440\\X0\\ 1") == "\u041f\u0440\u0438\u0430\u0440 1"
    assert decode_step_string(b"it''s") == "it's"
    assert decode_step_string("Größe".encode("utf-8")) == "Größe"  # UTF-8 as written by recent exporters


@pytest.mark.parametrize("written, expected", [
    ("Деталь1".encode("cp1251"), "Деталь1"),  # the Windows code page, unescaped (SolidWorks)
    ("Деталь1".encode("utf-8"), "Деталь1"),
    (b"\\X2\\0414043504420430043B044C\\X0\\1", "Деталь1"),
], ids=["windows-1251", "utf-8", "X2-escape"])
def test_non_ascii_names_come_out_as_written(shapes, tmp_path, written, expected):
    path = S.write_step(shapes["cylinder"], tmp_path / "cylinder.step")
    raw = path.read_bytes().replace(b"MANIFOLD_SOLID_BREP('',", b"MANIFOLD_SOLID_BREP('" + written + b"',")
    path.write_bytes(raw)
    assert [b.name for b in load_part(path).bodies.values()] == [expected]


def test_an_unnamed_solid_takes_its_products_name(shapes, tmp_path):
    path = S.write_step(shapes["cylinder"], tmp_path / "cylinder.step")
    text = re.sub(r"PRODUCT\('[^']*',\s*'[^']*'", "PRODUCT('R-12','roller'", path.read_text(), count=1)
    path.write_text(text)
    assert "MANIFOLD_SOLID_BREP('',"in text
    assert [b.name for b in load_part(path).bodies.values()] == ["roller"]


def _box_faces():
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox
    from OCP.TopAbs import TopAbs_ShapeEnum
    from OCP.TopExp import TopExp_Explorer

    box = BRepPrimAPI_MakeBox(20.0, 30.0, 10.0).Shape()
    explorer, faces = TopExp_Explorer(box, TopAbs_ShapeEnum.TopAbs_FACE), []
    while explorer.More():
        faces.append(explorer.Current())
        explorer.Next()
    return faces


def _solid_of(faces):
    from OCP.BRep import BRep_Builder
    from OCP.TopoDS import TopoDS_Shell, TopoDS_Solid

    builder, shell, solid = BRep_Builder(), TopoDS_Shell(), TopoDS_Solid()
    builder.MakeShell(shell)
    for f in faces:
        builder.Add(shell, f)
    builder.MakeSolid(solid)
    builder.Add(solid, shell)
    return solid


def test_an_open_shell_is_a_sheet_and_no_solid(shapes, tmp_path):
    from ibfem.geometry.solids import PartSolid

    path = S.write_step(_solid_of(_box_faces()[:5]), tmp_path / "open_box.step")  # a box without its top
    part = load_part(path)
    assert [b.body_type for b in part.bodies.values()] == ["SHEET"] and len(part.faces) == 5
    with pytest.raises(ValueError, match="sheet body .*not a closed solid"):
        PartSolid(part)


def test_a_solid_oriented_inward_is_reversed(shapes):
    from pathlib import Path

    from ibfem.importers.step.part import build_part
    from ibfem.importers.step.tessellation import mesh_shape

    solid = _solid_of([f.Reversed() for f in _box_faces()])  # every face's normal points into the box
    meshes, _ = mesh_shape(solid, 0.5, 0.25)
    part = build_part(solid, Path("inward"), meshes=meshes)
    assert any("oriented inward" in w and "reversed" in w for w in part.warnings), part.warnings
    assert part.metadata["volumes"]["B1"] == pytest.approx(20.0 * 30.0 * 10.0, rel=1e-12)  # built in mm here
    centre = np.array([10.0, 15.0, 5.0])
    for face in part.faces.values():  # outward: away from the box's centre
        V = np.asarray(face.mesh.vertices)
        outward = face.surface.project(V).normals * face.orientation
        assert np.all(np.einsum("ij,ij->i", outward, V - centre) > 0), face.id


def test_bodies_sharing_a_name_are_chosen_by_number(shapes, tmp_path):
    from OCP.BRep import BRep_Builder
    from OCP.gp import gp_Trsf, gp_Vec
    from OCP.TopLoc import TopLoc_Location
    from OCP.TopoDS import TopoDS_Compound

    from ibfem.geometry.solids import PartSolid

    builder, compound = BRep_Builder(), TopoDS_Compound()
    builder.MakeCompound(compound)
    for dx in (0.0, 100.0):
        move = gp_Trsf()
        move.SetTranslation(gp_Vec(dx, 0.0, 0.0))
        builder.Add(compound, shapes["sphere"].Moved(TopLoc_Location(move)))
    path = S.write_step(compound, tmp_path / "two.step")  # an assembly placing one part twice
    text = path.read_text()
    part_product = re.findall(r"PRODUCT\('[^']*',\s*'[^']*'", text)[-1]  # the first is the assembly's
    path.write_text(text.replace(part_product, "PRODUCT('ball','ball'"))
    part = load_part(path)
    assert [b.name for b in part.bodies.values()] == ["ball", "ball"]
    with pytest.raises(ValueError, match=r"2 bodies have this name; choose one: ball#1 \(B1\), ball#2 \(B2\)"):
        PartSolid(part, "ball")
    second = PartSolid(part, "ball#2")
    assert second.body.id == "B2" and second.bounds[0][0] > 0.05  # the one moved 100 mm along x


def test_an_extrusion_beyond_its_profile_curve_gets_the_curve_extended(tmp_path):
    """A face of a surface of linear extrusion whose B-spline profile (the parabola z = x^2 / 10 mm)
    the file cuts short at x = 10 mm while the face runs to x = 12 mm."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge
    from OCP.BRepPrimAPI import BRepPrimAPI_MakePrism
    from OCP.collections import Array1_double, Array1_gp_Pnt, Array1_int
    from OCP.Geom import Geom_BSplineCurve
    from OCP.gp import gp_Pnt, gp_Vec

    from ibfem.geometry.verify import verify_projection

    poles, knots, mults = Array1_gp_Pnt(1, 3), Array1_double(1, 2), Array1_int(1, 2)
    for i, (x, z) in enumerate(((0.0, 0.0), (0.6, 0.0), (1.2, 1.44)), 1):
        poles.SetValue(i, gp_Pnt(10 * x, 0.0, 10 * z))
    for k, (t, m) in enumerate(((0.0, 3), (1.2, 3)), 1):
        knots.SetValue(k, t)
        mults.SetValue(k, m)
    edge = BRepBuilderAPI_MakeEdge(Geom_BSplineCurve(poles, knots, mults, 2)).Edge()
    path = S.write_step(BRepPrimAPI_MakePrism(edge, gp_Vec(0.0, 10.0, 0.0)).Shape(), tmp_path / "sweep.step")
    text = path.read_text()
    swept = re.search(r"SURFACE_OF_LINEAR_EXTRUSION\('',#(\d+),", text).group(1)
    curve = re.search(rf"#{swept} = B_SPLINE_CURVE_WITH_KNOTS\('',2,\(#(\d+),#(\d+),#(\d+)\)[^;]*;", text)
    for ref, xyz in zip(curve.groups(), ("0.,0.,0.", "5.,0.,0.", "10.,0.,10.")):  # the same parabola, u <= 1
        text = re.sub(rf"#{ref} = CARTESIAN_POINT\('',\([^)]*\)\);", f"#{ref} = CARTESIAN_POINT('',({xyz}));", text)
    path.write_text(text.replace(curve.group(0), curve.group(0).replace("(0.,1.2)", "(0.,1.)")))
    part = load_part(path)
    (f,) = [f for f in part.faces.values() if f.surface_type == "SWEEP"]
    assert any("profile curve extended" in n for n in f.notes), f.notes
    x = np.linspace(0.0, 0.012, 41)
    parabola = np.column_stack([x, np.full(41, 0.005), 100.0 * x**2])
    assert np.abs(f.surface.project(parabola).distances).max() < 1e-12
    assert verify_projection(part)["verdict"] == "pass"


def test_a_triangulation_of_part_of_a_face_is_not_taken(shapes):
    """OpenCascade's mesher sometimes returns triangles over part of a face only (an Inventor
    spring's helical face: 7 % of its area): the triangles' area is compared with the face's."""
    from ibfem.importers.step import tessellation as T

    face = T._faces(shapes["torus"])[0]
    data = T.mesh_face(face, 0.05, 0.25)
    assert data is not None and data[2] and T._covers(face, data[:2])
    uv, triangles = data[:2]
    assert not T._covers(face, (uv, triangles[: len(triangles) // 2]))


def test_an_iges_solid_takes_its_directory_entry_label(shapes, tmp_path):
    # Inventor 2011 labels its solid (MSBO, entity 186) 'Solido1' with subscript 0 in the
    # directory entry's label field (columns 57-64, subscript 65-72)
    path = S.write_iges(shapes["box"], tmp_path / "box.igs")
    lines = path.read_text().splitlines()
    first = next(i for i, line in enumerate(lines) if line[72:73] == "D" and line[:8].strip() == "186"
                 and int(line[73:80]) % 2 == 1)
    second = lines[first + 1]
    lines[first + 1] = second[:56] + "Solido1".rjust(8) + "0".rjust(8) + second[72:]
    path.write_text("\n".join(lines) + "\n")
    assert [b.name for b in load_part(str(path)).bodies.values()] == ["Solido1"]


def test_a_face_of_revolution_of_an_unbounded_line_is_exact(tmp_path):
    """FreeCAD writes revolved faces whose profile is a LINE (unbounded): the surface is cut to the
    face's range of the profile before its B-spline conversion. Here a line through (20, 0, 0) and
    (30, 0, 10) mm turned about z (a cone of semi-angle 45 degrees, apex at z = -20 mm), the face
    its part 0 <= v <= 10 mm along the line over a quarter turn: every mesh node on the cone."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.Geom import Geom_Line, Geom_SurfaceOfRevolution
    from OCP.gp import gp_Ax1, gp_Dir, gp_Pnt

    line = Geom_Line(gp_Pnt(20.0, 0.0, 0.0), gp_Dir(1.0, 0.0, 1.0))
    surface = Geom_SurfaceOfRevolution(line, gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)))
    face = BRepBuilderAPI_MakeFace(surface, 0.0, math.pi / 2, 0.0, 10.0 * math.sqrt(2.0), 1e-7).Face()
    part = load_part(S.write_step(face, tmp_path / "revolved.step"))
    (f,) = part.faces.values()
    assert f.surface_type == "SPUN" and f.surface is not None
    x = np.asarray(f.mesh.vertices, float) * 1000.0  # mm
    radial = np.hypot(x[:, 0], x[:, 1])
    np.testing.assert_allclose(radial - (x[:, 2] + 20.0), 0.0, atol=1e-9)  # on the cone r = z + 20
    feet = np.asarray(f.surface.project(x / 1000.0).points, float)
    np.testing.assert_allclose(feet, x / 1000.0, atol=1e-12)
