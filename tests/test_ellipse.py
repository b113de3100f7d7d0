"""The ellipse: the 2D kernel against an independent reference (dense sampling of the ellipse
refined by golden-section search), exact answers on the axes and at the centre (Eberly's closed
forms), offset-and-project-back, and the 3D primitive."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ibfem.geometry import Ellipse, ellipse_closest_point_2d, primitive_from_dict

EPS = np.finfo(float).eps
GOLD = (math.sqrt(5.0) - 1.0) / 2.0


def reference_distance(a, b, x, y, samples=8192, iterations=90):
    """Unsigned distance from (x, y) to the ellipse, independently of the code under test:
    the best of ``samples`` eccentric angles, refined by golden-section search on the squared
    distance within one sample spacing either side (vectorised over the points)."""
    th = np.linspace(-np.pi, np.pi, samples, endpoint=False)
    ex, ey = a * np.cos(th), b * np.sin(th)
    best = np.empty(len(x), dtype=int)
    for i in range(0, len(x), 256):
        d2 = (x[i : i + 256, None] - ex) ** 2 + (y[i : i + 256, None] - ey) ** 2
        best[i : i + 256] = d2.argmin(axis=1)
    h = 2 * np.pi / samples

    def f(t):
        return (x - a * np.cos(t)) ** 2 + (y - b * np.sin(t)) ** 2

    lo, hi = th[best] - h, th[best] + h
    c, d = hi - GOLD * (hi - lo), lo + GOLD * (hi - lo)
    fc, fd = f(c), f(d)
    for _ in range(iterations):
        left = fc < fd
        hi = np.where(left, d, hi)
        lo = np.where(left, lo, c)
        new_c = hi - GOLD * (hi - lo)
        new_d = lo + GOLD * (hi - lo)
        c, d = np.where(left, new_c, d), np.where(left, c, new_d)
        fc, fd = np.where(left, f(new_c), fd), np.where(left, fc, f(new_d))
    return np.sqrt(np.minimum(np.minimum(fc, fd), f(th[best])))


def points_of_every_kind(a, b, rng, n=60):
    """Generic points, near the centre, on and near the axes, near the ellipse, near the evolute
    cusps, far away, and tiny (denormal) coordinates."""
    ev = (a - b) * (a + b) / a  # evolute cusp on the major axis
    th = rng.uniform(-np.pi, np.pi, n)
    on = np.c_[a * np.cos(th), b * np.sin(th)]
    nrm = np.c_[np.cos(th) / a, np.sin(th) / b]
    nrm /= np.linalg.norm(nrm, axis=1)[:, None]
    pts = [
        rng.uniform(-2, 2, (n, 2)) * [a, b],  # generic
        rng.uniform(-2, 2, (n, 2)) * a,
        rng.normal(size=(n // 2, 2)) * b * 1e-8,  # near the centre
        np.c_[rng.uniform(-2 * a, 2 * a, n // 2), np.zeros(n // 2)],  # on the major axis
        np.c_[np.zeros(n // 2), rng.uniform(-2 * b, 2 * b, n // 2)],  # on the minor axis
        np.c_[rng.uniform(-2 * a, 2 * a, n // 2), 10.0 ** rng.uniform(-300, -1, n // 2) * b],  # near it
        np.c_[10.0 ** rng.uniform(-300, -1, n // 2) * a, rng.uniform(-2 * b, 2 * b, n // 2)],
        on + rng.uniform(-1e-9, 1e-9, (n, 1)) * b * nrm,  # near the ellipse
        on,
        np.c_[ev * (1 + rng.uniform(-1e-6, 1e-6, n // 2)), 10.0 ** rng.uniform(-20, -2, n // 2) * b],  # cusp
        rng.normal(size=(n // 2, 2)) * 1e6 * a,  # far away
        np.array([[0.0, 0.0], [5e-324, 0.0], [0.0, 5e-324], [5e-324, 5e-324], [ev, 0.0], [-ev, 0.0], [a, 0.0], [0.0, -b]]),
    ]
    return np.vstack(pts)


def check_kernel(a, b, x, y):
    cx, cy = ellipse_closest_point_2d(a, b, x, y)
    scale = np.hypot(x, y) + max(a, b)
    # on the ellipse
    assert np.max(np.abs((cx / a) ** 2 + (cy / b) ** 2 - 1)) < 8 * EPS
    # p - c along the ellipse's normal (cx/a^2, cy/b^2)
    nx, ny = cx / a**2, cy / b**2
    nn = np.hypot(nx, ny)
    cross = ((x - cx) * ny - (y - cy) * nx) / nn
    assert np.max(np.abs(cross) / scale) < 16 * EPS
    # the distance is the smallest one (independent reference), to 1e-12 relative or round-off
    dist = np.hypot(x - cx, y - cy)
    ref = reference_distance(a, b, x, y)
    err = np.abs(dist - ref)
    assert np.all(err <= 1e-12 * ref + 16 * EPS * scale), (np.max(err / (ref + scale * EPS)), np.argmax(err))
    # the closest point is in the query point's quadrant
    assert np.all((cx * x >= 0) & (cy * y >= 0))
    return cx, cy


@pytest.mark.parametrize("ratio", [1.0, 1.0001, 1.01, 2.0, 10.0, 100.0, 1000.0])
def test_kernel_against_reference(ratio):
    rng = np.random.default_rng(int(ratio * 1000))
    a = 1.3
    b = a / ratio
    p = points_of_every_kind(a, b, rng)
    check_kernel(a, b, p[:, 0], p[:, 1])


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    log_ratio=st.floats(0.0, 3.0),
    log_scale=st.floats(-3.0, 3.0),
    seed=st.integers(0, 2**32 - 1),
    swap=st.booleans(),
)
def test_kernel_random_ellipses(log_ratio, log_scale, seed, swap):
    a = 10.0**log_scale
    b = a / 10.0**log_ratio
    rng = np.random.default_rng(seed)
    p = points_of_every_kind(a, b, rng, n=16)
    if swap:  # a < b: the kernel swaps the roles of the axes
        check_kernel(b, a, p[:, 1], p[:, 0])
    else:
        check_kernel(a, b, p[:, 0], p[:, 1])


@pytest.mark.parametrize("ratio", [1.0001, 1.5, 30.0, 1000.0])
def test_kernel_closed_forms_on_the_axes(ratio):
    a, b = 2.0, 2.0 / ratio
    ev = (a * a - b * b) / a
    # centre: the co-vertex, at distance b
    cx, cy = ellipse_closest_point_2d(a, b, np.zeros(1), np.zeros(1))
    assert cx[0] == 0.0 and cy[0] == b
    # major axis inside the evolute (Eberly): x0 = a^2 x / (a^2 - b^2), y0 = b sqrt(1 - (x0/a)^2)
    x = np.linspace(-0.999, 0.999, 41) * ev
    cx, cy = ellipse_closest_point_2d(a, b, x, np.zeros_like(x))
    x0 = a * a * x / ((a - b) * (a + b))
    assert np.allclose(cx, x0, rtol=4 * EPS, atol=4 * EPS * a)
    # (sqrt(1 - u^2) amplifies the last-bit error of u near the cusp: both sides round differently)
    assert np.allclose(cy, b * np.sqrt(1 - (x0 / a) ** 2), rtol=1e-14, atol=64 * EPS * a)
    # major axis beyond the evolute: the vertex
    x = np.r_[np.linspace(1.0001, 5, 20) * ev, a, 3 * a, 1e8]
    cx, cy = ellipse_closest_point_2d(a, b, x, np.zeros_like(x))
    assert np.array_equal(cx, np.full_like(x, a)) and np.array_equal(cy, np.zeros_like(x))
    # minor axis: the co-vertex
    y = np.r_[np.linspace(-5, 5, 21) * b, 1e9]
    cx, cy = ellipse_closest_point_2d(a, b, np.zeros_like(y), y)
    assert np.array_equal(np.abs(cx), np.zeros_like(y)) and np.allclose(cy, np.where(y < 0, -b, b), rtol=0, atol=0)


def test_kernel_broadcasts_and_validates():
    cx, cy = ellipse_closest_point_2d(2.0, 1.0, np.array([[3.0], [0.0]]), np.array([0.0, 2.0]))
    assert cx.shape == (2, 2)
    assert np.allclose(cx[0, 0], 2.0) and np.allclose(cy[1, 1], 1.0)
    with pytest.raises(ValueError, match="'b'"):
        ellipse_closest_point_2d(1.0, 0.0, [1.0], [1.0])
    with pytest.raises(ValueError, match="'a'"):
        ellipse_closest_point_2d(-1.0, 1.0, [1.0], [1.0])


def analytic_points(a, b, th):
    """Points of the ellipse, the outward unit normals there, and the largest inward offset
    that keeps the closest point (the centre of curvature or the major axis, whichever first)."""
    X = np.c_[a * np.cos(th), b * np.sin(th)]
    N = np.c_[b * np.cos(th), a * np.sin(th)]
    N /= np.linalg.norm(N, axis=1)[:, None]
    curvature_radius = (a * a * np.sin(th) ** 2 + b * b * np.cos(th) ** 2) ** 1.5 / (a * b)
    with np.errstate(divide="ignore", invalid="ignore"):
        to_axis = np.where(np.abs(N[:, 1]) > 0, np.abs(X[:, 1] / N[:, 1]), np.inf)
    return X, N, np.minimum(curvature_radius, to_axis)


@settings(max_examples=30, deadline=None)
@given(log_ratio=st.floats(0.0, 3.0), seed=st.integers(0, 2**32 - 1))
def test_offset_along_normal_projects_back_2d(log_ratio, seed):
    rng = np.random.default_rng(seed)
    a, b = 1.7, 1.7 / 10.0**log_ratio
    th = np.r_[rng.uniform(-np.pi, np.pi, 200), 0.0, np.pi / 2, np.pi, -np.pi / 2]
    X, N, inward = analytic_points(a, b, th)
    frac = rng.uniform(-0.95, 3.0, len(th))
    delta = np.where(frac < 0, frac * inward, frac * a)
    p = X + delta[:, None] * N
    e = primitive_from_dict({"type": "ellipse", "origin": [0, 0], "major_axis": [1, 0], "major_radius": a, "minor_radius": b})
    pr = e.project(p)
    assert pr.points.shape == p.shape and pr.normals.shape == p.shape
    scale = a + np.abs(delta)
    assert np.all(np.linalg.norm(pr.points - X, axis=1) <= 64 * EPS * scale / np.minimum(1.0, inward / a) ** 0.5)
    assert np.all(np.abs(pr.distances - delta) <= 32 * EPS * scale)
    assert np.max(np.linalg.norm(pr.normals - N, axis=1)) < 1e-9
    # the parameter is the eccentric angle
    assert np.max(np.abs(np.angle(np.exp(1j * (pr.parameters - th))))) < 1e-7


def random_frame(rng):
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return q[:, 0], q[:, 1], q[:, 2]


@settings(max_examples=25, deadline=None)
@given(log_ratio=st.floats(0.0, 3.0), seed=st.integers(0, 2**32 - 1))
def test_3d_ellipse_in_random_orientation(log_ratio, seed):
    rng = np.random.default_rng(seed)
    e1, e2, n = random_frame(rng)
    o = rng.uniform(-5, 5, 3)
    a = rng.uniform(0.2, 4)
    b = a / 10.0**log_ratio
    tilt = rng.normal(size=3) * 0.01  # the major axis need not be exactly in the plane
    d = {"type": "ellipse", "origin": list(o), "normal": list(n), "major_axis": list(e1 + tilt), "major_radius": a, "minor_radius": b}
    ell = primitive_from_dict(d)
    e1 = e1 + tilt - np.dot(e1 + tilt, n) * n
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(n, e1)
    p = o + rng.normal(size=(150, 3)) * a
    pr = ell.project(p)
    r = pr.points - o
    u, v, h = r @ e1, r @ e2, r @ n
    scale = a + np.linalg.norm(p - o, axis=1)
    assert np.max(np.abs(h) / scale) < 16 * EPS
    # global coordinates carry rounding of size eps |origin|: relative to b after the division
    assert np.max(np.abs((u / a) ** 2 + (v / b) ** 2 - 1)) < 32 * EPS * (np.linalg.norm(o) + a) / b
    assert np.max(np.abs(np.linalg.norm(pr.normals, axis=1) - 1)) < 1e-14
    assert np.max(np.abs(pr.normals @ n)) < 1e-14  # in-plane normal
    # outward: away from the centre
    assert np.all(np.einsum("ij,ij->i", pr.normals, r) > 0)
    # signed Euclidean distances: |p - closest|, sign of the in-plane offset along the normal
    assert np.max(np.abs(np.linalg.norm(p - pr.points, axis=1) - np.abs(pr.distances)) / scale) < 16 * EPS
    # the in-plane part of p - closest is along the normal
    w = (p - pr.points) - np.outer((p - o) @ n, n)
    inplane = np.einsum("ij,ij->i", w, pr.normals)
    assert np.max(np.linalg.norm(w - inplane[:, None] * pr.normals, axis=1) / scale) < 32 * EPS
    assert np.all(pr.distances * inplane >= 0)
    assert np.max(np.abs(np.hypot(inplane, (p - o) @ n) - np.abs(pr.distances)) / scale) < 32 * EPS
    # no point of the ellipse is closer (3D distances, independent reference in the plane)
    pu, pv, ph = (p - o) @ e1, (p - o) @ e2, (p - o) @ n
    ref = np.hypot(reference_distance(a, b, pu, pv), ph)
    got = np.linalg.norm(p - pr.points, axis=1)
    assert np.all(np.abs(got - ref) <= 1e-12 * ref + 32 * EPS * scale)
    # signed: negative inside
    inside = (pu / a) ** 2 + (pv / b) ** 2 < 1 - 1e-9
    outside = (pu / a) ** 2 + (pv / b) ** 2 > 1 + 1e-9
    assert np.all(pr.distances[inside] < 0) and np.all(pr.distances[outside] > 0)


def test_ellipse_definitions():
    base = {"type": "ellipse", "origin": [0, 0, 0], "normal": [0, 0, 1], "major_axis": [1, 0, 0], "major_radius": 2.0, "minor_radius": 1.0}
    e = primitive_from_dict(base)
    assert isinstance(e, Ellipse)
    back = primitive_from_dict(json.loads(json.dumps(e.to_dict())))
    assert back == e
    # 2D definition: normal defaults to +z
    e2 = primitive_from_dict({"type": "ellipse", "origin": [1, 2], "major_axis": [0, 3], "major_radius": 2, "minor_radius": 1})
    assert e2.normal == (0.0, 0.0, 1.0) and e2.major_axis == (0.0, 1.0, 0.0)
    pr = e2.project(np.array([[1.0, 2.0 + 5.0]]))
    assert np.allclose(pr.points, [[1.0, 4.0]]) and np.allclose(pr.distances, [3.0])
    bad = [
        ({"minor_radius": 3.0}, "minor_radius"),
        ({"minor_radius": 0.0}, "minor_radius"),
        ({"major_radius": float("inf")}, "major_radius"),
        ({"major_axis": [0, 0, 2]}, "major_axis"),
        ({"major_axis": [0, 0, 0]}, "major_axis"),
        ({"normal": [0, 0, 0]}, "normal"),
        ({"origin": [0, 0, "x"]}, "origin"),
    ]
    for change, field in bad:
        with pytest.raises(ValueError, match=field):
            primitive_from_dict({**base, **change})
    with pytest.raises(ValueError, match="z = 0"):
        primitive_from_dict({**base, "normal": [0, 1, 0]}).project(np.zeros((2, 2)))


def test_huge_and_tiny_coordinates():
    e = primitive_from_dict({"type": "ellipse", "origin": [0, 0, 0], "normal": [0, 0, 1], "major_axis": [1, 0, 0], "major_radius": 2.0, "minor_radius": 1.0})
    p = np.array([[1e200, 0, 0], [0, -1e200, 0], [3e150, 4e150, 1e150], [1e-200, 1e-200, 0], [5e-324, 0, 0], [0, 5e-324, 0]])
    with np.errstate(over="raise", invalid="raise", divide="raise"):  # (underflow is legitimate)
        pr = e.project(p)
    assert np.all(np.isfinite(pr.points)) and np.all(np.isfinite(pr.distances))
    assert np.allclose(np.linalg.norm(pr.normals, axis=1), 1.0, atol=1e-15)
    assert np.allclose(pr.points[:2], [[2, 0, 0], [0, -1, 0]])
    assert np.allclose(pr.distances[:2], [1e200 - 2, 1e200 - 1], rtol=1e-15)
    assert np.allclose(pr.distances[3:], -1.0) and np.allclose(np.abs(pr.points[3:, 1]), 1.0)


@pytest.mark.parametrize("height", [5e-324, 1e-310, 1e-200, 1e-120])
def test_points_a_hair_off_the_major_axis_inside_the_evolute(height):
    # make fuzz: (-1, 5e-324, 0) on the ellipse a = 2, b = 0.5 got the foot (-0.941, 0.441) at
    # 0.4451 instead of (-1.0667, 0.4230) at 0.4282 (Newton from a denormal height); the foot of a
    # point that close to the axis is the on-axis one (Eberly: x0 = a^2 x / (a^2 - b^2))
    from ibfem.geometry import primitive_from_dict

    e = primitive_from_dict({"type": "ellipse", "origin": [0, 0, 0], "normal": [0, 0, 1], "major_axis": [1, 0, 0],
                             "major_radius": 2.0, "minor_radius": 0.5})
    pr = e.project(np.array([[-1.0, height, 0.0], [-1.0, -height, 3.0]]))
    x0 = -1.0 * 4.0 / (4.0 - 0.25)
    y0 = 0.5 * np.sqrt(1.0 - (x0 / 2.0) ** 2)
    np.testing.assert_allclose(pr.points[:, 0], [x0, x0], rtol=1e-14)
    np.testing.assert_allclose(np.abs(pr.points[:, 1]), [y0, y0], rtol=1e-14)
    gap = np.linalg.norm(np.array([[-1.0, height, 0.0], [-1.0, -height, 3.0]]) - pr.points, axis=1)
    np.testing.assert_allclose(np.abs(pr.distances), gap, rtol=1e-14)
