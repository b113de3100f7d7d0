"""ibfem.geometry.solids, second part: ellipsoids and half ellipsoids, full
revolutions whose profile touches the axis, faces' closest points and curvatures, outward
normals, points on edges and vertices, and the solid of a CAD part (Onshape fixtures).

Truths: closed-form volumes (divergence theorem over the faces' quadrature), the optimality
conditions of a closest point (on the surface, p - foot along the exact normal) and dense samples
of the exact faces (no sample is nearer than the computed distance), analytic feet of spheres,
boxes and cylinders, and the curvatures of spheres, cylinders, tori and ellipsoid vertices."""

import math

import numpy as np
import pytest
from scipy.spatial import cKDTree

from ibfem.geometry.solids import solid_from_dict

QUARTER = math.sqrt(0.5)
# a profile with a rational B-spline edge (an exact quarter circle of radius 1 about the origin)
BSPLINE_QUARTER = {"type": "profile", "edges": [
    {"name": "base", "type": "line", "start": [0, 0], "end": [1, 0]},
    {"name": "round", "type": "bspline", "degree": 2, "control_points": [[1, 0], [1, 1], [0, 1]],
     "knots": [0, 0, 0, 1, 1, 1], "weights": [1, QUARTER, 1]},
    {"name": "left", "type": "line", "start": [0, 1], "end": [0, 0]}]}
ARC_SLOT = {"type": "profile", "edges": [
    {"name": "lower", "type": "line", "start": [-1, -0.5], "end": [1, -0.5]},
    {"name": "right", "type": "arc", "center": [1, 0], "radius": 0.5, "start_angle": -90, "end_angle": 90},
    {"name": "upper", "type": "line", "start": [1, 0.5], "end": [-1, 0.5]},
    {"name": "left", "type": "arc", "center": [-1, 0], "radius": 0.5, "start_angle": 90, "end_angle": 270}]}
HALF_DISK_RZ = {"type": "half_disk", "center": [0, 0.3], "radius": 1.2, "side": "right"}

SHAPES = [
    ({"type": "ellipsoid", "center": [0.2, -0.1, 0.3], "semi_axes": [1.0, 0.6, 0.35]}, 4 / 3 * math.pi * 0.21),
    ({"type": "ellipsoid", "center": [0, 0, 0], "semi_axes": [0.5, 1.1, 0.5]}, 4 / 3 * math.pi * 0.275),
    ({"type": "half_ellipsoid", "center": [0, 0, 1], "semi_axes": [0.8, 0.5, 0.4]}, 2 / 3 * math.pi * 0.16),
    ({"type": "half_ellipsoid", "center": [0, 0, 1], "semi_axes": [0.4, 0.5, 0.9], "side": "above"},
     2 / 3 * math.pi * 0.18),
    ({"type": "extrusion", "profile": BSPLINE_QUARTER, "z0": -0.5, "height": 1.5}, math.pi / 4 * 1.5),
    ({"type": "extrusion", "profile": ARC_SLOT, "height": 0.7}, (2.0 + math.pi * 0.25) * 0.7),
    ({"type": "revolution", "profile": HALF_DISK_RZ, "axis_origin": [0, 0, 0], "axis": [1, 1, 0]},
     4 / 3 * math.pi * 1.2**3),
    ({"type": "half_ellipsoid", "center": [0.1, 0, 0], "semi_axes": [0.8, 0.5, 0.4], "rotate": {"axis": [1, 2, 3],
      "angle_deg": 40}, "pivot": [1, 0, 0], "translate": [0, 1, 0]}, 2 / 3 * math.pi * 0.16),
]
IDS = [f"{s['type']}{i}" for i, (s, _) in enumerate(SHAPES)]


def _all_quadrature(solid, resolution):
    return (np.concatenate(v) for v in zip(*[f.quadrature(resolution) for f in solid.faces.values()]))


@pytest.mark.parametrize("shape,volume", SHAPES, ids=IDS)
def test_divergence_theorem_and_outward_normals(shape, volume):
    solid = solid_from_dict(shape)
    x, w, n = _all_quadrature(solid, 0.05)
    assert ((x * n).sum(axis=1) @ w) / 3.0 == pytest.approx(volume, rel=1e-10)
    assert solid.volume == pytest.approx(volume, rel=1e-10)
    eps = 1e-4
    away = np.abs(solid.signed_distance(x)) < 1e-9  # quadrature points lie on the boundary ...
    assert away.all()
    lo, hi = solid.bounds
    assert np.all(x >= lo - 1e-9) and np.all(x <= hi + 1e-9)
    inside, outside = solid.signed_distance(x - eps * n), solid.signed_distance(x + eps * n)
    edge = np.abs(inside) < 0.5 * eps  # ... and their normals point out (points at a kink excepted)
    assert np.all(outside < 0) and np.all((inside > 0) | edge) and edge.mean() < 0.05


@pytest.mark.parametrize("shape,volume", SHAPES, ids=IDS)
def test_distance_is_never_above_the_nearest_boundary_sample_and_close_to_it(shape, volume):
    solid = solid_from_dict(shape)
    samples = np.concatenate([f.quadrature(0.025)[0] for f in solid.faces.values()])
    lo, hi = solid.bounds
    rng = np.random.default_rng(7)
    far = rng.normal(size=(30, 3)) * 10.0
    near = samples[rng.choice(len(samples), 150)] + 1e-3 * rng.normal(size=(150, 3))  # edges and vertices too
    p = np.concatenate([rng.uniform(lo - 0.2, hi + 0.2, (300, 3)), far, near])
    d = solid.signed_distance(p)
    brute = cKDTree(samples).query(p)[0]
    assert np.all(np.abs(d) <= brute + 1e-9)
    assert np.max(brute - np.abs(d)) < 0.025
    # the sign against the solid angle of the exact faces
    x, w, n = _all_quadrature(solid, 0.08)
    for q, dq in zip(p[:30], d[:30]):
        if abs(dq) > 0.05:
            r = x - q
            turns = ((r * n).sum(axis=1) / np.linalg.norm(r, axis=1) ** 3 @ w) / (4 * math.pi)
            assert round(turns) == (1 if dq > 0 else 0)


def test_ellipsoid_feet_satisfy_the_closest_point_conditions():
    solid = solid_from_dict({"type": "ellipsoid", "center": [0, 0, 0], "semi_axes": [1.5, 0.7, 0.3]})
    rng = np.random.default_rng(1)
    p = np.concatenate([rng.normal(size=(400, 3)), rng.normal(size=(100, 3)) * [1, 1, 0],  # on the z = 0 plane
                        rng.normal(size=(50, 3)) * [0, 1, 1], np.zeros((1, 3))])  # the x = 0 plane, the centre
    foot, inside = solid.foot(p)
    a = solid.semi_axes
    np.testing.assert_allclose(((foot / a) ** 2).sum(axis=1), 1.0, atol=1e-12)
    grad = foot / a**2
    r = p - foot
    cross = np.linalg.norm(np.cross(r, grad), axis=1) / np.linalg.norm(grad, axis=1)
    assert cross.max() < 1e-10
    assert np.array_equal(inside, ((p / a) ** 2).sum(axis=1) < 1)
    # the feet are global: no point of a dense sampling is nearer
    u, v = np.meshgrid(np.linspace(0, math.pi, 400), np.linspace(0, 2 * math.pi, 800))
    s = np.stack([a[0] * np.sin(u) * np.cos(v), a[1] * np.sin(u) * np.sin(v), a[2] * np.cos(u)], -1).reshape(-1, 3)
    assert np.all(np.linalg.norm(r, axis=1) <= cKDTree(s).query(p)[0] + 1e-12)


def test_full_revolution_ignores_its_axis_edge():
    solid = solid_from_dict({"type": "revolution", "profile": HALF_DISK_RZ, "axis_origin": [0, 0, 0], "axis": [0, 0, 1]})
    p = np.random.default_rng(2).uniform(-1.5, 1.5, (2000, 3))
    p[:100, :2] *= 1e-3  # next to the axis
    np.testing.assert_allclose(solid.signed_distance(p), 1.2 - np.linalg.norm(p - [0, 0, 0.3], axis=1), atol=1e-12)
    assert set(solid.faces) == {"arc"}


def test_points_on_edges_and_vertices_are_inside_and_at_zero():
    box = solid_from_dict({"type": "box", "min": [0, 0, 0], "max": [1, 2, 3], "rotate": {"axis": [1, 1, 0],
                                                                                          "angle_deg": 33}})
    corners = np.array([[x, y, z] for x in (0, 1) for y in (0, 2) for z in (0, 3)], float)
    turned = corners @ box.rotation.T
    assert np.all(np.abs(box.signed_distance(turned)) < 1e-12)  # zero to the round-off of the turn
    half = solid_from_dict({"type": "half_sphere", "center": [0, 0, 0], "radius": 1})
    t = np.linspace(0, 2 * math.pi, 50)
    rim = np.column_stack([np.cos(t), np.sin(t), np.zeros_like(t)])
    assert np.all(np.abs(half.signed_distance(rim)) < 1e-15)
    # near the rim, the distance is the Euclidean one to the rim circle outside the corner
    q = rim * 1.1 + [0, 0, 0.05]
    np.testing.assert_allclose(half.signed_distance(q), -np.hypot(0.1, 0.05), atol=1e-12)


def test_face_projection_against_analytic_feet():
    box = solid_from_dict({"type": "box", "min": [0, 0, 0], "max": [1, 2, 3]})
    p = np.random.default_rng(3).uniform(-2, 4, (300, 3))
    pr = box.faces["x_max"].project(p)
    np.testing.assert_allclose(pr.points, np.column_stack([np.ones(300), np.clip(p[:, 1], 0, 2), np.clip(p[:, 2], 0, 3)]),
                               atol=1e-12)
    cyl = solid_from_dict({"type": "cylinder", "center": [0, 0, 0], "axis": [0, 0, 1], "radius": 0.5, "length": 2})
    pr = cyl.faces["side"].project(p)
    radial = p[:, :2] / np.linalg.norm(p[:, :2], axis=1)[:, None]
    np.testing.assert_allclose(pr.points, np.column_stack([0.5 * radial, np.clip(p[:, 2], -1, 1)]), atol=1e-9)
    sphere = solid_from_dict({"type": "sphere", "center": [0.1, 0, 0], "radius": 2})
    pr = sphere.faces["surface"].project(p)
    r = p - [0.1, 0, 0]
    np.testing.assert_allclose(pr.points, [0.1, 0, 0] + 2 * r / np.linalg.norm(r, axis=1)[:, None], atol=1e-12)
    np.testing.assert_allclose(pr.distances, np.linalg.norm(r, axis=1) - 2, atol=1e-12)
    cap = solid_from_dict({"type": "extrusion", "profile": {"type": "disk", "center": [0, 0], "radius": 1}, "height": 1})
    pr = cap.faces["top"].project(p)
    rho = np.linalg.norm(p[:, :2], axis=1)
    expect = np.column_stack([p[:, :2] / np.maximum(rho, 1)[:, None], np.ones(300)])
    np.testing.assert_allclose(pr.points, expect, atol=1e-12)
    assert cap.faces["top"].surface.normal == (0.0, 0.0, 1.0)


def test_curvatures_of_spheres_cylinders_tori_and_ellipsoid_vertices():
    sphere = solid_from_dict({"type": "sphere", "center": [0, 0, 0], "radius": 2, "rotate": {"axis": [1, 0, 1],
                                                                                            "angle_deg": 20}})
    p = np.random.default_rng(4).normal(size=(50, 3))
    k1, k2, d1, d2 = sphere.faces["surface"].curvature(p)
    np.testing.assert_allclose(np.concatenate([k1, k2]), 0.5, rtol=1e-7)
    cyl = solid_from_dict({"type": "cylinder", "center": [0, 0, 0], "axis": [1, 1, 1], "radius": 0.5, "length": 2})
    k1, k2, d1, d2 = cyl.faces["side"].curvature(p)
    np.testing.assert_allclose(k1, 0, atol=1e-6)
    np.testing.assert_allclose(k2, 2, rtol=1e-7)
    np.testing.assert_allclose(np.abs(d1 @ np.ones(3) / math.sqrt(3)), 1, atol=1e-7)  # the flat direction: the axis
    torus = solid_from_dict({"type": "revolution", "profile": {"type": "disk", "center": [1, 0], "radius": 0.25},
                             "axis_origin": [0, 0, 0], "axis": [0, 0, 1]})
    k1, k2, _, _ = torus.faces["boundary"].curvature(np.array([[2.0, 0, 0], [0, 0.5, 0]]))
    np.testing.assert_allclose(k1, [1 / 1.25, -1 / 0.75], rtol=1e-6)  # outer equator; inner equator (saddle)
    np.testing.assert_allclose(k2, [4, 4], rtol=1e-6)
    ell = solid_from_dict({"type": "ellipsoid", "center": [0, 0, 0], "semi_axes": [3, 2, 1]})
    k1, k2, _, _ = ell.faces["surface"].curvature(np.array([[4.0, 0, 0], [0, 3.0, 0]]))
    np.testing.assert_allclose(k1, [3 / 4, 2 / 9], rtol=1e-6)  # a / b^2, b / a^2
    np.testing.assert_allclose(k2, [3, 2], rtol=1e-6)  # a / c^2, b / c^2


@pytest.mark.parametrize("shape,message", [
    ({"type": "ellipsoid", "center": [0, 0, 0], "semi_axes": [1, -1, 1]}, "shape.semi_axes[1] must be a positive number"),
    ({"type": "ellipsoid", "center": [0, 0, 0], "semi_axes": [1, 1]}, "shape.semi_axes must be a list of three numbers"),
    ({"type": "half_ellipsoid", "center": [0, 0, 0], "semi_axes": [1, 1, 1], "side": "up"}, "shape.side must be"),
    ({"type": "ellipsoid", "center": [0, 0, 0], "semi_axes": [1, 1, 1], "side": "below"}, "unknown key(s) side"),
    ({"type": "onshape", "path": "x", "body": "b"}, "CAD solids need a part loader"),
    ({"type": "extrusion", "profile": {"type": "rectangle", "min": [0, 0], "max": [1, 1]}, "height": 1},
     "clash with the face names bottom and top"),
])
def test_bad_shapes_name_the_key_and_value(shape, message):
    with pytest.raises(ValueError) as err:
        solid_from_dict(shape)
    assert message in str(err.value)


@pytest.fixture(scope="module")
def cone_sphere():
    importers = pytest.importorskip("ibfem.importers.onshape")
    return importers.load_part("fixtures/onshape/cone_sphere")


def test_part_solid_ball_and_capped_cone(cone_sphere):
    ball = solid_from_dict({"type": "onshape", "path": "fixtures/onshape/cone_sphere", "body": "Ball"},
                           load_part=lambda d: cone_sphere)
    centre = np.asarray(next(iter(ball.faces.values())).surface.origin)
    p = centre + np.random.default_rng(5).normal(size=(500, 3)) * 0.01
    np.testing.assert_allclose(ball.signed_distance(p), 0.012 - np.linalg.norm(p - centre, axis=1), atol=1e-15)
    assert ball.volume == pytest.approx(4 / 3 * math.pi * 0.012**3, rel=1e-8)
    cone = solid_from_dict({"type": "onshape", "path": "x", "body": "Cone with sphere cap"}, load_part=lambda d: cone_sphere)
    r0, r1, h = 0.01, 0.02, 0.03
    exact = math.pi * h / 3 * (r0**2 + r0 * r1 + r1**2) + 2 / 3 * math.pi * r1**3
    assert cone.volume == pytest.approx(exact, rel=2e-4)  # the flat cap is trimmed by its chords (documented)
    samples = np.concatenate([f.quadrature(0.0006)[0] for f in cone.faces.values()])
    lo, hi = cone.bounds
    q = np.random.default_rng(6).uniform(lo - 0.005, hi + 0.005, (800, 3))
    d = cone.signed_distance(q)
    brute = cKDTree(samples).query(q)[0]
    assert np.all(np.abs(d) <= brute + 1e-12) and np.max(brute - np.abs(d)) < 1e-3
    with pytest.raises(ValueError, match="no such body"):
        solid_from_dict({"type": "onshape", "path": "x", "body": "nope"}, load_part=lambda d: cone_sphere)
