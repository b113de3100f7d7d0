"""STEP and IGES import: parts built with OpenCascade in millimetres
(test_step_support), written to STEP and IGES, read back by importers.step and checked against
the parameters they were built with, analytical areas and volumes, OpenCascade's own point
classification (outward normals) and the projection check of the tessellated vertices."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("OCP")

import test_step_support as S  # noqa: E402
from ibfem.geometry.verify import verify_projection  # noqa: E402
from ibfem.importers.step import load_part  # noqa: E402

REL = 1e-12


@pytest.fixture(scope="module")
def shapes():
    from ibfem.importers.step.reader import _quiet_messenger

    _quiet_messenger()
    return S.primitives()


@pytest.fixture(scope="module")
def files(shapes, tmp_path_factory):
    d = tmp_path_factory.mktemp("step")
    out = {name: S.write_step(shape, d / f"{name}.step") for name, shape in shapes.items()}
    for name in ("sphere", "fillet", "revolved", "prism"):
        out[f"{name}.igs"] = S.write_iges(shapes[name], d / f"{name}.igs")
    out["box_inch"] = S.write_step(shapes["box"], d / "box_inch.step", "INCH")
    out["box_m"] = S.write_step(shapes["box"], d / "box_m.step", "M")
    out["box_inch.igs"] = S.write_iges(shapes["box"], d / "box_inch.igs", "INCH")
    return out


@pytest.fixture(scope="module")
def parts(files):
    return {name: load_part(path) for name, path in files.items()}


def _only(part, kind):
    faces = [f for f in part.faces.values() if f.surface_type == kind]
    assert len(faces) == 1, part.faces_by_type()
    return faces[0].surface.to_dict()


def _on_axis(origin, axis):
    """Distance (m) from ``origin`` to the true axis through ORIGIN along AXIS."""
    d = np.asarray(origin) - np.asarray(S.ORIGIN) * S.MM
    a = np.asarray(S.AXIS)
    return float(np.linalg.norm(d - (d @ a) * a))


def test_analytic_surfaces_read_back_with_their_parameters(parts):
    c = _only(parts["cylinder"], "CYLINDER")
    assert c["radius"] == pytest.approx(S.CYLINDER["radius"] * S.MM, rel=REL)
    assert abs(abs(np.dot(c["axis"], S.AXIS)) - 1) < REL and _on_axis(c["origin"], S.AXIS) < 1e-15
    s = _only(parts["sphere"], "SPHERE")
    np.testing.assert_allclose(s["origin"], np.asarray(S.ORIGIN) * S.MM, rtol=REL, atol=1e-17)
    assert s["radius"] == pytest.approx(S.SPHERE["radius"] * S.MM, rel=REL)
    k = _only(parts["cone"], "CONE")
    half = math.atan((S.CONE["r1"] - S.CONE["r2"]) / S.CONE["height"])
    assert k["half_angle"] == pytest.approx(half, rel=REL)
    assert _on_axis(k["origin"], S.AXIS) < 1e-15
    # the radius shrinks along +AXIS, so the primitive's axis (radius growing) is -AXIS
    assert np.dot(k["axis"], S.AXIS) == pytest.approx(-1.0, rel=REL)
    base = k["radius"] + np.dot(np.asarray(S.ORIGIN) * S.MM - k["origin"], k["axis"]) * math.tan(half)
    assert base == pytest.approx(S.CONE["r1"] * S.MM, rel=1e-11)
    t = _only(parts["torus"], "TORUS")
    assert (t["major_radius"], t["minor_radius"]) == pytest.approx((S.TORUS["major"] * S.MM, S.TORUS["minor"] * S.MM),
                                                                    rel=REL)
    np.testing.assert_allclose(t["origin"], np.asarray(S.ORIGIN) * S.MM, rtol=REL, atol=1e-17)


def test_sweep_of_a_bspline_keeps_the_curve(parts, shapes):
    _, curve = S.prism()
    sweep = _only(parts["prism"], "SWEEP")
    assert np.abs(sweep["direction"]) == pytest.approx([0.0, 0.0, 1.0], abs=REL)  # either sense
    profile = sweep["profile"]
    poles = np.array([[curve.Pole(i).X(), curve.Pole(i).Y(), curve.Pole(i).Z()]
                      for i in range(1, curve.NbPoles() + 1)]) * S.MM
    np.testing.assert_allclose(profile["control_points"], poles, rtol=REL, atol=1e-17)
    assert profile["degree"] == curve.Degree()
    edges = [e for e in parts["prism"].edges.values() if e.curve_type == "BCURVE"]
    assert len(edges) == 2 and all(e.curve is not None for e in edges)


def test_faces_edges_and_loops(parts):
    p = parts["fillet"]
    assert p.faces_by_type() == {"PLANE": 6, "CYLINDER": 12, "SPHERE": 8}
    assert list(p.faces) == [f"F{i}" for i in range(1, 27)]
    for f in p.faces.values():
        assert f.loops and f.loops[0].is_outer
        assert all(c.edge_id in p.edges for lp in f.loops for c in lp.coedges)
    radii = {round(f.surface.to_dict()["radius"] / S.MM, 9) for f in p.faces.values() if f.surface_type != "PLANE"}
    assert radii == {S.FILLET}
    assert p.edges_by_type()["CIRCLE"] == 24 and not p.warnings
    assert len(p.bodies) == 1 and next(iter(p.bodies.values())).body_type == "SOLID"


@pytest.mark.parametrize("name", ["cylinder", "sphere", "cone", "torus", "fillet", "revolved", "prism", "loft",
                                  "sphere.igs", "fillet.igs", "revolved.igs", "prism.igs"])
def test_verify_on_every_fixture(parts, name):
    part = parts[name]
    report = verify_projection(part, 1e-4)
    size = np.ptp(np.concatenate([f.mesh.vertices for f in part.faces.values()]), axis=0)
    size = float(np.linalg.norm(size))
    assert report["tessellation_only_faces"] == 0
    for kind, e in report["by_type"].items():
        bound = 1e-9 * size if kind in ("BSURFACE", "SPUN", "SWEEP") else 1e-15
        assert e["max_error"] < bound, (kind, e)
        assert e["max_normal_error"] < 1e-9, (kind, e)


@pytest.mark.parametrize("name", ["cylinder", "cone", "torus", "fillet", "revolved", "prism", "loft", "fillet.igs"])
def test_outward_normals_point_out_of_the_solid(parts, shapes, name):
    """A point a little along each face's exact outward normal is outside the solid, a point a
    little against it inside (OpenCascade's classifier on the shape as built)."""
    part, shape = parts[name], shapes[name.removesuffix(".igs")]
    reversed_seen = 0
    for face in part.faces.values():
        V = np.asarray(face.mesh.vertices)
        T = np.asarray(face.mesh.faces)
        centroids = V[T[:: max(1, len(T) // 5)]].mean(axis=1)
        pr = face.surface.project(centroids)
        outward = pr.normals * face.orientation
        h = 2e-4 * S.MM * 10
        for p, n in zip(pr.points, outward):
            assert not S.solid_contains(shape, p + h * n), (name, face.id)
            assert S.solid_contains(shape, p - h * n), (name, face.id)
        # the triangles are wound outward too
        P = V[T]
        cross = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
        agree = np.einsum("ij,ij->i", cross, face.surface.project(P.mean(axis=1)).normals * face.orientation)
        assert (agree > 0).mean() > 0.99, (name, face.id)
        reversed_seen += face.orientation < 0
    if name in ("cylinder", "cone"):
        assert reversed_seen >= 1  # a planar cap whose plane normal points inward


def test_volumes_and_areas_against_closed_forms(parts, files):
    import trimesh

    def volume(part):
        mesh = trimesh.util.concatenate([f.mesh for f in part.faces.values()])
        return abs(float(mesh.volume))

    r = S.SPHERE["radius"] * S.MM
    tol = parts["sphere"].metadata["tolerance"]
    v = volume(parts["sphere"])
    assert v == pytest.approx(4 / 3 * math.pi * r**3, rel=3 * tol / r)
    assert v < 4 / 3 * math.pi * r**3  # chords lie inside a convex solid
    a, b, c = (x * S.MM for x in S.BOX)
    exact = S.rounded_box_volume(a, b, c, S.FILLET * S.MM)
    assert volume(parts["fillet"]) == pytest.approx(exact, rel=3 * parts["fillet"].metadata["tolerance"] / 3e-3)
    from ibfem.importers.step.profile import profile_from_shape

    prof = profile_from_shape({"type": "step", "path": str(files["cylinder"]), "face": "F2"})
    assert prof.area == pytest.approx(math.pi * (S.CYLINDER["radius"] * S.MM) ** 2, rel=1e-12)


def test_units_inch_and_metre_files_come_out_in_metres(parts, files):
    text = files["box_inch"].read_text()
    assert "'INCH'" in text and "(0.,2.,0.)" in text.replace(" ", "")  # 50.8 mm written as 2 inches
    want = np.array([25.4, 50.8, 12.7]) * S.MM
    for name in ("box", "box_inch", "box_m", "box_inch.igs"):
        V = np.concatenate([f.mesh.vertices for f in parts[name].faces.values()])
        np.testing.assert_allclose(V.max(axis=0) - V.min(axis=0), want, rtol=1e-12, err_msg=name)
        planes = sorted(abs(float(np.dot(f.surface.to_dict()["origin"], f.surface.to_dict()["normal"])))
                        for f in parts[name].faces.values())
        np.testing.assert_allclose(planes, [0, 0, 0, 12.7e-3, 25.4e-3, 50.8e-3], atol=1e-15, err_msg=name)


def test_iges_reads_the_same_sphere(parts):
    a, b = _only(parts["sphere"], "SPHERE"), _only(parts["sphere.igs"], "SPHERE")
    assert a["radius"] == pytest.approx(b["radius"], rel=REL)
    np.testing.assert_allclose(a["origin"], b["origin"], rtol=REL)


def test_tolerance_is_the_users(files):
    coarse = load_part(files["sphere"], tolerance=1e-4)
    fine = load_part(files["sphere"], tolerance=1e-6)
    n = [len(p.faces["F1"].mesh.vertices) for p in (coarse, fine)]
    assert n[1] > 4 * n[0]
    for p, tol in ((coarse, 1e-4), (fine, 1e-6)):
        f = p.faces["F1"]
        P = np.asarray(f.mesh.vertices)[np.asarray(f.mesh.faces)]
        sag = np.abs(f.surface.project(P.mean(axis=1)).distances).max()
        assert sag <= 2.0 * tol  # the mesher bounds the edge sag; a centroid may sit up to ~1.7x deeper
    with pytest.raises(ValueError, match="tolerance must be a positive number"):
        load_part(files["sphere"], tolerance=-1.0)


def test_an_offset_surface_is_kept_as_tessellation_and_reported(tmp_path):
    """A face on an offset of the loft's B-spline surface (no geometry primitive): kept with its
    triangles, reported, never dropped; a lone face is a SHEET body."""
    from OCP.BRep import BRep_Tool
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.Geom import Geom_OffsetSurface
    from OCP.TopAbs import TopAbs_ShapeEnum
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    explorer = TopExp_Explorer(S.loft(), TopAbs_ShapeEnum.TopAbs_FACE)
    surfaces = []
    while explorer.More():
        surfaces.append(BRep_Tool.Surface_s(TopoDS.Face(explorer.Current())))
        explorer.Next()
    bspline = [s for s in surfaces if type(s).__name__ == "Geom_BSplineSurface"][0]
    u0, u1, v0, v1 = bspline.Bounds()
    face = BRepBuilderAPI_MakeFace(Geom_OffsetSurface(bspline, 2.0), u0, u1, v0, v1, 1e-7).Face()
    path = S.write_step(face, tmp_path / "offset.step")
    assert "OFFSET_SURFACE" in path.read_text()
    part = load_part(path)
    assert part.faces_by_type() == {"OFFSET": 1}
    f = part.faces["F1"]
    assert f.surface is None and len(f.mesh.faces) > 100
    assert "surface OFFSET: kept as tessellation-only: F1" in part.warnings
    assert [b.body_type for b in part.bodies.values()] == ["SHEET"]
    assert verify_projection(part)["tessellation_only_faces"] == 1
