"""Volumes and centroids of CAD bodies, by the faces' parameter-domain moments and, for parts
without them, by the divergence theorem over the faces' quadrature, which closes up with the
strips between the tessellation's chords and the exact trimming curves (a flat face bounded by a
circle loses the segments between the circle and its chords otherwise); both about the body's own
centre, so they hold at any placement. Checked against closed forms: a cylinder, a box with a
drilled hole (strips wound against the face), a rounded box (Steiner's formula), all moved far
from the origin."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("OCP")

import test_step_support as S  # noqa: E402
from ibfem.geometry.solids.part_solid import PartSolid  # noqa: E402
from ibfem.importers.step import load_part  # noqa: E402

MM = 1e-3


def _moved(shape, offset_mm):
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Transform
    from OCP.gp import gp_Trsf, gp_Vec

    move = gp_Trsf()
    move.SetTranslation(gp_Vec(*offset_mm))
    return BRepBuilderAPI_Transform(shape, move, True).Shape()


def _drilled_box():
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCylinder
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

    box = BRepPrimAPI_MakeBox(40.0, 30.0, 10.0).Shape()
    hole = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(20.0, 15.0, -1.0), gp_Dir(0, 0, 1)), 8.0, 12.0).Shape()
    return BRepAlgoAPI_Cut(box, hole).Shape()


CASES = {
    "cylinder": (lambda: S.primitives()["cylinder"],
                 lambda: math.pi * S.CYLINDER["radius"] ** 2 * S.CYLINDER["height"]),
    "drilled box": (_drilled_box, lambda: 40.0 * 30.0 * 10.0 - math.pi * 8.0**2 * 10.0),
    "rounded box": (S.filleted_box, lambda: S.rounded_box_volume(*S.BOX, S.FILLET)),
}


def _without_moments(part):
    """The part as an importer without the faces' parameter-domain moments gives it: PartSolid
    falls back to the faces' quadrature with the trimming strips."""
    from dataclasses import replace

    part.faces = {k: replace(f, moments=None) for k, f in part.faces.items()}
    return part


def _volumes(name, offsets, tmp_path, moments=True):
    from ibfem.importers.step.reader import _quiet_messenger

    _quiet_messenger()
    build, exact = CASES[name]
    for k, offset in enumerate(offsets):
        path = S.write_step(_moved(build(), offset), tmp_path / f"part{k}.step")
        part = load_part(str(path))
        occ = next(iter(part.metadata["volumes"].values()))
        yield PartSolid(part if moments else _without_moments(part)).volume, occ, exact() * MM**3


FAR = (3.0e4, -2.0e4, 1.0e4)  # 30 m away (mm)


def test_a_drilled_box_far_from_the_origin_has_its_exact_volume_and_centroid(tmp_path):
    from ibfem.importers.step.reader import _quiet_messenger

    _quiet_messenger()
    path = S.write_step(_moved(_drilled_box(), FAR), tmp_path / "box.step")
    exact = CASES["drilled box"][1]() * MM**3
    centre = (np.array(FAR) + [20.0, 15.0, 5.0]) * MM  # the hole is centred in the box
    for moments in (True, False):  # the parameter-domain moments, and the strips without them
        part = load_part(str(path))
        solid = PartSolid(part if moments else _without_moments(part))
        assert solid.volume == pytest.approx(exact, rel=1e-7)  # without the strips: -1.4e-4
        assert np.abs(solid.centroid - centre).max() < 1e-7 * solid.size


@pytest.mark.slow
@pytest.mark.parametrize("moments", [True, False])
@pytest.mark.parametrize("name", list(CASES))
def test_volume_matches_the_closed_form_at_any_placement(name, moments, tmp_path):
    for ours, occ, exact in _volumes(name, [(0.0, 0.0, 0.0), FAR], tmp_path, moments):
        assert ours == pytest.approx(exact, rel=1e-7)
        assert ours == pytest.approx(occ, rel=1e-6)
