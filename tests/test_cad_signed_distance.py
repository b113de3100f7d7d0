"""Signed distances of STEP solids near their edges, vertices and seams against OpenCascade's own
answers: the side by ``BRepClass3d_SolidClassifier``, the distance to the boundary by
``BRepExtrema_DistShapeShape`` (independent of the importer's surfaces, tessellation and edges).

The parts are built here with OpenCascade and written to STEP: a box with two rounded edges (planes
meeting cylinders tangentially, corners where a fillet ends), the quarter of a ball's lower half
(two symmetry planes and a sphere meeting at the pole, as in the shipped CAD example) and a
cylinder with a chamfered rim (a cone, the cylinder's seam). The points are scattered about every
edge at a third of, at and at three times the tessellation's tolerance: where a face's triangles
alone cannot tell whether a foot lies on the face.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("OCP")

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "examples" / "cad"))

import make_quarter_ball  # noqa: E402
import test_step_support as S  # noqa: E402
from ibfem.geometry.solids.part_solid import PartSolid  # noqa: E402
from ibfem.importers.step import load_part  # noqa: E402

MM = 1e-3


def _edges(shape):
    from OCP.TopAbs import TopAbs_ShapeEnum
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    explorer = TopExp_Explorer(shape, TopAbs_ShapeEnum.TopAbs_EDGE)
    while explorer.More():
        yield TopoDS.Edge(explorer.Current())
        explorer.Next()


def box_with_two_fillets():
    """A 20 x 30 x 10 mm box with a vertical and a horizontal edge rounded (radius 4 mm)."""
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox

    box = BRepPrimAPI_MakeBox(20.0, 30.0, 10.0).Shape()
    fillet = BRepFilletAPI_MakeFillet(box)
    for k, edge in enumerate(_edges(box)):
        if k in (0, 5):
            fillet.Add(4.0, edge)
    return fillet.Shape()


def chamfered_cylinder():
    """A cylinder of radius 10 mm and height 20 mm, its top rim chamfered 2 mm."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeChamfer
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder

    cylinder = BRepPrimAPI_MakeCylinder(10.0, 20.0).Shape()
    chamfer = BRepFilletAPI_MakeChamfer(cylinder)
    for edge in _edges(cylinder):
        curve = BRepAdaptor_Curve(edge)
        if curve.GetType().name == "GeomAbs_Circle" and curve.Value(curve.FirstParameter()).Z() > 10.0:
            chamfer.Add(2.0, edge)
    return chamfer.Shape()


PARTS = {"rounded box": box_with_two_fillets, "quarter ball": make_quarter_ball.build,
         "chamfered cylinder": chamfered_cylinder}


def _edge_samples(shape, per_edge: int = 12) -> np.ndarray:
    """Points (mm) along every edge of the shape, seams and their ends included."""
    from OCP.BRep import BRep_Tool
    from OCP.BRepAdaptor import BRepAdaptor_Curve

    out = []
    for edge in _edges(shape):
        if BRep_Tool.Degenerated_s(edge):
            continue
        curve = BRepAdaptor_Curve(edge)
        for t in np.linspace(curve.FirstParameter(), curve.LastParameter(), per_edge):
            p = curve.Value(t)
            out.append([p.X(), p.Y(), p.Z()])
    return np.array(out)


def _kernel(shape, points_mm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """OpenCascade's side (+1 inside, -1 outside, 0 on) and distance to the shell (mm)."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex
    from OCP.BRepClass3d import BRepClass3d_SolidClassifier
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape
    from OCP.gp import gp_Pnt
    from OCP.TopAbs import TopAbs_ShapeEnum, TopAbs_State
    from OCP.TopExp import TopExp_Explorer

    shell = TopExp_Explorer(shape, TopAbs_ShapeEnum.TopAbs_SHELL).Current()
    classifier = BRepClass3d_SolidClassifier(shape)
    side, dist = [], []
    for x in points_mm:
        p = gp_Pnt(*map(float, x))
        classifier.Perform(p, 1e-9)
        state = classifier.State()
        side.append(1 if state == TopAbs_State.TopAbs_IN else -1 if state == TopAbs_State.TopAbs_OUT else 0)
        dist.append(BRepExtrema_DistShapeShape(BRepBuilderAPI_MakeVertex(p).Vertex(), shell).Value())
    return np.array(side), np.array(dist)


@pytest.mark.parametrize("name", sorted(PARTS))
def test_signed_distance_near_edges_agrees_with_the_kernel(name, tmp_path):
    from ibfem.importers.step.reader import _quiet_messenger

    _quiet_messenger()
    shape = PARTS[name]()
    solid = PartSolid(load_part(str(S.write_step(shape, tmp_path / "part.step"))))
    tol = solid.tolerance / MM
    rng = np.random.default_rng(3)
    along = _edge_samples(shape)
    points = np.concatenate([along + rng.normal(scale=s * tol, size=along.shape) for s in (1 / 3, 1.0, 3.0)])
    side, dist = _kernel(shape, points)
    got = np.asarray(solid.signed_distance(points * MM), float) / MM
    decided = side != 0
    assert decided.sum() > 0.95 * len(points)
    wrong = np.flatnonzero(decided & (np.sign(got) != side))
    assert not len(wrong), (len(wrong), points[wrong[:3]], got[wrong[:3]], side[wrong[:3]])
    # the kernel's distance is exact to its own precision (1e-7 mm); the faces' are to round-off
    assert np.abs(np.abs(got) - dist).max() < 1e-6, np.abs(np.abs(got) - dist).max()


def test_a_foot_just_beyond_a_symmetry_face_rim_is_no_foot(tmp_path):
    """Beside a symmetry plane of the quarter ball, just below the sphere: the plane's foot lies
    outside its quarter disc (by less than the tessellation's sag), so the nearest point is on the
    sphere and the point is outside, |x - c| - R away (c the centre, R = 25 mm)."""
    solid = PartSolid(load_part(str(make_quarter_ball.write(tmp_path / "quarter.step"))))
    p = np.array([[0.563, 0.048, -0.05], [3.0, 0.02, 0.15]])  # mm
    want = 25.0 - np.linalg.norm(p - [0.0, 0.0, 25.0], axis=1)
    assert solid.tolerance / MM > 0.048  # the band the triangles alone would accept
    got = np.asarray(solid.signed_distance(p * MM), float) / MM
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)


def _sphere_triangles(rings: int = 24, sectors: int = 48, crack: float = 1e-6) -> np.ndarray:
    """A unit sphere's latitude-longitude triangles, wound outward; the northern half's vertices
    on the equator moved out radially by ``crack`` (the halves then meet with a gap, as faces
    meshed one by one do) and its triangles along the equator cut at their midpoints (T-junctions)."""
    theta = np.linspace(0.0, np.pi, rings + 1)
    phi = np.linspace(0.0, 2.0 * np.pi, sectors + 1)

    def point(i, j, bump=0.0):
        r = 1.0 + bump
        return r * np.array([np.sin(theta[i]) * np.cos(phi[j]), np.sin(theta[i]) * np.sin(phi[j]), np.cos(theta[i])])

    tri = []
    for i in range(rings):
        for j in range(sectors):
            north = i < rings // 2
            bump = crack if north else 0.0
            a, b = point(i, j, bump * (i == rings // 2)), point(i + 1, j, bump * (i + 1 == rings // 2))
            c, d = point(i + 1, j + 1, bump * (i + 1 == rings // 2)), point(i, j + 1, bump * (i == rings // 2))
            if north and i + 1 == rings // 2:  # b, c on the equator: split b-c at its midpoint
                m = 0.5 * (b + c)
                tri += [(a, b, m), (a, m, d), (d, m, c)]
                continue
            tri += [(a, b, c), (a, c, d)]
    return np.array(tri)


def test_winding_tree_equals_the_sum_over_every_triangle():
    """The box hierarchy's cones give each point the solid angle of the triangles they replace
    (a patch and the cone over its boundary close a surface of winding number 0 outside their
    box): the same winding numbers as the sum over every triangle, to round-off, for a closed
    sphere whose halves meet with a gap and T-junctions (as a CAD part's faces meshed one by one)
    and for an open half of it (the root's boundary is then not empty)."""
    from ibfem.geometry.solids.mesh_jit import mesh_kernels
    from ibfem.geometry.solids.part_solid import _winding
    from ibfem.geometry.solids.winding_tree import WindingTree

    kernels = mesh_kernels()
    if kernels is None:
        pytest.skip("compiled kernels off (numba missing or IBFEM_NO_JIT)")
    sphere = _sphere_triangles()
    rng = np.random.default_rng(5)
    off = rng.choice([-1e-4, 1e-4], 500)
    p = np.concatenate([rng.uniform(-1.2, 1.2, size=(500, 3)),  # about the sphere, and 1e-4 off its triangles
                        sphere.mean(axis=1)[rng.integers(0, len(sphere), 500)] * (1.0 + off[:, None])])
    for tri in (sphere, sphere[sphere[:, :, 0].mean(axis=1) < 0.3]):
        tree = WindingTree(tri)
        want = _winding(p, tri)
        got = tree.winding(p, kernels) / (4.0 * np.pi)
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)
        assert len(tree.cone) and tree.child[0, 0] >= 0  # cones and children were used
    r = np.linalg.norm(p[:500], axis=1)
    far = np.abs(r - 1.0) > 0.01  # beyond the chords' sag (0.0086)
    full = WindingTree(sphere).winding(p, kernels) / (4.0 * np.pi)
    np.testing.assert_array_equal(full[:500][far] > 0.5, r[far] < 1.0)
    np.testing.assert_array_equal(full[500:] > 0.5, off < 0.0)


def test_compiled_nearest_point_of_a_polyline_equals_numpy(monkeypatch):
    """The compiled nearest point of a polyline takes the same steps as the numpy one: the same
    feet, distances and segment directions (equally near segments: the first)."""
    from ibfem.geometry.solids import face_trim
    from ibfem.geometry.solids.mesh_jit import mesh_kernels

    if mesh_kernels() is None:
        pytest.skip("compiled kernels off (numba missing or IBFEM_NO_JIT)")
    s = np.linspace(0.0, 4.0 * np.pi, 90)
    line = np.stack([np.cos(s), np.sin(s), 0.1 * s], axis=1)  # a helix, its turns near each other
    line[40] = line[39]  # a segment of zero length
    p = np.random.default_rng(2).uniform(-1.5, 1.5, size=(500, 3))
    p[:10] = line[:10]  # on vertices
    got = face_trim._nearest_on_polyline(p, line)
    monkeypatch.setenv("IBFEM_NO_JIT", "1")
    want = face_trim._nearest_on_polyline(p, line)
    for g, w in zip(got, want):
        np.testing.assert_allclose(g, w, rtol=0, atol=1e-14)
