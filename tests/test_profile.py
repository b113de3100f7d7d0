"""Profiles: exact signed distance against closed forms and brute force, inside test on
edges and corners, orientation and naming, area, tessellation, rigid-motion invariance."""

import math

import numpy as np
import pytest
from matplotlib.path import Path

from ibfem.geometry.bounded import Arc, BSplineArc, EllipticArc, Segment
from ibfem.geometry.profile import Profile, UnknownEdgeError

RNG = np.random.default_rng(7)


def rectangle(x0=-1.0, y0=-0.5, x1=2.0, y1=1.5):
    return Profile(
        [
            [
                Segment((x0, y0), (x1, y0), "bottom"),
                Segment((x1, y0), (x1, y1), "right"),
                Segment((x1, y1), (x0, y1), "top"),
                Segment((x0, y1), (x0, y0), "left"),
            ]
        ]
    )


def rectangle_phi(P, x0=-1.0, y0=-0.5, x1=2.0, y1=1.5):
    inside = np.minimum.reduce([P[:, 0] - x0, x1 - P[:, 0], P[:, 1] - y0, y1 - P[:, 1]])
    dx = np.maximum.reduce([x0 - P[:, 0], np.zeros(len(P)), P[:, 0] - x1])
    dy = np.maximum.reduce([y0 - P[:, 1], np.zeros(len(P)), P[:, 1] - y1])
    return np.where(inside >= 0, inside, -np.hypot(dx, dy))


def annulus(c=(0.3, -0.2), R=2.0, r=0.7):
    # the hole is given counter-clockwise: the constructor must turn it clockwise
    return Profile([[Arc(c, R, 0.0, 2 * math.pi, "outer")], [Arc(c, r, 0.0, 2 * math.pi, "inner")]])


def lshape():
    pts = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
    return Profile([[Segment(pts[i], pts[(i + 1) % 6], f"e{i}") for i in range(6)]])


def mixed_profile():
    """Line + circular arc + elliptic arc + B-spline, some listed backwards."""
    a = Segment((0.0, 0.0), (3.0, 0.0), "base")
    b = Arc((3.0, 1.0), 1.0, -90.0 * math.pi / 180, 90.0 * math.pi / 180, "round")  # (3,0) -> (3,2)
    c = BSplineArc(3, [[0.0, 2.0], [1.0, 2.8], [2.0, 1.4], [3.0, 2.0]], [0, 0, 0, 0, 1, 1, 1, 1], None, "wave")
    # listed from (0, 2) to (3, 2): backwards along the loop
    d = EllipticArc((0.0, 1.0), (0.6, 1.0), 0.0, math.pi / 2, 3 * math.pi / 2, "nose")  # (0,2) -> (0,0)
    return Profile([[a.reversed(), b, c, d]])


def dense_boundary(profile, n=4000):
    pts = []
    for lp in profile.loops:
        loop = []
        for c in lp:
            t = np.linspace(c.t_start, c.t_end, n)
            loop.append(c.evaluate(t)[:-1])
        pts.append(np.vstack(loop))
    return pts


def brute_force_phi(profile, P):
    """Distance to a densely sampled boundary, sign from matplotlib's polygon test."""
    loops = dense_boundary(profile)
    S = np.vstack(loops)
    d = np.array([np.min(np.hypot(S[:, 0] - p[0], S[:, 1] - p[1])) for p in P])
    inside = Path(loops[0]).contains_points(P)
    for h in loops[1:]:
        inside &= ~Path(h).contains_points(P)
    return np.where(inside, d, -d), S


def test_rectangle_signed_distance_closed_form():
    p = rectangle()
    P = RNG.uniform(-3, 4, (4000, 2))
    np.testing.assert_allclose(p.signed_distance(P), rectangle_phi(P), atol=1e-15)
    # points on the medial axis, at corners, on edges, on the grid lines through corners
    special = np.array([[0.5, 0.5], [-1, -0.5], [2, 1.5], [0.0, -0.5], [2.0, 0.3], [-1.0, 3.0], [3.0, 1.5], [-2, -1.5]])
    np.testing.assert_allclose(p.signed_distance(special), rectangle_phi(special), atol=1e-15)


def test_disk_and_annulus_closed_forms():
    c = np.array([0.3, -0.2])
    disk = Profile([[Arc(c, 2.0, 0.0, 2 * math.pi, "boundary")]])
    P = RNG.uniform(-3, 3, (3000, 2))
    rho = np.linalg.norm(P - c, axis=1)
    np.testing.assert_allclose(disk.signed_distance(P), 2.0 - rho, atol=1e-14)
    ring = annulus()
    np.testing.assert_allclose(ring.signed_distance(P), np.minimum(2.0 - rho, rho - 0.7), atol=1e-14)
    assert ring.area == pytest.approx(math.pi * (4.0 - 0.49), rel=1e-14)
    # the hole's edge normal points into the hole (out of the material)
    inner = ring.edge("inner")
    t = np.linspace(inner.t_start, inner.t_end, 5)
    np.testing.assert_allclose(inner.normal(t), -(inner.evaluate(t) - c) / 0.7, atol=1e-14)
    # the projection's normals are outward and phi agrees with (p - c).n
    pr = ring.project(P)
    np.testing.assert_allclose(-np.einsum("ij,ij->i", P - pr.points, pr.normals), pr.phi, atol=1e-13)


def test_contains_on_edges_and_corners_counts_as_inside():
    p = rectangle()
    on = np.array([[-1, -0.5], [2, -0.5], [2, 1.5], [-1, 1.5], [0.5, -0.5], [2, 0.0], [0.0, 1.5], [-1, 0.25]])
    assert np.all(p.contains(on))
    np.testing.assert_array_equal(p.signed_distance(on), 0.0)
    out = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1], [0, -1], [1, 0], [0, 1], [-1, 0]])
    assert not np.any(p.contains(on + 1e-10 * out))
    assert np.all(p.contains(on - 1e-10 * out))
    # exact sign with tolerance 0: on straight edges phi is exactly 0, so still inside
    assert np.all(p.contains(on, tolerance=0.0))
    assert not np.any(p.contains(on + 1e-15 * out, tolerance=0.0))
    ring = annulus()
    on_circle = np.vstack([ring.edge(e).evaluate(np.linspace(0, 2 * math.pi, 13)) for e in ("outer", "inner")])
    assert np.all(np.abs(ring.signed_distance(on_circle)) < 1e-15)
    assert np.all(ring.contains(on_circle))


def thin_half_ellipse():
    arc = EllipticArc((0.0, 0.0), (3.0, 0.2), 10.0, math.pi, 2 * math.pi, "arc")
    return Profile([[arc, Segment(arc.end, arc.start, "flat")]])


@pytest.mark.parametrize("make", [lshape, mixed_profile, annulus, thin_half_ellipse])
def test_random_points_against_brute_force(make):
    profile = make()
    lo, hi = profile.bounds
    P = RNG.uniform(lo - 0.5, hi + 0.5, (600, 2))
    ref, S = brute_force_phi(profile, P)
    spacing = np.max(np.linalg.norm(np.diff(S, axis=0), axis=1)[:-1])
    phi = profile.signed_distance(P)
    assert np.all(np.abs(phi) <= np.abs(ref) + 1e-12)
    assert np.all(np.abs(phi) >= np.abs(ref) - spacing)
    clear = np.abs(ref) > 2 * spacing  # matplotlib's polygon test is only valid away from the boundary
    np.testing.assert_array_equal(np.sign(phi[clear]), np.sign(ref[clear]))


def test_reflex_and_sharp_corners_sign():
    # points around the reflex corner (1, 1) of the L-shape and the sharp tip of a thin wedge
    L = lshape()
    ang = np.linspace(0, 2 * math.pi, 721)
    for r in (1e-9, 1e-3, 0.3):
        P = np.array([1.0, 1.0]) + r * np.column_stack([np.cos(ang), np.sin(ang)])
        phi = L.signed_distance(P)
        outside = (P[:, 0] > 1) & (P[:, 1] > 1)
        on_edge = (np.abs(P[:, 0] - 1) < 1e-15) | (np.abs(P[:, 1] - 1) < 1e-15)
        assert np.all(phi[outside & ~on_edge] < 0) and np.all(phi[~outside & ~on_edge] > 0)
        # outside the reflex corner the nearest point is on an edge: min(x - 1, y - 1)
        ref = np.minimum(P[:, 0] - 1, P[:, 1] - 1)
        np.testing.assert_allclose(-phi[outside], ref[outside], atol=1e-15)
        # inside, near the reflex corner: the corner itself is nearest in the quadrant x < 1, y < 1
        q = (P[:, 0] < 1) & (P[:, 1] < 1)
        np.testing.assert_allclose(phi[q], r, rtol=1e-6)
    tip = np.array([4.0, 0.0])
    wedge = Profile([[Segment((0, -0.1), tip, "lower"), Segment(tip, (0, 0.1), "upper"), Segment((0, 0.1), (0, -0.1), "back")]])
    P = tip + 0.05 * np.column_stack([np.cos(ang), np.sin(ang)])
    half = math.atan2(0.1, 4.0)
    inside = np.abs(np.arctan2(P[:, 1], P[:, 0] - 4.0)) > math.pi - half
    phi = wedge.signed_distance(P)
    np.testing.assert_array_equal(phi > 0, inside)


def test_orientation_and_names_follow_the_geometry():
    # clockwise outer loop with edges listed in mixed directions
    e = [Segment((0, 0), (0, 1), "west"), Segment((1, 1), (0, 1), "north"), Segment((1, 1), (1, 0), "east"), Segment((0, 0), (1, 0), "south")]
    p = Profile([e])
    assert p.area == pytest.approx(1.0)
    for name, mid, outward in [("west", (0, 0.5), (-1, 0)), ("north", (0.5, 1), (0, 1)), ("east", (1, 0.5), (1, 0)), ("south", (0.5, 0), (0, -1))]:
        c = p.edge(name)
        pr = c.project([mid])
        assert pr.distances[0] == pytest.approx(0.0, abs=1e-15)
        np.testing.assert_allclose(pr.normals[0], outward, atol=1e-15)
    # chained end to start
    for a, b in zip(p.loops[0], p.loops[0][1:] + p.loops[0][:1]):
        np.testing.assert_allclose(a.end, b.start, atol=1e-15)


def test_mixed_profile_normals_point_out():
    p = mixed_profile()
    for name, c in p.edges.items():
        t = np.linspace(c.t_start, c.t_end, 9)[1:-1]
        X, n = c.evaluate(t), c.normal(t)
        assert np.all(p.signed_distance(X + 1e-4 * n) < 0), name
        assert np.all(p.signed_distance(X - 1e-4 * n) > 0), name


def test_area_by_quadrature():
    assert lshape().area == pytest.approx(3.0, rel=1e-15)
    half_ellipse = Profile([[EllipticArc((0, 0), (3.0, 1.2), 0.0, math.pi, 2 * math.pi, "arc"), Segment((3, 0), (-3, 0), "flat")]])
    assert half_ellipse.area == pytest.approx(0.5 * math.pi * 3.0 * 1.2, rel=1e-14)
    # mixed profile: compare with the shoelace area of a very fine tessellation
    p = mixed_profile()
    (poly, _), = p.tessellate(1e-7)
    shoelace = 0.5 * np.sum(poly[:-1, 0] * poly[1:, 1] - poly[1:, 0] * poly[:-1, 1])
    assert p.area == pytest.approx(shoelace, rel=1e-6)


def test_rigid_motion_invariance():
    for p in (mixed_profile(), annulus(), lshape()):
        lo, hi = p.bounds
        P = RNG.uniform(lo - 0.3, hi + 0.3, (500, 2))
        q = p.transformed(rotate_deg=-63.0, pivot=(0.4, 0.9), translate=(-2.0, 5.0))
        a = math.radians(-63.0)
        R = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
        Q = (P - [0.4, 0.9]) @ R.T + [0.4, 0.9] + [-2.0, 5.0]
        np.testing.assert_allclose(q.signed_distance(Q), p.signed_distance(P), atol=1e-12)
        assert q.edge_names == p.edge_names


def test_bounds_are_exact():
    lo, hi = annulus().bounds
    np.testing.assert_allclose(lo, [0.3 - 2.0, -0.2 - 2.0], atol=1e-14)
    np.testing.assert_allclose(hi, [0.3 + 2.0, -0.2 + 2.0], atol=1e-14)
    p = Profile([[Arc((0, 0), 1.0, 0.0, math.pi, "arc"), Segment((-1, 0), (1, 0), "flat")]])
    lo, hi = p.bounds
    np.testing.assert_allclose(lo, [-1, 0], atol=1e-15)
    np.testing.assert_allclose(hi, [1, 1], atol=1e-15)


def test_tessellation_is_closed_and_indexed():
    p = mixed_profile()
    (pts, idx), = p.tessellate(1e-3)
    np.testing.assert_array_equal(pts[0], pts[-1])
    assert len(idx) == len(pts) - 1
    assert set(idx) == set(range(len(p.edge_names)))
    # every polyline vertex lies on its edge
    for k, name in enumerate(p.edge_names):
        seg_pts = pts[:-1][idx == k]
        assert np.all(np.abs(p.edge(name).project(seg_pts).distances) < 1e-12)


def test_errors():
    with pytest.raises(ValueError, match="not closed"):
        Profile([[Segment((0, 0), (1, 0), "a"), Segment((1, 0), (1, 1), "b")]])
    with pytest.raises(ValueError, match="do not meet|does not start"):
        Profile([[Segment((0, 0), (1, 0), "a"), Segment((2, 0), (2, 1), "b"), Segment((2, 1), (0, 0), "c")]])
    with pytest.raises(ValueError, match="unique"):
        Profile([[Segment((0, 0), (1, 0), "a"), Segment((1, 0), (0, 1), "a"), Segment((0, 1), (0, 0), "c")]])
    with pytest.raises(ValueError, match="outside the outer loop"):
        Profile([[Arc((0, 0), 1.0, 0, 2 * math.pi, "o")], [Arc((5, 0), 0.5, 0, 2 * math.pi, "h")]])
    p = rectangle()
    with pytest.raises(KeyError) as exc:
        p.edge("front")
    assert "bottom, right, top, left" in str(exc.value)
    assert isinstance(exc.value, ValueError) and isinstance(exc.value, UnknownEdgeError)


def test_edge_names_keep_the_given_order_and_loops_out_of_order_are_chained():
    # clockwise square listed out of chain order
    e = [Segment((0, 0), (0, 1), "a"), Segment((1, 0), (0, 0), "b"), Segment((0, 1), (1, 1), "c"), Segment((1, 1), (1, 0), "d")]
    p = Profile([e])
    assert p.edge_names == ("a", "b", "c", "d")
    assert p.area == pytest.approx(1.0)
    for lp in p.loops:
        for x, y in zip(lp, lp[1:] + lp[:1]):
            np.testing.assert_allclose(x.end, y.start, atol=1e-15)
    (pts, idx), = p.tessellate(0.1)
    for k, name in enumerate(p.edge_names):
        assert np.all(np.abs(p.edge(name).project(pts[:-1][idx == k]).distances) < 1e-15)
    q = p.transformed(rotate_deg=10.0)
    assert q.edge_names == p.edge_names
    assert Profile([[Segment(**{"p0": c["start"], "p1": c["end"], "name": c["name"]}) for c in p.to_dict()["edges"]]]).edge_names == p.edge_names
    # the pseudo-normal uses the right neighbours: corners of the square
    corners = np.array([[-1e-3, -1e-3], [1.001, 1.001], [0.001, 0.001], [0.999, 0.5]])
    np.testing.assert_allclose(p.signed_distance(corners), [-math.sqrt(2e-6), -math.sqrt(2e-6), 1e-3, 1e-3], rtol=1e-9)


from hypothesis import assume, given, settings, strategies as st  # noqa: E402


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(3, 12))
def test_random_star_polygons_against_point_segment_brute_force(seed, n):
    rng = np.random.default_rng(seed)
    ang = np.sort(rng.uniform(0, 2 * math.pi, n))
    gaps = np.diff(np.concatenate([ang, [ang[0] + 2 * math.pi]]))
    assume(gaps.min() > 1e-3 and gaps.max() < math.pi - 1e-3)  # simple: star-shaped about the centre
    rad = rng.uniform(0.2, 2.0, n)
    pts = np.column_stack([rad * np.cos(ang), rad * np.sin(ang)]) + rng.uniform(-5, 5, 2)
    if rng.random() < 0.5:
        pts = pts[::-1]  # clockwise input
    p = Profile([[Segment(pts[i], pts[(i + 1) % n], f"s{i}") for i in range(n)]])
    # queries: random, on vertices, on edge midpoints, and along lines through vertices
    mids = 0.5 * (pts + np.roll(pts, -1, axis=0))
    Q = np.vstack([rng.uniform(pts.min(0) - 1, pts.max(0) + 1, (300, 2)), pts, mids, pts + [[0.37, 0.0]]])
    a, b = pts, np.roll(pts, -1, axis=0)
    ab = b - a
    s = np.clip(np.einsum("qkj,kj->qk", Q[:, None, :] - a[None], ab) / np.sum(ab**2, axis=1), 0, 1)
    d = np.min(np.linalg.norm(Q[:, None, :] - (a[None] + s[..., None] * ab[None]), axis=2), axis=1)
    inside = Path(pts).contains_points(Q)
    phi = p.signed_distance(Q)
    np.testing.assert_allclose(np.abs(phi), d, atol=1e-12)
    clear = d > 1e-9
    np.testing.assert_array_equal(phi[clear] > 0, inside[clear])
    assert p.area == pytest.approx(0.5 * abs(np.sum(a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1])), rel=1e-12)
