"""Volumes and centroids of CAD solids integrated over each face's (u, v) parameter domain with
the exact surface (geometry.solids.domain_moments, importers.step.face_moments).

The rules are checked on closed forms without OpenCascade: a disc and an annulus trimmed by
circles (the strips between the chords and the curves), a triangulation with a piece missing at
its boundary (the gap between the trimming curves' polygon and the triangles), a surface whose
area element jumps along a line (the cut at a low-continuity knot), and a sphere over its
rectangle of parameters (degenerate at its poles), at the origin and far from it. The closed
forms of OpenCascade's elementary surfaces and the vectorised evaluation of a located B-spline
surface (periodic beyond its knots, as OpenCascade continues it) are checked against its own
evaluation. Then parts
written by OpenCascade to STEP and imported: a screw thread swept along a helix (B-spline flanks
bent sharply across the thread, on which mapping the triangles onto the surface by closest
points was 1.6e-2 off in volume), also turned and moved far from the origin, against
OpenCascade's BRepGProp volume and centre of mass.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from ibfem.geometry.solids.domain_moments import (domain_rule, face_moments, gap_rule, solid_moments,
                                                  strip_parameters, strip_rule)


def _plane(uv):
    n = len(uv)
    return np.column_stack([uv, np.zeros(n)]), np.tile([1.0, 0.0, 0.0], (n, 1)), np.tile([0.0, 1.0, 0.0], (n, 1))


def _polygon_chords(radius, n, side):
    """The chords of a regular n-gon inscribed in a circle, with the circle's arcs sampled as
    strip_rule wants them (side: +1 for the outer boundary, -1 for a hole, both ccw)."""
    t = np.linspace(0.0, 2.0 * math.pi, n + 1)
    t0, t1 = t[:-1], t[1:]
    s = strip_parameters()
    ts = t0[:, None] + s[None] * (t1 - t0)[:, None]
    curve = radius * np.stack([np.cos(ts), np.sin(ts)], axis=-1)
    tangent = radius * np.stack([-np.sin(ts), np.cos(ts)], axis=-1)
    a = radius * np.column_stack([np.cos(t0), np.sin(t0)])
    b = radius * np.column_stack([np.cos(t1), np.sin(t1)])
    return strip_rule(a, b, np.full(n, float(side)), curve, tangent, t1 - t0)


def _disc_triangulation(n, radius=1.0):
    t = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    uv = np.vstack([[0.0, 0.0], radius * np.column_stack([np.cos(t), np.sin(t)])])
    triangles = np.array([[0, 1 + k, 1 + (k + 1) % n] for k in range(n)])
    return uv, triangles


def _area(*rules):
    points, weights = (np.concatenate(v) for v in zip(*rules))
    return face_moments(points, weights, _plane).area


def test_strips_close_a_disc_and_an_annulus_on_their_circles():
    n = 12
    uv, triangles = _disc_triangulation(n)
    polygon = domain_rule(uv, triangles)
    assert _area(polygon) == pytest.approx(0.5 * n * math.sin(2 * math.pi / n))  # the 12-gon: 4.5 % short
    assert _area(polygon, _polygon_chords(1.0, n, +1)) == pytest.approx(math.pi, rel=1e-12)
    # an annulus 0.5 < r < 1: the hole's polygon taken as a (clockwise) boundary, its strips negative
    inner = 0.5 * uv[1:]
    ring = np.vstack([uv[1:], inner])
    quads = [[k, (k + 1) % n, n + (k + 1) % n, n + k] for k in range(n)]
    tri = np.array([[q[0], q[1], q[2]] for q in quads] + [[q[0], q[2], q[3]] for q in quads])
    area = _area(domain_rule(ring, tri), _polygon_chords(1.0, n, +1), _polygon_chords(0.5, n, -1))
    assert area == pytest.approx(math.pi * (1.0 - 0.25), rel=1e-12)


def test_a_boundary_triangle_the_mesher_left_out_is_filled_from_the_polygon():
    n = 12
    uv, triangles = _disc_triangulation(n)
    chords = np.array([[1 + k, 1 + (k + 1) % n] for k in range(n)])  # the polygon, domain on the left
    kept = triangles[1:]  # the triangle (centre, 1, 2) missing: its chord is not on the boundary
    full = _area(domain_rule(uv, triangles))
    assert _area(domain_rule(uv, kept)) == pytest.approx(full * (n - 1) / n)
    assert _area(domain_rule(uv, kept), gap_rule(uv, kept, chords)) == pytest.approx(full, rel=1e-14)


def test_triangles_are_cut_where_the_area_element_jumps():
    """x = (phi(u), v, 0), phi' = 1 for u < 0.5 and 2 beyond: the area of [0, 1]^2 is 1.5."""
    def surface(uv):
        n = len(uv)
        slope = np.where(uv[:, 0] < 0.5, 1.0, 2.0)
        x = np.column_stack([np.where(uv[:, 0] < 0.5, uv[:, 0], 2 * uv[:, 0] - 0.5), uv[:, 1], np.zeros(n)])
        return x, np.column_stack([slope, np.zeros(n), np.zeros(n)]), np.tile([0.0, 1.0, 0.0], (n, 1))

    uv = np.array([[0, 0], [0.4, 0], [1, 0], [0, 1], [0.4, 1], [1, 1]], float)
    triangles = np.array([[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]])
    uncut = face_moments(*domain_rule(uv, triangles), surface).area
    cut = face_moments(*domain_rule(uv, triangles, cuts=([0.5], [])), surface).area
    assert abs(uncut - 1.5) > 1e-2
    assert cut == pytest.approx(1.5, rel=1e-14)


def _sphere_moments(centre, radius, n=24):
    """The sphere's one face over its parameter rectangle (u around, v from pole to pole)."""
    u, v = np.meshgrid(np.linspace(0, 2 * math.pi, 2 * n + 1), np.linspace(-math.pi / 2, math.pi / 2, n + 1))
    uv = np.column_stack([u.ravel(), v.ravel()])
    k = np.arange((n + 1) * (2 * n + 1)).reshape(n + 1, 2 * n + 1)
    a, b, c, d = k[:-1, :-1].ravel(), k[:-1, 1:].ravel(), k[1:, 1:].ravel(), k[1:, :-1].ravel()
    triangles = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])

    def surface(p):
        cu, su, cv, sv = np.cos(p[:, 0]), np.sin(p[:, 0]), np.cos(p[:, 1]), np.sin(p[:, 1])
        x = centre + radius * np.column_stack([cv * cu, cv * su, sv])
        return x, radius * np.column_stack([-cv * su, cv * cu, 0 * cv]), radius * np.column_stack([-sv * cu, -sv * su, cv])

    return face_moments(*domain_rule(uv, triangles), surface)


@pytest.mark.parametrize("centre", [(0.0, 0.0, 0.0), (3.0e4, -2.0e4, 1.0e4)])
def test_a_sphere_has_its_volume_and_centre_anywhere(centre):
    radius = 2.0
    volume, centroid = solid_moments([_sphere_moments(np.array(centre), radius)])
    assert volume == pytest.approx(4 / 3 * math.pi * radius**3, rel=1e-8)
    assert np.abs(centroid - centre).max() < 1e-9 * radius


# ---- with OpenCascade -------------------------------------------------------------------------

def _occ():
    pytest.importorskip("OCP")
    from ibfem.importers.step.reader import _quiet_messenger

    _quiet_messenger()


def _frames():
    from OCP.gp import gp_Ax3, gp_Dir, gp_Pnt

    right = gp_Ax3(gp_Pnt(1.0, -2.0, 0.5), gp_Dir(0.0, 0.6, 0.8), gp_Dir(1.0, 0.0, 0.0))
    left = gp_Ax3(gp_Pnt(1.0, -2.0, 0.5), gp_Dir(0.0, 0.6, 0.8), gp_Dir(1.0, 0.0, 0.0))
    left.YReverse()  # an indirect (left-handed) frame, as some exporters write
    return right, left


def test_elementary_surfaces_in_closed_form_are_opencascades():
    _occ()
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.Geom import (Geom_ConicalSurface, Geom_CylindricalSurface, Geom_Plane, Geom_SphericalSurface,
                          Geom_ToroidalSurface)
    from OCP.gp import gp_Pnt, gp_Vec

    from ibfem.importers.step.face_moments import _closed_form

    rng = np.random.default_rng(3)
    uv = np.column_stack([rng.uniform(-3, 3, 40), rng.uniform(-1.2, 1.2, 40)])
    p, du, dv = gp_Pnt(), gp_Vec(), gp_Vec()
    for frame in _frames():
        for geom in (Geom_Plane(frame), Geom_CylindricalSurface(frame, 2.0), Geom_ConicalSurface(frame, 0.3, 1.5),
                     Geom_SphericalSurface(frame, 2.0), Geom_ToroidalSurface(frame, 3.0, 1.0)):
            surface = BRepAdaptor_Surface(BRepBuilderAPI_MakeFace(geom, 1e-7).Face(), False)
            ours = np.concatenate(_closed_form(surface)(uv), axis=1)
            theirs = []
            for u, v in uv:
                surface.D1(float(u), float(v), p, du, dv)
                theirs.append([*p.Coord(), *du.Coord(), *dv.Coord()])
            assert np.abs(ours - np.array(theirs)).max() < 1e-13, type(geom).__name__


def _helix(turns, pitch, radius):
    """A helix (mm) on a cylinder about z, as a wire."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeWire
    from OCP.BRepLib import BRepLib
    from OCP.Geom import Geom_CylindricalSurface
    from OCP.Geom2d import Geom2d_Line
    from OCP.gp import gp_Ax3, gp_Dir, gp_Dir2d, gp_Pnt, gp_Pnt2d

    cylinder = Geom_CylindricalSurface(gp_Ax3(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), radius)
    helix = BRepBuilderAPI_MakeEdge(Geom2d_Line(gp_Pnt2d(0, 0), gp_Dir2d(2 * math.pi, pitch)), cylinder,
                                    0.0, turns * math.hypot(2 * math.pi, pitch)).Edge()
    BRepLib.BuildCurves3d_s(helix)
    return BRepBuilderAPI_MakeWire(helix).Wire()


def _swept(profile, helix):
    """The solid of a closed profile swept along a helix about z, the axis kept (B-spline faces)."""
    from OCP.BRepOffsetAPI import BRepOffsetAPI_MakePipeShell
    from OCP.gp import gp_Dir

    pipe = BRepOffsetAPI_MakePipeShell(helix)
    pipe.SetMode(gp_Dir(0, 0, 1))
    pipe.Add(profile)
    pipe.Build()
    pipe.MakeSolid()
    return pipe.Shape()


def _thread(turns=1.0, pitch=1.25, radius=4.0, depth=0.7):
    """A screw thread (mm): a trapezoid swept along a helix."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakePolygon
    from OCP.gp import gp_Pnt

    h = 0.45 * pitch
    profile = BRepBuilderAPI_MakePolygon(gp_Pnt(radius, 0, -h), gp_Pnt(radius + depth, 0, -0.05),
                                         gp_Pnt(radius + depth, 0, 0.05), gp_Pnt(radius, 0, h), True).Wire()
    return _swept(profile, _helix(turns, pitch, radius))


def _spring(turns=3.0, pitch=6.0, radius=10.0, wire=1.5):
    """A helical spring (mm): a circle swept along a helix."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeWire
    from OCP.gp import gp_Ax2, gp_Circ, gp_Dir, gp_Pnt

    start = gp_Ax2(gp_Pnt(radius, 0, 0), gp_Dir(0, 2 * math.pi * radius, pitch))
    profile = BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(gp_Circ(start, wire)).Edge()).Wire()
    return _swept(profile, _helix(turns, pitch, radius))


def _turned(shape, angle=0.7, axis=(1.0, 2.0, 3.0), offset=(3.0e4, -2.0e4, 1.0e4)):
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Transform
    from OCP.gp import gp_Ax1, gp_Dir, gp_Pnt, gp_Trsf, gp_Vec

    turn, move = gp_Trsf(), gp_Trsf()
    turn.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(*axis)), angle)
    move.SetTranslation(gp_Vec(*offset))
    return BRepBuilderAPI_Transform(BRepBuilderAPI_Transform(shape, turn, True).Shape(), move, True).Shape()


def _reference(shape):
    """BRepGProp's volume (m^3) and centre of mass (m) of a shape built in mm, at a tight tolerance."""
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, props, 1e-10)
    c = props.CentreOfMass()
    return props.Mass() * 1e-9, np.array([c.X(), c.Y(), c.Z()]) * 1e-3


def _compare(shape, tmp_path, name, rel):
    import test_step_support as S

    from ibfem.geometry.solids.part_solid import PartSolid
    from ibfem.importers.step import load_part

    part = load_part(str(S.write_step(shape, tmp_path / f"{name}.step")))
    assert all(f.moments is not None for f in part.faces.values())
    solid = PartSolid(part)
    volume, centre = _reference(shape)
    size = solid.size
    assert solid.volume == pytest.approx(volume, rel=rel)
    assert np.abs(solid.centroid - centre).max() < rel * size
    return part


def test_a_screw_thread_has_opencascades_volume_in_place_and_turned_far_away(tmp_path):
    _occ()
    thread = _thread()
    part = _compare(thread, tmp_path, "thread", 1e-9)
    assert part.faces_by_type()["BSURFACE"] == 4
    from ibfem.geometry.solids.part_solid import PartSolid
    from ibfem.importers.step.cache import read_cache, write_cache

    cached = read_cache(write_cache(part, tmp_path / "cache"))  # the moments kept by `ibfem import`
    assert PartSolid(cached).volume == pytest.approx(_reference(thread)[0], rel=1e-9)
    _compare(_turned(thread), tmp_path, "turned", 1e-9)


def _thin_torus():
    """A torus of radii 20 and 0.6 mm converted to one rational B-spline face (knots of continuity
    C1 only, where the area element's derivatives jump)."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_NurbsConvert
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeTorus

    return BRepBuilderAPI_NurbsConvert(BRepPrimAPI_MakeTorus(20.0, 0.6).Shape(), True).Shape()


@pytest.mark.slow
@pytest.mark.parametrize("name", ["spring", "thin torus"])
def test_swept_and_converted_parts_have_opencascades_volume_at_any_placement(name, tmp_path):
    _occ()
    shape = {"spring": _spring, "thin torus": _thin_torus}[name]()
    _compare(shape, tmp_path, "in_place", 1e-6)
    _compare(_turned(shape), tmp_path, "turned", 1e-6)


def test_a_located_bspline_surface_is_evaluated_as_opencascade_does_also_beyond_its_knots():
    _occ()
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.BRepBuilderAPI import BRepBuilderAPI_NurbsConvert
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeTorus
    from OCP.gp import gp_Ax1, gp_Dir, gp_Pnt, gp_Trsf, gp_Vec
    from OCP.TopLoc import TopLoc_Location

    from ibfem.importers.step.face_moments import _bspline_form
    from ibfem.importers.step.tessellation import _faces

    trsf = gp_Trsf()
    trsf.SetRotation(gp_Ax1(gp_Pnt(1, 2, 3), gp_Dir(1, 2, 3)), 0.7)
    trsf.SetTranslationPart(gp_Vec(5.0, -4.0, 3.0))
    shape = BRepBuilderAPI_NurbsConvert(BRepPrimAPI_MakeTorus(3.0, 1.0).Shape(), True).Shape()
    face = _faces(shape.Moved(TopLoc_Location(trsf)))[0]
    surface = BRepAdaptor_Surface(face, False)
    rng = np.random.default_rng(5)
    uv = rng.uniform(-0.3, 2 * math.pi + 0.3, (40, 2))  # beyond the knots [0, 2 pi] too: periodic there
    ours = np.concatenate(_bspline_form(surface)(uv), axis=1)
    from OCP.gp import gp_Vec as V

    p, du, dv = gp_Pnt(), V(), V()
    theirs = []
    for u, v in uv:
        surface.D1(float(u), float(v), p, du, dv)
        theirs.append([*p.Coord(), *du.Coord(), *dv.Coord()])
    assert np.abs(ours - np.array(theirs)).max() < 1e-12
