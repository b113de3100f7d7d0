"""What real exporters write (issue 33), reproduced with parts OpenCascade writes inside the test and
then edits the way other CAD systems write them: presentation and unit entities OpenCascade's parser
does not accept, ... Each test checks the import against the parameters the part was built with."""

from __future__ import annotations

import math
import re

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
