"""2D profiles from imported parts (the ``onshape`` shape): areas and distances against
the closed forms of each studio's design, edge naming, and clear errors."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ibfem.importers.onshape.profile import face_profile, profile_from_shape, section_profile
from test_onshape_support import FIXTURES, cached_part, generator


def _shape(studio, **kw):
    return {"type": "onshape", "path": str(FIXTURES / studio), **kw}


def _cap(part, body_name, sign=+1, axis=None):
    """The planar face of a body whose outward normal is sign * axis (default z)."""
    axis = np.array([0.0, 0.0, 1.0]) if axis is None else axis
    body = next(b for b in part.bodies.values() if b.name == body_name)
    for fid in body.face_ids:
        f = part.faces[fid]
        if f.surface_type == "PLANE":
            n = np.asarray(f.surface.to_dict()["normal"]) * f.orientation
            if np.dot(n, axis) * sign > 1 - 1e-9:
                return fid
    raise AssertionError("no cap")


def test_half_cylinder_face():
    part = cached_part("half_cylinder_on_block")
    fid = _cap(part, "Half cylinder")
    prof = profile_from_shape(_shape("half_cylinder_on_block", face=fid))
    R = 0.05
    assert prof.area == pytest.approx(math.pi * R**2 / 2, rel=1e-12)
    assert set(prof.edge_names) <= set(part.edges)  # named by Onshape edge ids
    types = sorted(type(prof.edge(n)).__name__ for n in prof.edge_names)
    assert types == ["Arc", "Segment"]
    # exact signed distance (positive inside): nearest is the arc at (0, 0.02)
    phi = prof.signed_distance(np.array([[0.0, 0.02], [0.0, -0.01], [0.03, 0.045]]))
    assert phi[0] == pytest.approx(0.02, abs=1e-15)
    assert phi[1] == pytest.approx(-0.01, abs=1e-15)
    assert phi[2] == pytest.approx(min(R - math.hypot(0.03, 0.005), 0.005), abs=1e-15)


def test_block_face_and_contact_point():
    part = cached_part("half_cylinder_on_block")
    prof = face_profile(part, _cap(part, "Block"))
    lo, hi = prof.bounds
    assert np.allclose(lo, [-0.1, -0.1], atol=1e-15) and np.allclose(hi, [0.1, 0.0], atol=1e-15)
    cyl = face_profile(part, _cap(part, "Half cylinder"))
    # the two bodies touch at the origin
    assert abs(prof.signed_distance(np.zeros((1, 2)))[0]) < 1e-15
    assert abs(cyl.signed_distance(np.zeros((1, 2)))[0]) < 1e-15


def test_a_face_with_a_hole_in_a_rotated_part():
    """block_hole_fillet is placed with a rotation: its top face is not axis-aligned."""
    part = cached_part("block_hole_fillet")
    body = next(iter(part.bodies.values()))
    planes = [f for f in body.face_ids if part.faces[f].surface_type == "PLANE"]
    inner = [f for f in planes if len(part.faces[f].loops) == 2]
    a, b, rc = 0.04, 0.03, 0.006
    rounded = 4 * a * b - (4 - math.pi) * rc**2
    areas = sorted(face_profile(part, f).area for f in inner)
    assert areas == pytest.approx(sorted([rounded - math.pi * 0.01**2, rounded - math.pi * 0.013**2]), rel=1e-12)
    prof = face_profile(part, inner[0])
    assert len(prof.loops) == 2
    kinds = {type(c).__name__ for lp in prof.loops for c in lp}
    assert kinds == {"Segment", "Arc"}


def test_elliptic_edges():
    part = cached_part("half_ellipse_on_block")
    prof = face_profile(part, _cap(part, "Half ellipse"))
    assert prof.area == pytest.approx(math.pi * 0.05 * 0.025 / 2, rel=1e-12)
    assert {type(c).__name__ for c in prof.loops[0]} == {"EllipticArc", "Segment"}
    # radius of curvature 0.1 m at the contact point (bottom of the ellipse)
    arc = next(c for c in prof.loops[0] if type(c).__name__ == "EllipticArc")
    t = arc.project(np.array([[0.0, -0.001]])).parameters
    assert abs(1.0 / arc.curvature(t)[0]) == pytest.approx(0.1, rel=1e-9)
    part = cached_part("elliptical_extrusion")  # a closed ellipse in a rotated plane
    caps = [f for f in part.faces if part.faces[f].surface_type == "PLANE"]
    for fid in caps:
        assert face_profile(part, fid).area == pytest.approx(math.pi * 0.03 * 0.015, rel=1e-12)


def test_bspline_edges():
    """The swept spline's cap: three segments and a B-spline; the area against Green's
    theorem on a fine polygon of the design curve (the generator's own evaluation)."""
    part = cached_part("swept_spline")
    spline_edges = {e.id for e in part.edges.values() if e.curve_type == "BCURVE"}
    caps = [f for f in part.faces if part.faces[f].surface_type == "PLANE" and
            spline_edges & {c.edge_id for c in part.faces[f].loops[0].coedges}]
    assert len(caps) == 2
    gen = generator()
    ctrl = np.array([[0.03, 0.01], [0.02, 0.02], [0.01, 0.005], [-0.005, 0.025], [-0.02, 0.012], [-0.03, 0.01]])
    knots = [0.0, 0.0, 0.0, 0.0, 1 / 3, 2 / 3, 1.0, 1.0, 1.0, 1.0]
    C, _ = gen.nurbs_eval(np.linspace(0, 1, 40001), 3, knots, ctrl)
    P = np.vstack([[-0.03, -0.01], [0.03, -0.01], C])  # counter-clockwise
    area = 0.5 * np.sum(P[:, 0] * np.roll(P[:, 1], -1) - np.roll(P[:, 0], -1) * P[:, 1])
    for fid in caps:
        prof = face_profile(part, fid)
        assert {type(c).__name__ for c in prof.loops[0]} == {"BSplineArc", "Segment"}
        assert prof.area == pytest.approx(area, rel=1e-9)


def test_sections_of_prisms():
    R1, R2 = 0.05, 0.1
    seat = profile_from_shape(_shape("cylinder_in_concave_seat", section={"origin": [0, 0, 0.013], "normal": [0, 0, 1]},
                                     body="Concave seat"))
    assert seat.area == pytest.approx(0.2 * 0.12 - (R2**2 * math.acos(0.8) - 0.08 * 0.06), rel=1e-12)
    part = cached_part("cylinder_in_concave_seat")
    body = next(b for b in part.bodies.values() if b.name == "Concave seat")
    # section edges are named by the side faces they cut
    assert set(seat.edge_names) <= set(body.face_ids)
    groove = next(n for n in seat.edge_names if part.faces[n].surface_type == "CYLINDER")
    # the seat's groove is concave: phi just above its lowest point is negative, below positive
    assert seat.signed_distance(np.array([[0.0, 1e-3]]))[0] == pytest.approx(-1e-3, abs=1e-15)
    assert seat.signed_distance(np.array([[0.0, -1e-3]]))[0] == pytest.approx(1e-3, abs=1e-15)
    assert type(seat.edge(groove)).__name__ == "Arc"
    cyl = section_profile(part, [0, 0, 0.01], [0, 0, -1], body="Half cylinder")
    assert cyl.area == pytest.approx(math.pi * R1**2 / 2, rel=1e-12)


def test_v_groove_faces_are_inclined_15_degrees():
    part = cached_part("cylinder_on_v_groove")
    prof = profile_from_shape(_shape("cylinder_on_v_groove", face=_cap(part, "V-groove block")))
    slopes = []
    for n in prof.edge_names:
        c = prof.edge(n)
        d = c.end - c.start
        if abs(d[0]) > 0 and 0 < abs(d[1]) < abs(d[0]):
            slopes.append(math.degrees(math.atan2(abs(d[1]), abs(d[0]))))
    assert slopes == pytest.approx([15.0, 15.0], abs=1e-12)
    cyl = face_profile(part, _cap(part, "Half cylinder"))
    # the cylinder touches both groove faces: both profiles have distance 0 at the contact points
    x = 0.05 * math.sin(math.radians(15))
    yc = 0.05 / math.cos(math.radians(15)) - 0.06 * math.tan(math.radians(15))
    touch = np.array([[x, yc - 0.05 * math.cos(math.radians(15))], [-x, yc - 0.05 * math.cos(math.radians(15))]])
    assert np.max(np.abs(prof.signed_distance(touch))) < 1e-15
    assert np.max(np.abs(cyl.signed_distance(touch))) < 1e-15


def test_transform_keys():
    part = cached_part("half_cylinder_on_block")
    fid = _cap(part, "Block")
    prof = profile_from_shape(_shape("half_cylinder_on_block", face=fid, rotate_deg=90.0, translate=[1.0, 2.0]))
    lo, hi = prof.bounds
    assert np.allclose(lo, [1.0, 1.9], atol=1e-12) and np.allclose(hi, [1.1, 2.1], atol=1e-12)


@pytest.mark.parametrize("kw,msg", [
    ({}, "shape: give exactly one of 'face'"),
    ({"face": "NOPE"}, "shape.face: no face 'NOPE'; planar faces:"),
    ({"section": {"origin": [0, 0, 0.01], "normal": [0, 0, 1]}}, "shape.section: the part has 2 bodies"),
    ({"section": {"origin": [0, 0, 0.5], "normal": [0, 0, 1]}, "body": "Block"}, "shape.section: section plane at 0.5"),
    ({"section": {"origin": [0, 0, 0.01], "normal": [1, 1, 0]}, "body": "Block"}, "shape.section: body"),
    ({"face": "JQZ", "colour": "red"}, "shape.colour: unknown key"),
    ({"face": "JQZ", "x_axis": [0, 0, 1]}, "shape.face: x_axis [0.0, 0.0, 1.0] is along the plane normal"),
])
def test_errors(kw, msg):
    with pytest.raises(ValueError) as info:
        profile_from_shape(_shape("half_cylinder_on_block", **kw))
    assert str(info.value).startswith(msg)


def test_non_planar_face_and_non_prism():
    part = cached_part("cone_sphere")
    cone = next(f for f in part.faces.values() if f.surface_type == "CONE")
    with pytest.raises(ValueError, match="is not planar"):
        face_profile(part, cone.id)
    with pytest.raises(ValueError, match="not parallel to the section normal"):
        section_profile(part, [0, 0, 0], [0, 0, 1], body="Cone with sphere cap")
    with pytest.raises(ValueError, match=r"shape\.path: .*missing tessellatedfaces.json"):
        profile_from_shape({"type": "onshape", "path": str(FIXTURES), "face": "X"})


def test_a_zero_section_normal_is_a_clear_error():
    # make fuzz: a section normal of [0, 0, 0] divided by zero (RuntimeWarning) before failing
    import warnings

    shape = {"type": "onshape", "path": str(FIXTURES / "half_cylinder_on_block"),
             "section": {"origin": [0, 0, 0.01], "normal": [0, 0, 0]}, "body": "Block"}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=r"section.*non-zero"):
            profile_from_shape(shape)
