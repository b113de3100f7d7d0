"""Profile loops are checked for crossings: every loop against itself,
holes against the outer loop and against each other, for every edge type. The truth is
either constructed by hand (where two edges cross) or a brute-force test of all pairs of
polygon sides."""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from ibfem.geometry import Profile
from ibfem.geometry.bounded import Arc, BSplineArc, EllipticArc, Segment
from ibfem.geometry.loop_checks import check_loops
from ibfem.geometry.shapes import profile_from_shape

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import loop_checks  # noqa: E402  (the benchmark's loops and timer)


def line(name, a, b):
    return {"name": name, "type": "line", "start": list(a), "end": list(b)}


def square(prefix, c, r):
    x, y = c
    pts = [(x - r, y - r), (x + r, y - r), (x + r, y + r), (x - r, y + r)]
    return [line(f"{prefix}{k}", pts[k], pts[(k + 1) % 4]) for k in range(4)]


def circle(name, c, r):
    return [{"name": name, "type": "arc", "center": list(c), "radius": r, "start_angle": 0.0, "end_angle": 360.0}]


def refusal(shape) -> str:
    with pytest.raises(ValueError) as exc:
        profile_from_shape(shape)
    return str(exc.value)


# --- loops that cross themselves ---------------------------------------------------------------


def test_the_crossing_point_and_edges_are_named():
    # (0,0)->(2,1) and (2,0)->(0,2) cross where t (2, 1) = (2, 0) + s (-2, 2): t = s = 2/3
    msg = refusal({"type": "profile", "edges": [line("a", (0, 0), (2, 1)), line("b", (2, 1), (2, 0)),
                                                 line("c", (2, 0), (0, 2)), line("d", (0, 2), (0, 0))]})
    assert msg == "shape: outer loop crosses itself (edges 'a' and 'c' at [1.33333, 0.666667])"


def test_an_arc_crossing_a_line_of_its_loop():
    # the arc of radius 1 about (0, 0) from 0 to 180 degrees, closed by a path that cuts it at
    # x = 0.6: (-1, 0) -> (0.6, 2) -> (0.6, -1) -> (1, -1) -> (1, 0). The line x = 0.6 meets the
    # circle at y = 0.8.
    edges = [{"name": "arc", "type": "arc", "center": [0, 0], "radius": 1.0, "start_angle": 0, "end_angle": 180},
             line("l1", (-1, 0), (0.6, 2)), line("l2", (0.6, 2), (0.6, -1)), line("l3", (0.6, -1), (1, -1)),
             line("l4", (1, -1), (1, 0))]
    msg = refusal({"type": "profile", "edges": edges})
    assert "crosses itself (edges 'arc' and 'l2' at [0.6, 0.8])" in msg


def test_an_elliptic_arc_crossing_a_line():
    # ellipse x^2/4 + y^2 = 1 upper half; a line from (-2, 0) to (0, 1.5) crosses it above
    # y = 0; then down to (1, -1) and back to (2, 0): the line (0,1.5)->(1,-1) crosses the arc too
    edges = [{"name": "ell", "type": "elliptic_arc", "center": [0, 0], "semi_axes": [2, 1], "start_angle": 0,
              "end_angle": 180}, line("a", (-2, 0), (0, 1.5)), line("b", (0, 1.5), (1, -1)), line("c", (1, -1), (2, 0))]
    msg = refusal({"type": "profile", "edges": edges})
    assert "crosses itself" in msg and "'ell'" in msg
    point = np.array([float(v) for v in msg.split("at [")[1].rstrip("])").split(",")])
    assert point[0] ** 2 / 4 + point[1] ** 2 == pytest.approx(1.0, abs=1e-5)


def test_a_bspline_edge_that_loops_on_itself():
    # a cubic with a loop: control points swap sides, so the curve crosses itself once
    cp = [[0, 0], [3, 2], [-1, 2], [2, 0]]
    loop = [BSplineArc(3, cp, [0, 0, 0, 0, 1, 1, 1, 1], name="s"), Segment((2, 0), (0, 0), "flat")]
    with pytest.raises(ValueError, match="crosses itself \\(edges 's' and 's'"):
        Profile([loop])


def test_a_spike_that_runs_back_along_its_edge():
    with pytest.raises(ValueError, match="crosses itself"):
        profile_from_shape({"type": "polygon", "points": [[0, 0], [2, 0], [2, 1], [1, 1], [3, 1], [0, 2]]})


@pytest.mark.parametrize("shape", [
    {"type": "rectangle", "min": [-2, -2], "max": [2, 0]},
    {"type": "disk", "center": [0, 0], "radius": 1.0},
    {"type": "half_disk", "center": [0, 1], "radius": 1.0, "side": "below"},
    {"type": "half_ellipse", "center": [0, 0], "semi_axes": [2.0, 0.5], "side": "above"},
    {"type": "half_ellipse", "center": [0, 0], "semi_axes": [1e-3, 50.0], "side": "left"},
])
def test_every_valid_shape_still_builds(shape):
    assert profile_from_shape(shape).area > 0.0


def test_tangent_joints_and_a_lens_are_not_crossings():
    # rounded rectangle: lines meet quarter arcs tangentially
    r = 0.25
    edges = [line("b", (r, 0), (2 - r, 0)), {"name": "c1", "type": "arc", "center": [2 - r, r], "radius": r,
             "start_angle": -90, "end_angle": 0}, line("r", (2, r), (2, 1 - r)),
             {"name": "c2", "type": "arc", "center": [2 - r, 1 - r], "radius": r, "start_angle": 0, "end_angle": 90},
             line("t", (2 - r, 1), (r, 1)), {"name": "c3", "type": "arc", "center": [r, 1 - r], "radius": r,
             "start_angle": 90, "end_angle": 180}, line("l", (0, 1 - r), (0, r)),
             {"name": "c4", "type": "arc", "center": [r, r], "radius": r, "start_angle": 180, "end_angle": 270}]
    prof = profile_from_shape({"type": "profile", "edges": edges})
    assert prof.area == pytest.approx(2.0 - (4 - math.pi) * r * r, rel=1e-12)
    # lens: two arcs of radius 1 about (0, -0.5) and (0, 0.5) meeting at (+-sqrt(3)/2, 0)
    h = math.degrees(math.asin(0.5))
    lens = [{"name": "up", "type": "arc", "center": [0, -0.5], "radius": 1.0, "start_angle": h, "end_angle": 180 - h},
            {"name": "down", "type": "arc", "center": [0, 0.5], "radius": 1.0, "start_angle": 180 + h,
             "end_angle": 360 - h}]
    area = 2 * (math.pi / 3 - math.sqrt(3) / 4)  # two circular segments of half-angle 60 degrees
    assert profile_from_shape({"type": "profile", "edges": lens}).area == pytest.approx(area, rel=1e-12)


def test_a_crescent_with_tangent_tips_is_accepted():
    # outer circle r = 1 about 0 and inner circle r = 0.5 about (0.5, 0), both starting at
    # their tangent point (1, 0): one loop of the two full circles (the inner one clockwise)
    # bounds the region between them; the edges meet only at their shared vertex, at zero angle
    loop = [Arc((0, 0), 1.0, 0.0, 2 * math.pi, "outer"), Arc((0.5, 0), 0.5, 2 * math.pi, 0.0, "inner")]
    prof = Profile([loop])
    assert prof.area == pytest.approx(math.pi * (1 - 0.25), rel=1e-9)


# --- holes --------------------------------------------------------------------------------------


@pytest.mark.parametrize("holes, words", [
    ([square("h", (0, 0), 0.5), square("k", (0.3, 0), 0.5)], "hole 1 crosses hole 0"),
    ([square("h", (1.8, 0), 0.5)], "hole 0 crosses outer loop"),
    ([square("h", (0, 0), 0.5), square("k", (0, 0), 0.2)], "hole 1 lies inside hole 0"),
    ([square("h", (5, 0), 0.5)], "hole 0 lies outside the outer loop"),
    ([circle("h", (1.5, 0), 0.5)], "hole 0 crosses outer loop"),  # touches the side x = 2 at (2, 0)
    ([circle("h", (0, 0), 0.5), circle("k", (1.0, 0), 0.5)], "hole 1 crosses hole 0"),  # two circles touching
])
def test_holes_are_checked(holes, words):
    msg = refusal({"type": "profile", "edges": square("o", (0, 0), 2), "holes": holes})
    assert words in msg


def test_a_touching_hole_names_the_point():
    msg = refusal({"type": "profile", "edges": square("o", (0, 0), 2), "holes": [circle("h", (1.5, 0), 0.5)]})
    point = [float(v) for v in msg.split("at [")[1].rstrip("])").split(",")]
    assert point == pytest.approx([2.0, 0.0], abs=1e-6)


def test_many_separate_holes_are_accepted():
    holes = [circle(f"h{i}{j}", (-1.5 + i, -1.5 + j), 0.3) for i in range(4) for j in range(4)]
    prof = profile_from_shape({"type": "profile", "edges": square("o", (0, 0), 2), "holes": holes})
    assert prof.area == pytest.approx(16.0 - 16 * math.pi * 0.09, rel=1e-12)


def test_an_elliptic_hole_near_the_outer_loop_but_clear_of_it():
    # semi-axis 0.999999 about x = 1: reaches x = 1.999999, 1e-6 from the side x = 2
    hole = [{"name": "h", "type": "elliptic_arc", "center": [1.0, 0], "semi_axes": [0.999999, 0.3], "start_angle": 0,
             "end_angle": 360}]
    prof = profile_from_shape({"type": "profile", "edges": square("o", (0, 0), 2), "holes": [hole]})
    assert prof.area == pytest.approx(16.0 - math.pi * 0.999999 * 0.3, rel=1e-12)


# --- against brute force ------------------------------------------------------------------------


def _brute_force_simple(pts: np.ndarray) -> bool:
    """No two non-adjacent sides of the polygon meet (all pairs, exact orientation tests)."""
    n = len(pts)
    for i in range(n):
        for j in range(i + 2, n):
            if i == 0 and j == n - 1:
                continue
            p1, q1, p2, q2 = pts[i], pts[(i + 1) % n], pts[j], pts[(j + 1) % n]

            def o(a, b, c):
                return np.sign((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))

            if o(p1, q1, p2) * o(p1, q1, q2) < 0 and o(p2, q2, p1) * o(p2, q2, q1) < 0:
                return False
    return True


def test_random_polygons_agree_with_brute_force():
    rng = np.random.default_rng(7)
    agree = {True: 0, False: 0}
    for _ in range(150):
        n = int(rng.integers(4, 9))
        # star-shaped around the centre (simple) with random radii, then some vertices swapped
        ang = np.sort(rng.uniform(0, 2 * np.pi, n))
        pts = np.c_[np.cos(ang), np.sin(ang)] * rng.uniform(0.3, 1.0, (n, 1))
        if rng.random() < 0.5:
            i, j = rng.choice(n, 2, replace=False)
            pts[[i, j]] = pts[[j, i]]
        simple = _brute_force_simple(pts)
        try:
            profile_from_shape({"type": "polygon", "points": pts.tolist()})
            accepted = True
        except ValueError as exc:
            accepted = False
            assert "crosses itself" in str(exc) or "encloses no area" in str(exc)
        assert accepted == simple, pts.tolist()
        agree[simple] += 1
    assert agree[True] > 20 and agree[False] > 20


# --- speed --------------------------------------------------------------------------------------


@pytest.mark.parametrize("kind", ["circle", "zigzag"])
def test_loop_checks_scale_nearly_linearly(kind):
    """Checking a loop of n segments costs about n log n, not n^2: 4x the segments take well
    under 10x the time (16x for a quadratic search). A ratio of two timings in one process holds
    on a loaded machine; the absolute speed (about 0.02 s for 10,000 segments) is a benchmark's."""
    small, large = loop_checks.loop(kind, 2_500), loop_checks.loop(kind, 10_000)
    loop_checks.best_time(small, 1)  # warm caches
    ratio = min(loop_checks.best_time(large) / loop_checks.best_time(small) for _ in range(2))
    assert ratio < 10.0, f"4x the segments took {ratio:.1f}x the time"


def test_curved_edges_are_checked_fast():
    loop = [EllipticArc((0, 0), (3, 1), 10.0, 0.0, 2 * math.pi, "e")]
    holes = [[Arc((-2 + 0.5 * k, 0), 0.2, 0.0, 2 * math.pi, f"h{k}")] for k in range(9)]
    t0 = time.perf_counter()
    Profile([loop] + holes)
    assert time.perf_counter() - t0 < 1.0


@pytest.mark.parametrize("eps", [1e-13, 1e-9, 1e-3])
def test_tiny_edges_at_a_corner_are_not_crossings(eps):
    # the corner (0, 1) cut by an edge of length eps * sqrt(2): the sides before and after it
    # come within eps of each other, and meet the tiny edge only at its ends
    pts = [[0, 0], [1, 0], [1, 1], [eps, 1], [0, 1 - eps]]
    prof = profile_from_shape({"type": "polygon", "points": pts})
    assert prof.area == pytest.approx(1.0 - 0.5 * eps * eps, rel=1e-15)


def test_a_vertex_touching_a_side_of_its_loop_is_refused():
    # the vertex (1, 0) between sides e2 and e3 lies on side e0, from (0, 0) to (2, 0): the
    # loop pinches there (two triangles touching at a point)
    msg = refusal({"type": "polygon", "points": [[0, 0], [2, 0], [2, 1], [1, 0], [0, 1]]})
    assert "outer loop crosses itself (edges 'e0' and 'e2' at [1, 0])" in msg
