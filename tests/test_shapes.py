"""The scene format's 2D shapes: edge names, geometry against closed forms, rotate/translate,
and error messages naming the key."""

import math

import numpy as np
import pytest

from ibfem.geometry.shapes import profile_from_shape

RNG = np.random.default_rng(11)


def test_rectangle():
    p = profile_from_shape({"type": "rectangle", "min": [-2.0, -2.0], "max": [2.0, 0.0]})
    assert p.edge_names == ("bottom", "right", "top", "left")
    assert p.area == pytest.approx(8.0)
    np.testing.assert_allclose(p.edge("top").project([[0.3, 1.0]]).normals[0], [0, 1])
    np.testing.assert_allclose(p.edge("left").start, [-2, 0])
    assert p.signed_distance([[0.0, -1.0]])[0] == pytest.approx(1.0)


def test_disk():
    p = profile_from_shape({"type": "disk", "center": [1.0, 2.0], "radius": 0.5})
    assert p.edge_names == ("boundary",)
    assert p.area == pytest.approx(math.pi * 0.25, rel=1e-14)
    P = RNG.uniform(0, 3, (200, 2))
    np.testing.assert_allclose(p.signed_distance(P), 0.5 - np.linalg.norm(P - [1, 2], axis=1), atol=1e-15)


@pytest.mark.parametrize(
    "side,keep",
    [("below", lambda q: q[:, 1] < 0), ("above", lambda q: q[:, 1] > 0), ("left", lambda q: q[:, 0] < 0), ("right", lambda q: q[:, 0] > 0)],
)
def test_half_disk_sides(side, keep):
    c = np.array([0.0, 1.0])
    p = profile_from_shape({"type": "half_disk", "center": c.tolist(), "radius": 1.0, "side": side})
    assert p.edge_names == ("arc", "flat")
    assert p.area == pytest.approx(math.pi / 2, rel=1e-14)
    P = RNG.uniform(-1.5, 1.5, (2000, 2)) + c
    q = P - c
    rho = np.linalg.norm(q, axis=1)
    inside = keep(q) & (rho < 1.0)
    np.testing.assert_array_equal(p.contains(P), inside | (np.abs(rho - 1) < 1e-12) & keep(q))
    # in the kept half, away from the flat: phi = min(R - rho, distance to the flat)
    flat_dist = np.abs(q[:, 1]) if side in ("below", "above") else np.abs(q[:, 0])
    np.testing.assert_allclose(p.signed_distance(P[inside]), np.minimum(1.0 - rho, flat_dist)[inside], atol=1e-15)


def test_half_disk_contact_point_of_the_scene_example():
    p = profile_from_shape({"type": "half_disk", "center": [0.0, 1.0], "radius": 1.0, "side": "below"})
    lo, hi = p.bounds
    np.testing.assert_allclose(lo, [-1, 0], atol=1e-15)
    np.testing.assert_allclose(hi, [1, 1], atol=1e-15)
    pr = p.project([[0.0, -0.1]])
    np.testing.assert_allclose(pr.points[0], [0, 0], atol=1e-15)
    np.testing.assert_allclose(pr.normals[0], [0, -1], atol=1e-15)
    assert p.edge_names[pr.edge_index[0]] == "arc"


def test_half_ellipse():
    p = profile_from_shape({"type": "half_ellipse", "center": [0.0, 0.1], "semi_axes": [0.2, 0.1], "side": "below"})
    assert p.edge_names == ("arc", "flat")
    assert p.area == pytest.approx(0.5 * math.pi * 0.02, rel=1e-13)
    lo, hi = p.bounds
    np.testing.assert_allclose(lo, [-0.2, 0.0], atol=1e-15)
    np.testing.assert_allclose(hi, [0.2, 0.1], atol=1e-15)
    # radius of curvature at the contact point (0, 0): a^2 / b = 0.4
    arc = p.edge("arc")
    pr = arc.project([[0.0, -0.01]])
    assert 1.0 / abs(arc.curvature(pr.parameters)[0]) == pytest.approx(0.2**2 / 0.1, rel=1e-12)
    q = profile_from_shape({"type": "half_ellipse", "center": [0.0, 0.0], "semi_axes": [0.2, 0.1], "side": "right"})
    lo, hi = q.bounds
    np.testing.assert_allclose(lo, [0.0, -0.1], atol=1e-15)
    np.testing.assert_allclose(hi, [0.2, 0.1], atol=1e-15)


def test_polygon_names_follow_the_points_in_either_order():
    pts = [[0, 0], [0, 1], [1, 1], [1, 0]]  # clockwise
    p = profile_from_shape({"type": "polygon", "points": pts})
    assert set(p.edge_names) == {"e0", "e1", "e2", "e3"}
    e0 = p.edge("e0")  # the piece between points[0] and points[1] (reversed to run CCW)
    assert {tuple(e0.start), tuple(e0.end)} == {(0.0, 0.0), (0.0, 1.0)}
    np.testing.assert_allclose(e0.normal(0.5)[0], [-1, 0])
    assert p.area == pytest.approx(1.0)
    named = profile_from_shape({"type": "polygon", "points": pts, "edge_names": ["w", "n", "e", "s"]})
    assert named.edge("n").project([[0.5, 2.0]]).distances[0] == pytest.approx(1.0)


def test_profile_shape_with_all_edge_forms_and_hole():
    d = {
        "type": "profile",
        "edges": [
            {"name": "base", "type": "line", "start": [4.0, 0.0], "end": [0.0, 0.0]},  # listed backwards
            {"name": "side", "type": "line", "start": [4.0, 0.0], "end": [4.0, 1.0]},
            {"name": "top", "type": "arc", "center": [3.0, 1.0], "radius": 1.0, "start_angle": 0.0, "end_angle": 90.0},
            {"name": "curve", "type": "bspline", "degree": 2, "control_points": [[3.0, 2.0], [2.0, 3.0], [1.0, 2.0]], "knots": [0, 0, 0, 1, 1, 1], "weights": [1.0, 0.5, 1.0]},
            {"name": "nose", "type": "elliptic_arc", "center": [0.0, 1.0], "semi_axes": [1.0, 0.5], "rotate_deg": 90.0, "start_angle": 0.0, "end_angle": 180.0},
        ],
        "holes": [[{"name": "pin", "type": "arc", "center": [2.0, 1.0], "radius": 0.25, "start_angle": 0, "end_angle": 360}]],
    }
    # the nose: rotated 90 degrees, parametric 0 -> 180 runs from (0, 2) to (0, 0) through (-0.5, 1);
    # the curve ends at (1, 2), so connect it with a line
    d["edges"].insert(4, {"name": "link", "type": "line", "start": [1.0, 2.0], "end": [0.0, 2.0]})
    p = profile_from_shape(d)
    assert p.edge_names == ("base", "side", "top", "curve", "link", "nose", "pin")
    assert len(p.loops) == 2
    assert p.signed_distance([[2.0, 1.0]])[0] == pytest.approx(-0.25)
    assert p.signed_distance([[2.0, 0.5]])[0] == pytest.approx(0.25)
    # every edge's normal points out of the material
    for name, c in p.edges.items():
        t = np.linspace(c.t_start, c.t_end, 7)[1:-1]
        X, n = c.evaluate(t), c.normal(t)
        assert np.all(p.signed_distance(X + 1e-5 * n) < 0), name


def test_rotate_and_translate():
    base = {"type": "rectangle", "min": [0.0, 0.0], "max": [2.0, 1.0]}
    p = profile_from_shape({**base, "rotate_deg": 90.0, "pivot": [1.0, 0.0], "translate": [0.0, 5.0]})
    lo, hi = p.bounds
    np.testing.assert_allclose(lo, [0.0, 4.0], atol=1e-14)
    np.testing.assert_allclose(hi, [1.0, 6.0], atol=1e-14)
    # the edge named bottom moved with the rectangle: now the right-hand side x = 1
    b = p.edge("bottom")
    np.testing.assert_allclose([b.start[0], b.end[0]], [1.0, 1.0], atol=1e-14)
    q = profile_from_shape({"type": "half_disk", "center": [0, 1], "radius": 1, "side": "below", "rotate_deg": 30.0, "translate": [1.0, -2.0]})
    r = profile_from_shape({"type": "half_disk", "center": [0, 1], "radius": 1, "side": "below"})
    P = RNG.uniform(-2, 2, (300, 2))
    a = math.radians(30.0)
    R = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
    np.testing.assert_allclose(q.signed_distance(P @ R.T + [1.0, -2.0]), r.signed_distance(P), atol=1e-14)


@pytest.mark.parametrize(
    "d,msg",
    [
        ({"type": "disk", "center": [0, 0], "radius": -1}, "shape.radius must be positive, got -1"),
        ({"type": "half_disk", "center": [0, 0], "radius": 1, "side": "up"}, "shape.side must be one of"),
        ({"type": "rectangle", "min": [0, 0], "max": [0, 1]}, "shape.max must exceed shape.min"),
        ({"type": "rectangle", "min": [0, 0]}, "missing key(s) max"),
        ({"type": "rectangle", "min": [0, 0], "max": [1, 1], "radius": 2}, "unknown key(s) radius"),
        ({"type": "square"}, "shape.type must be one of"),
        ({"type": "polygon", "points": [[0, 0], [1, 0]]}, "shape.points must be a list of at least 3"),
        ({"type": "polygon", "points": [[0, 0], [1, 0], [0, 1]], "edge_names": ["a", "b"]}, "shape.edge_names"),
        ({"type": "half_ellipse", "center": [0, 0], "semi_axes": [1, -1], "side": "below"}, "shape.semi_axes must be positive"),
        ({"type": "polygon", "points": [[0, 0], [1, 1], [1, 0], [0, 1]]}, "shape: outer loop crosses itself (edges 'e0' and 'e2' at [0.5, 0.5])"),
        ({"type": "polygon", "points": [[0, 0], [2, 0], [2, 2], [1, 0], [0, 2]]}, "crosses itself"),
        ({"type": "disk", "center": [0, "x"], "radius": 1}, "shape.center"),
        ({"type": "disk", "center": [0, 0], "radius": 1, "rotate_deg": "a"}, "shape.rotate_deg"),
        (
            {"type": "profile", "edges": [{"name": "a", "type": "arc", "center": [0, 0], "radius": 0, "start_angle": 0, "end_angle": 90}]},
            "shape.edges[0].radius must be positive",
        ),
        (
            {"type": "profile", "edges": [{"name": "a", "type": "line", "start": [0, 0], "end": [1, 0]}, {"name": "b", "type": "line", "start": [1, 0], "end": [1, 1]}]},
            "shape: outer loop: the loop is not closed",
        ),
    ],
)
def test_errors_name_the_key(d, msg):
    with pytest.raises(ValueError) as exc:
        profile_from_shape(d)
    assert msg in str(exc.value)


from hypothesis import given, settings, strategies as st  # noqa: E402


@settings(max_examples=25, deadline=None)
@given(
    w=st.floats(0.1, 10.0),
    h=st.floats(0.1, 10.0),
    angle=st.floats(-360.0, 360.0),
    tx=st.floats(-100.0, 100.0),
    ty=st.floats(-100.0, 100.0),
    r=st.floats(0.05, 5.0),
    side=st.sampled_from(["below", "above", "left", "right"]),
)
def test_random_rigid_motions_keep_the_closed_forms(w, h, angle, tx, ty, r, side):
    a = math.radians(angle)
    R = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
    rng = np.random.default_rng(0)
    # rectangle [0, w] x [0, h] turned about its corner (pivot) and moved
    p = profile_from_shape({"type": "rectangle", "min": [0, 0], "max": [w, h], "rotate_deg": angle, "translate": [tx, ty]})
    L = rng.uniform([-1, -1], [w + 1, h + 1], (300, 2))
    inside = np.minimum.reduce([L[:, 0], w - L[:, 0], L[:, 1], h - L[:, 1]])
    dx = np.maximum.reduce([-L[:, 0], np.zeros(len(L)), L[:, 0] - w])
    dy = np.maximum.reduce([-L[:, 1], np.zeros(len(L)), L[:, 1] - h])
    ref = np.where(inside >= 0, inside, -np.hypot(dx, dy))
    scale = max(w, h, abs(tx), abs(ty))
    np.testing.assert_allclose(p.signed_distance(L @ R.T + [tx, ty]), ref, atol=1e-13 * scale)
    # half disk: phi = min(r - rho, distance to the flat) in the kept half
    q = profile_from_shape({"type": "half_disk", "center": [0, 0], "radius": r, "side": side, "rotate_deg": angle, "translate": [tx, ty]})
    L = rng.uniform(-1.5 * r, 1.5 * r, (300, 2))
    keep = {"below": -L[:, 1], "above": L[:, 1], "left": -L[:, 0], "right": L[:, 0]}[side]
    rho = np.hypot(L[:, 0], L[:, 1])
    ok = (keep > 0) & (rho < r)
    phi = q.signed_distance(L @ R.T + [tx, ty])
    np.testing.assert_allclose(phi[ok], np.minimum(r - rho, keep)[ok], atol=1e-13 * max(r, abs(tx), abs(ty)))
    assert np.all(phi[(keep < -1e-9 * r) | (rho > r * (1 + 1e-9))] < 0)
