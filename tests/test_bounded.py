"""Bounded 2D curves against independent references: closed forms, scipy's elliptic
integrals, and brute force on densely sampled curves."""

import math

import numpy as np
import pytest
from scipy.special import ellipeinc

from ibfem.geometry.bounded import Arc, BSplineArc, EllipticArc, Segment, bounded_curve_from_dict

RNG = np.random.default_rng(20261122)


def quarter_circle_nurbs(r=1.5, center=(0.3, -0.2)):
    """Exact quarter circle as a rational quadratic (weights 1, sqrt(2)/2, 1)."""
    c = np.asarray(center)
    cp = c + r * np.array([[1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    return BSplineArc(2, cp, [0, 0, 0, 1, 1, 1], [1.0, math.sqrt(0.5), 1.0], "q")


def wavy_bspline():
    cp = [[0, 0], [1, 2], [2, -1], [3, 1.5], [4, -0.5], [5, 1.0], [6, 0.0]]
    knots = [0, 0, 0, 0, 0.2, 0.5, 0.7, 1, 1, 1, 1]
    return BSplineArc(3, cp, knots, None, "w")


CURVES = {
    "segment": Segment((-1.0, 0.5), (2.0, 1.7), "s"),
    "arc_ccw": Arc((0.5, -0.3), 1.3, math.radians(20), math.radians(250), "a"),
    "arc_cw": Arc((0.5, -0.3), 1.3, math.radians(200), math.radians(-30), "a"),
    "circle": Arc((0.0, 0.0), 2.0, 0.0, 2 * math.pi, "c"),
    "ellipse_arc": EllipticArc((0.2, 0.1), (3.0, 1.0), 25.0, math.radians(-100), math.radians(120), "e"),
    "ellipse_cw": EllipticArc((0.2, 0.1), (1.0, 2.5), -40.0, math.radians(160), math.radians(-80), "e"),
    "ellipse_thin": EllipticArc((0.0, 0.0), (3.0, 0.15), 15.0, math.radians(200), math.radians(-10), "e"),
    "nurbs": quarter_circle_nurbs(),
    "bspline": wavy_bspline(),
}


def dense(curve, n=200_001):
    t = np.linspace(curve.t_start, curve.t_end, n)
    return curve.evaluate(t)


def brute_force_distance(curve, P, n1=20_001, n2=4_001):
    """Nearest distance to a densely sampled curve, refined by resampling around the best
    sample: (distance, largest sample spacing of the second level)."""
    t1 = np.linspace(curve.t_start, curve.t_end, n1)
    S = curve.evaluate(t1)
    h = t1[1] - t1[0]
    out = np.empty(len(P))
    spacing = 0.0
    for i, p in enumerate(P):
        k = np.argmin(np.hypot(S[:, 0] - p[0], S[:, 1] - p[1]))
        t2 = np.linspace(max(t1[k] - 2 * h, curve.t_start), min(t1[k] + 2 * h, curve.t_end), n2)
        S2 = curve.evaluate(t2)
        out[i] = np.min(np.hypot(S2[:, 0] - p[0], S2[:, 1] - p[1]))
        spacing = max(spacing, np.max(np.linalg.norm(np.diff(S2, axis=0), axis=1)))
    return out, spacing


# -- arc length ------------------------------------------------------------------------------


def test_arc_length_closed_form():
    arc = CURVES["arc_cw"]
    assert arc.length == pytest.approx(1.3 * math.radians(230), rel=1e-15)
    t = np.linspace(0, arc.t_end, 7)
    np.testing.assert_allclose(arc.parameter_at_length(arc.arc_length(t)), t, rtol=0, atol=1e-14)


def ellipse_arc_length_reference(a, b, th0, th1):
    """s(th) = integral sqrt(a^2 sin^2 + b^2 cos^2) = a E(th - pi/2 | m) + const, m = 1 - b^2/a^2 (a >= b)."""
    m = 1.0 - (b / a) ** 2
    return a * (ellipeinc(th1 - math.pi / 2, m) - ellipeinc(th0 - math.pi / 2, m))


@pytest.mark.parametrize("a,b", [(1.0001, 1.0), (2.0, 1.0), (10.0, 1.0), (1000.0, 1.0)])
def test_elliptic_arc_length_against_ellipeinc(a, b):
    th0, th1 = math.radians(-37.0), math.radians(291.0)
    arc = EllipticArc((1.0, 2.0), (a, b), 33.0, th0, th1, "e")
    ref = ellipse_arc_length_reference(a, b, th0, th1)
    assert arc.length == pytest.approx(ref, rel=1e-13)
    # partial lengths and their inverse
    th = np.linspace(th0, th1, 11)
    s_ref = np.array([ellipse_arc_length_reference(a, b, th0, x) for x in th])
    np.testing.assert_allclose(arc.arc_length(th - th0), s_ref, rtol=1e-12, atol=1e-12 * ref)
    np.testing.assert_allclose(arc.parameter_at_length(s_ref), th - th0, atol=1e-10)


def test_generic_length_table_on_a_circle():
    # an elliptic arc with equal semi-axes is a circle: length r * sweep
    arc = EllipticArc((0, 0), (2.0, 2.0), 0.0, 0.3, 4.0, "c")
    assert arc.length == pytest.approx(2.0 * 3.7, rel=1e-14)


def test_nurbs_quarter_circle_is_exact():
    q = quarter_circle_nurbs(r=1.5, center=(0.3, -0.2))
    assert q.length == pytest.approx(1.5 * math.pi / 2, rel=1e-13)
    t = np.linspace(0, 1, 9)
    np.testing.assert_allclose(np.linalg.norm(q.evaluate(t) - [0.3, -0.2], axis=1), 1.5, rtol=1e-15)
    np.testing.assert_allclose(q.curvature(t), 1 / 1.5, rtol=1e-12)
    P = RNG.uniform(-3, 3, (500, 2))
    pr = q.project(P)
    # where the foot lies on the quarter, the distance is |p - c| - r
    rel = P - [0.3, -0.2]
    inside = (rel[:, 0] > 0) & (rel[:, 1] > 0)
    np.testing.assert_allclose(pr.distances[inside], np.linalg.norm(rel[inside], axis=1) - 1.5, atol=1e-13)


# -- projection --------------------------------------------------------------------------------


@pytest.mark.parametrize("key", list(CURVES))
def test_projection_matches_dense_sampling(key):
    curve = CURVES[key]
    # random points, points near the centre of ellipses (inside the evolute: several local
    # minima) and points on the curve
    P = np.vstack(
        [
            RNG.uniform(-4, 5, (300, 2)),
            RNG.normal(getattr(curve, "center", np.zeros(2)), 0.3, (60, 2)),
            curve.evaluate(RNG.uniform(curve.t_start, curve.t_end, 20)),
        ]
    )
    pr = curve.project(P)
    brute, spacing = brute_force_distance(curve, P[::3])
    got = np.abs(pr.distances[::3])
    assert np.all(got <= brute + 1e-12)  # never farther than a sampled point
    assert np.all(got >= brute - 0.5 * spacing - 1e-12)  # and no sample is closer
    # closest point lies on the curve at the reported parameter, normal is unit
    np.testing.assert_allclose(curve.evaluate(pr.parameters), pr.points, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(pr.normals, axis=1), 1.0, atol=1e-14)
    # p - c along the normal wherever the foot is interior
    interior = (pr.parameters > curve.t_start + 1e-9) & (pr.parameters < curve.t_end - 1e-9)
    np.testing.assert_allclose(
        np.einsum("ij,ij->i", P - pr.points, pr.normals)[interior], pr.distances[interior], atol=1e-10
    )
    # points on the curve project onto themselves
    np.testing.assert_allclose(pr.distances[-20:], 0.0, atol=1e-12)


def test_elliptic_arc_interior_local_minimum_beats_the_ends():
    # lower half of a 4 x 1 ellipse; the point near the centre but above the axis has its
    # global foot on the (missing) upper half; on the lower half the nearest point is (0, -1)
    arc = EllipticArc((0, 0), (4.0, 1.0), 0.0, math.pi, 2 * math.pi, "low")
    pr = arc.project([[0.01, 0.05]])
    assert abs(pr.points[0, 0]) < 0.05 and pr.points[0, 1] < -0.99
    S = dense(arc)
    assert abs(pr.distances[0]) <= np.min(np.linalg.norm(S - [0.01, 0.05], axis=1)) + 1e-12
    assert abs(pr.distances[0]) == pytest.approx(1.05, abs=1e-3)


def test_arc_projection_ends_and_centre():
    arc = Arc((0, 0), 1.0, 0.0, math.pi / 2, "q")
    pr = arc.project([[1.0, -3.0], [-3.0, 1.0], [0.0, 0.0], [2.0, 2.0]])
    np.testing.assert_allclose(pr.points[0], [1, 0], atol=1e-15)
    np.testing.assert_allclose(pr.points[1], [0, 1], atol=1e-15)
    assert abs(pr.distances[2]) == pytest.approx(1.0)
    assert pr.distances[3] == pytest.approx(2 * math.sqrt(2) - 1)
    # the end point distance is Euclidean, not (p - c) . n
    assert abs(pr.distances[0]) == pytest.approx(3.0)


def test_normals_and_curvature_sign():
    ccw = Arc((0, 0), 2.0, 0.0, 1.0, "a")
    np.testing.assert_allclose(ccw.normal(0.5), [[math.cos(0.5), math.sin(0.5)]], atol=1e-15)
    assert ccw.curvature(0.2)[0] == pytest.approx(0.5)
    cw = ccw.reversed()
    np.testing.assert_allclose(cw.normal(0.5), -ccw.normal(0.5), atol=1e-15)
    assert cw.curvature(0.1)[0] == pytest.approx(-0.5)
    seg = Segment((0, 0), (1, 0), "s")
    np.testing.assert_allclose(seg.normal(0.3), [[0, -1]])
    # ellipse curvature at the end of the major axis: a / b^2
    e = EllipticArc((0, 0), (3.0, 1.5), 0.0, -1.0, 1.0, "e")
    assert e.curvature(1.0)[0] == pytest.approx(3.0 / 1.5**2, rel=1e-13)


# -- axis crossings ---------------------------------------------------------------------------------


@pytest.mark.parametrize("key", list(CURVES))
def test_axis_crossings_lie_on_the_line_and_are_complete(key):
    curve = CURVES[key]
    S = dense(curve, 20_001)
    for axis in (0, 1):
        lo, hi = S[:, axis].min(), S[:, axis].max()
        for value in np.linspace(lo - 0.1, hi + 0.1, 9):
            t = curve.axis_crossings(axis, value)
            assert np.all(np.diff(t) > 0)
            if t.size:
                np.testing.assert_allclose(curve.evaluate(t)[:, axis], value, atol=1e-12)
            f = S[:, axis] - value
            changes = np.count_nonzero(f[:-1] * f[1:] < 0)
            assert t.size >= changes


def test_axis_crossings_exact_values():
    arc = Arc((0, 0), 2.0, 0.0, math.pi, "upper")
    t = arc.axis_crossings(0, 1.0)
    np.testing.assert_allclose(t, [math.pi / 3])
    np.testing.assert_allclose(arc.axis_crossings(1, 1.0), [math.pi / 6, 5 * math.pi / 6])
    seg = Segment((0, 0), (2, 0), "s")
    np.testing.assert_allclose(seg.axis_crossings(0, 0.5), [0.5])
    np.testing.assert_allclose(seg.axis_crossings(1, 0.0), [0.0, 2.0])  # lying on the line
    assert seg.axis_crossings(1, 1e-3).size == 0


# -- quadrature ------------------------------------------------------------------------------------


def test_quadrature_integrates_x_squared_along_an_arc():
    cx, r, th0, th1 = 0.7, 1.9, 0.4, 2.9
    arc = Arc((cx, -1.0), r, th0, th1, "a")
    X, w, n, t = arc.quadrature(0.0, arc.t_end, 24)
    ref = r * (
        cx**2 * (th1 - th0)
        + 2 * cx * r * (math.sin(th1) - math.sin(th0))
        + r**2 * ((th1 - th0) / 2 + (math.sin(2 * th1) - math.sin(2 * th0)) / 4)
    )
    assert np.sum(w * X[:, 0] ** 2) == pytest.approx(ref, rel=1e-14)
    assert np.sum(w) == pytest.approx(arc.length, rel=1e-14)
    np.testing.assert_allclose(n, arc.normal(t))


def test_quadrature_on_segment_is_exact_for_polynomials():
    seg = Segment((1.0, 0.0), (4.0, 4.0), "s")  # length 5
    X, w, n, t = seg.quadrature(0.0, 5.0, 2)
    # x = 1 + 3 s / 5 ; integral of x^2 ds over [0, 5] = (4^3 - 1) / 3 * 5 / 3
    assert np.sum(w * X[:, 0] ** 2) == pytest.approx((64 - 1) / 3 * 5 / 3, rel=1e-14)


def test_quadrature_on_ellipse_sums_to_length_and_splits_bsplines_at_knots():
    e = CURVES["ellipse_arc"]
    _, w, _, _ = e.quadrature(0.0, e.t_end, 80)
    assert np.sum(w) == pytest.approx(e.length, rel=1e-13)
    # a piece of the size the solver integrates (one cell): a low order is already exact
    _, w, _, _ = e.quadrature(0.5, 0.6, 6)
    assert np.sum(w) == pytest.approx(e.arc_length(0.6)[0] - e.arc_length(0.5)[0], rel=1e-12)
    b = CURVES["bspline"]
    _, w, _, t = b.quadrature(0.1, 0.8, 30)
    assert len(t) == 30 * 4  # pieces [0.1,0.2],[0.2,0.5],[0.5,0.7],[0.7,0.8]
    assert np.sum(w) == pytest.approx(b.arc_length(0.8)[0] - b.arc_length(0.1)[0], rel=1e-13)


# -- chord matching --------------------------------------------------------------------------------


@pytest.mark.parametrize("key", list(CURVES))
def test_parameter_at_chord_distance(key):
    curve = CURVES[key]
    t_from = curve.t_start + 0.3 * (curve.t_end - curve.t_start)
    origin = curve.evaluate(t_from)[0]
    for direction in (1, -1):
        chords = np.linspace(0.0, 0.5 * curve.length, 7)
        t = curve.parameter_at_chord(origin, chords, t_from, direction)
        ok = np.isfinite(t)
        assert ok[0] and t[0] == pytest.approx(t_from)
        np.testing.assert_allclose(np.linalg.norm(curve.evaluate(t[ok]) - origin, axis=1), chords[ok], atol=1e-12)
        assert np.all(direction * (t[ok] - t_from) >= -1e-15)
    # farther than any point of the curve: NaN
    far = curve.parameter_at_chord(origin, [100.0], t_from, 1)
    assert np.isnan(far[0])


def test_parameter_at_chord_on_arc_closed_form():
    r = 2.0
    arc = Arc((0, 0), r, 0.0, math.pi, "a")
    chords = np.array([0.1, 1.0, 2.5, 3.9])
    t = arc.parameter_at_chord(arc.start, chords, 0.0, 1)
    np.testing.assert_allclose(t, 2 * np.arcsin(chords / (2 * r)), atol=1e-14)


# -- tessellation, reversal, transforms, dicts -----------------------------------------------------------


@pytest.mark.parametrize("key", list(CURVES))
def test_tessellation_within_tolerance(key):
    curve = CURVES[key]
    tol = 1e-3
    X, t = curve.tessellate(tol)
    np.testing.assert_allclose(X[0], curve.start, atol=1e-15)
    np.testing.assert_allclose(X[-1], curve.end, atol=1e-12)
    # dense curve points are within tol of the polyline
    S = dense(curve, 5001)
    a, b = X[:-1], X[1:]
    ab = b - a
    L2 = np.maximum(np.sum(ab**2, axis=1), 1e-300)
    best = np.full(len(S), np.inf)
    for i in range(len(a)):
        s = np.clip((S - a[i]) @ ab[i] / L2[i], 0, 1)
        best = np.minimum(best, np.linalg.norm(S - a[i] - s[:, None] * ab[i], axis=1))
    assert best.max() <= tol * 1.05


@pytest.mark.parametrize("key", list(CURVES))
def test_reversed_and_transformed(key):
    curve = CURVES[key]
    rev = curve.reversed()
    np.testing.assert_allclose(rev.start, curve.end, atol=1e-13)
    np.testing.assert_allclose(rev.end, curve.start, atol=1e-13)
    assert rev.length == pytest.approx(curve.length, rel=1e-12)
    P = RNG.uniform(-3, 3, (50, 2))
    np.testing.assert_allclose(rev.project(P).distances, -curve.project(P).distances, atol=1e-11)
    # rigid motion: distances invariant
    moved = curve.transformed(rotate_deg=37.0, pivot=(1.0, -2.0), translate=(0.5, 3.0))
    ang = math.radians(37.0)
    R = np.array([[math.cos(ang), -math.sin(ang)], [math.sin(ang), math.cos(ang)]])
    Q = (P - [1.0, -2.0]) @ R.T + [1.0, -2.0] + [0.5, 3.0]
    np.testing.assert_allclose(moved.project(Q).distances, curve.project(P).distances, atol=1e-11)
    # the scene format's edge dict round-trips
    back = bounded_curve_from_dict(curve.to_dict())
    t = np.linspace(curve.t_start, curve.t_end, 5)
    np.testing.assert_allclose(back.evaluate(t), curve.evaluate(t), atol=1e-13)


@pytest.mark.parametrize(
    "d,msg",
    [
        ({"type": "arc", "center": [0, 0], "radius": -1, "start_angle": 0, "end_angle": 90}, "edge.radius must be positive"),
        ({"type": "line", "start": [0, 0], "end": [0, 0]}, "coincide"),
        ({"type": "line", "start": [0, 0]}, "missing key(s) end"),
        ({"type": "circle"}, "edge.type must be one of"),
        ({"type": "arc", "center": [0, 0], "radius": 1, "start_angle": 0, "end_angle": 400}, "more than 360"),
        ({"type": "elliptic_arc", "center": [0, 0], "semi_axes": [1, 0], "start_angle": 0, "end_angle": 9}, "semi_axes"),
        ({"type": "bspline", "degree": 2, "control_points": [[0, 0], [1, 1], [2, 0]], "knots": [0, 0, 1, 1]}, "knots"),
        ({"type": "bspline", "degree": 1, "control_points": [[0, 0], [1, 1]], "knots": [0, 0, 1, 1], "weights": [1, -1]}, "weights"),
        ({"type": "line", "start": [0, "a"], "end": [1, 1]}, "edge.start"),
    ],
)
def test_invalid_edges_name_the_key(d, msg):
    with pytest.raises(ValueError, match=None) as exc:
        bounded_curve_from_dict(d)
    assert msg in str(exc.value)


@pytest.mark.parametrize("key", list(CURVES))
def test_empty_and_single_point_queries(key):
    curve = CURVES[key]
    pr = curve.project(np.zeros((0, 2)))
    assert pr.points.shape == (0, 2) and pr.distances.shape == (0,)
    one = curve.project([0.1, 0.2])
    assert one.points.shape == (1, 2)
    with pytest.raises(ValueError, match="points must have shape"):
        curve.project(np.zeros((3, 3)))


def test_breakpoints_and_sampled_crossings_of_a_spline():
    b = CURVES["bspline"]
    np.testing.assert_allclose(b.breakpoints(), [0, 0.2, 0.5, 0.7, 1.0])
    # x(t) of this spline is monotone: one crossing per vertical line, at the right place
    for v in np.linspace(0.1, 5.9, 13):
        t = b.axis_crossings(0, v)
        assert t.size == 1
        assert b.evaluate(t)[0, 0] == pytest.approx(v, abs=1e-13)


def test_bspline_with_a_corner_signs_by_pseudo_normal():
    # degree-2 spline with a double knot at 0.5: a sharp corner at control point (1, 3)
    cp = [[0, 0], [0.5, 1.5], [1, 3], [1.5, 1.5], [2, 0]]
    b = BSplineArc(2, cp, [0, 0, 0, 0.5, 0.5, 1, 1, 1], None, "tent")
    np.testing.assert_allclose(b.kinks, [0.5])
    np.testing.assert_allclose(b.evaluate(0.5)[0], [1, 3])
    # the tent runs left to right: its normal (right-hand side) points down, into the tent
    ang = np.linspace(0.0, 2 * math.pi, 361)
    P = np.array([1.0, 3.0]) + 0.2 * np.column_stack([np.cos(ang), np.sin(ang)])
    pr = b.project(P)
    # above the apex (inside the cone of the two outward-up normals) the side is "left" (-)
    left_normal = np.array([3.0, 1.0]) / math.sqrt(10.0)  # outward normal of the left leg (up-left side)
    right_normal = np.array([-3.0, 1.0]) / math.sqrt(10.0)
    above = ((P - [1, 3]) @ left_normal < 0) & ((P - [1, 3]) @ right_normal < 0)
    at_apex = np.linalg.norm(pr.points - [1, 3], axis=1) < 1e-9
    assert np.all(pr.distances[at_apex & above] < 0)
    brute, _ = brute_force_distance(b, P[::20])
    np.testing.assert_allclose(np.abs(pr.distances[::20]), brute, atol=1e-9)


def test_parameter_at_chord_not_monotone_returns_the_first_crossing():
    circle = CURVES["circle"]  # r = 2, starts at (2, 0)
    t = circle.parameter_at_chord(circle.start, [1.0, 3.9, 4.0], 0.0, 1)
    np.testing.assert_allclose(t[:2], 2 * np.arcsin(np.array([1.0, 3.9]) / 4.0), atol=1e-13)
    assert t[2] == pytest.approx(math.pi, abs=1e-7)  # the far point, reached once (tangency)
    t = circle.parameter_at_chord(circle.start, [1.0], 0.0, -1)
    np.testing.assert_allclose(t, [2 * math.pi - 2 * math.asin(0.25)], atol=1e-13)
    # origin off the curve: the distance first falls to the chord, then rises again
    seg = Segment((-2.0, 0.0), (2.0, 0.0), "s")
    from ibfem.geometry.bounded import BoundedCurve

    for method in (seg.parameter_at_chord, lambda *a: BoundedCurve.parameter_at_chord(seg, *a)):
        t = method((0.0, 1.0), np.array([1.5, 0.5, 3.0]), 0.0, 1)
        np.testing.assert_allclose(t[0], 2.0 - math.sqrt(1.25), atol=1e-14)
        assert np.isnan(t[1]) and np.isnan(t[2])  # closer than the curve ever gets / farther


@pytest.mark.parametrize("seed", range(6))
def test_random_bsplines_against_brute_force(seed):
    # random degree 1-4 splines (rational half of the time): polylines with many corners and
    # points close to the curve are the hard cases for sampled seeding
    rng = np.random.default_rng(100 + seed)
    n = int(rng.integers(5, 16))
    p = int(min(rng.integers(1, 5), n - 1))
    inner = np.sort(rng.uniform(0, 1, n - p - 1))
    knots = np.concatenate([np.zeros(p + 1), inner, np.ones(p + 1)])
    b = BSplineArc(p, rng.uniform(-3, 3, (n, 2)), knots, rng.uniform(0.3, 3, n) if seed % 2 else None, "r")
    on = b.evaluate(rng.uniform(0, 1, 40))
    P = np.vstack([rng.uniform(-4, 4, (80, 2)), on + rng.normal(0, 0.05, on.shape)])
    pr = b.project(P)
    brute, spacing = brute_force_distance(b, P, n1=50_001, n2=1_001)
    assert np.all(np.abs(pr.distances) <= brute + 1e-12)
    assert np.all(np.abs(pr.distances) >= brute - 0.5 * spacing - 1e-12)


def test_spline_crossings_near_a_tangent_line_are_found():
    # y(t) = 4t - 3.5t^2: apex y = 8/7 at t = 4/7, between two samples (they are at k/12)
    b = BSplineArc(2, [[-1.0, 0.0], [0.0, 2.0], [1.0, 0.5]], [0, 0, 0, 1, 1, 1], None, "cap")
    apex = 8.0 / 7.0
    grid, S, _ = b._pieces
    assert np.all(np.abs(grid - 4 / 7) > 1e-3) and np.all(S[:, 1] < apex - 2e-4)  # no sample reaches
    for value in (apex - 1e-9, apex - 1e-4, apex - 0.3):
        tc = b.axis_crossings(1, value)
        assert tc.size == 2
        np.testing.assert_allclose(b.evaluate(tc)[:, 1], value, atol=1e-14)
        ref = (4 + np.array([-1, 1]) * np.sqrt(16 - 14 * value)) / 7  # roots of 3.5t^2 - 4t + v
        np.testing.assert_allclose(tc, ref, atol=1e-7)
    assert b.axis_crossings(1, apex + 1e-9).size == 0


@pytest.mark.parametrize("key", ["nurbs", "bspline"])
def test_trimmed_spline_is_the_same_curve_piece(key):
    b = CURVES[key]
    for t0, t1 in [(0.13, 0.61), (0.0, 0.5), (0.2, 1.0), (0.5, 0.7)]:
        piece = b.trimmed(t0, t1)
        assert piece.t_start == t0 and piece.t_end == t1
        t = np.linspace(t0, t1, 17)
        np.testing.assert_allclose(piece.evaluate(t), b.evaluate(t), atol=1e-14)
        np.testing.assert_allclose(piece.derivative(t[1:-1]), b.derivative(t[1:-1]), atol=1e-12)
        assert piece.length == pytest.approx(b.arc_length(t1)[0] - b.arc_length(t0)[0], rel=1e-13)
    with pytest.raises(ValueError, match="trim range"):
        b.trimmed(0.5, 0.2)


from hypothesis import given, settings, strategies as st  # noqa: E402


@settings(max_examples=40, deadline=None)
@given(
    kind=st.sampled_from(["arc", "elliptic"]),
    a=st.floats(0.01, 100.0),
    ratio=st.floats(0.001, 1.0),
    rot=st.floats(-180.0, 180.0),
    th0=st.floats(-360.0, 360.0),
    sweep=st.floats(-360.0, 360.0).filter(lambda x: abs(x) > 1e-3),
    cx=st.floats(-1e3, 1e3),
    cy=st.floats(-1e3, 1e3),
    seed=st.integers(0, 2**31),
)
def test_property_arcs_in_random_orientations(kind, a, ratio, rot, th0, sweep, cx, cy, seed):
    t0, t1 = math.radians(th0), math.radians(th0 + sweep)
    if kind == "arc":
        c = Arc((cx, cy), a, t0, t1, "h")
    else:
        c = EllipticArc((cx, cy), (a, a * ratio), rot, t0, t1, "h")
    rng = np.random.default_rng(seed)
    P = np.array([cx, cy]) + a * rng.normal(0, 1.0, (40, 2))
    P = np.vstack([P, [[cx, cy]], c.evaluate(rng.uniform(0, c.t_end, 5))])
    pr = c.project(P)
    scale = a + abs(cx) + abs(cy)
    # the closest point is on the curve at its parameter, inside the trimmed range
    assert np.all((pr.parameters >= 0) & (pr.parameters <= c.t_end))
    np.testing.assert_allclose(c.evaluate(pr.parameters), pr.points, atol=1e-12 * scale)
    # no densely sampled point of the curve is closer
    S = c.evaluate(np.linspace(0, c.t_end, 20_001))
    brute = np.min(np.hypot(P[:, 0, None] - S[None, :, 0], P[:, 1, None] - S[None, :, 1]), axis=1)
    assert np.all(np.abs(pr.distances) <= brute + 1e-12 * scale)
    # p - c along the normal where the foot is interior
    inner = (pr.parameters > 1e-9) & (pr.parameters < c.t_end - 1e-9)
    r = P - pr.points
    tang = c.tangent(pr.parameters)
    assert np.all(np.abs(np.einsum("ij,ij->i", r, tang))[inner] <= 1e-9 * scale)
    # points on the curve project onto themselves
    np.testing.assert_allclose(pr.distances[-5:], 0.0, atol=1e-12 * scale)
