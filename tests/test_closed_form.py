"""Closed-form primitives (line, circle, plane, sphere, cylinder, cone, torus): property tests
against independent references.

Every check below uses formulas written here, from the primitive's definition dict, never the
code under test: the implicit equation of the primitive (is the closest point on it?), dense
sampling of the primitive (is any sampled point closer?), offsetting a parametrised point along
its analytic normal (does it project back?), and hand-derived answers at degenerate points.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ibfem import geometry
from ibfem.geometry import primitive_from_dict

EPS = np.finfo(float).eps
SETTINGS = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])


# ---------------------------------------------------------------------------------------
# independent helpers
# ---------------------------------------------------------------------------------------


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def perp_frame(axis):
    """Any orthonormal (e1, e2) perpendicular to the unit axis (test's own construction)."""
    axis = unit(axis)
    trial = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = unit(trial - trial.dot(axis) * axis)
    return e1, np.cross(axis, e1)


def rows_dot(a, b):
    return np.einsum("ij,ij->i", a, b)


def norms(a):
    return np.linalg.norm(a, axis=1)


def brute_min_distance(pts, samples, chunk=16):
    """min_j |p_i - s_j| by exhaustive comparison (differences formed explicitly, so there is
    no cancellation for points close to a sample)."""
    out = np.empty(len(pts))
    for i in range(0, len(pts), chunk):
        diff = pts[i : i + chunk, None, :] - samples[None, :, :]
        out[i : i + chunk] = np.sqrt(np.einsum("ijk,ijk->ij", diff, diff).min(axis=1))
    return out


# strategies ----------------------------------------------------------------------------

coord = st.floats(-5.0, 5.0, allow_nan=False)
vec3 = st.tuples(coord, coord, coord)
direction = st.tuples(
    st.floats(-1, 1, allow_nan=False), st.floats(-1, 1, allow_nan=False), st.floats(-1, 1, allow_nan=False)
).filter(lambda v: math.sqrt(sum(x * x for x in v)) > 0.2)
length = st.floats(0.2, 5.0, allow_nan=False)
seed = st.integers(0, 2**32 - 1)


def line_dict(o, d):
    return {"type": "line", "origin": list(o), "direction": list(d)}


@st.composite
def primitives(draw, kind):
    o = list(draw(vec3))
    if kind == "line":
        return line_dict(o, draw(direction))
    if kind == "circle":
        return {"type": "circle", "origin": o, "normal": list(draw(direction)), "radius": draw(length)}
    if kind == "plane":
        return {"type": "plane", "origin": o, "normal": list(draw(direction))}
    if kind == "sphere":
        return {"type": "sphere", "origin": o, "radius": draw(length)}
    if kind == "cylinder":
        return {"type": "cylinder", "origin": o, "axis": list(draw(direction)), "radius": draw(length)}
    if kind == "cone":
        return {
            "type": "cone",
            "origin": o,
            "axis": list(draw(direction)),
            "radius": draw(st.one_of(st.just(0.0), st.floats(0.0, 4.0))),
            "half_angle": draw(st.floats(0.05, 1.5)),
        }
    if kind == "torus":
        R = draw(length)
        return {
            "type": "torus",
            "origin": o,
            "axis": list(draw(direction)),
            "major_radius": R,
            "minor_radius": R * draw(st.floats(0.05, 0.95)),
        }
    raise AssertionError(kind)


KINDS = ["line", "circle", "plane", "sphere", "cylinder", "cone", "torus"]


# ---------------------------------------------------------------------------------------
# per-primitive independent references: implicit residual, dense samples, scale
# ---------------------------------------------------------------------------------------


def residual(d, c):
    """Implicit-equation residual of points c (should be ~0 on the primitive)."""
    o = np.asarray(d["origin"], dtype=float)
    r = c - o
    kind = d["type"]
    if kind == "line":
        return norms(np.cross(r, unit(d["direction"])))
    if kind == "circle":
        n = unit(d["normal"])
        h = r @ n
        return np.abs(h) + np.abs(np.sqrt(np.maximum(rows_dot(r, r) - h * h, 0)) - d["radius"])
    if kind == "plane":
        return np.abs(r @ unit(d["normal"]))
    if kind == "sphere":
        return np.abs(norms(r) - d["radius"])
    if kind == "cylinder":
        return np.abs(norms(np.cross(r, unit(d["axis"]))) - d["radius"])
    if kind == "cone":
        a = unit(d["axis"])
        t = r @ a
        rho = norms(np.cross(r, a))
        radius_at = d["radius"] + t * math.tan(d["half_angle"])
        # on the cone's surface, and on the nappe that carries it (radius >= 0)
        return np.abs(rho - radius_at) * math.cos(d["half_angle"]) + np.maximum(-radius_at, 0.0)
    if kind == "torus":
        a = unit(d["axis"])
        h = r @ a
        rho = norms(np.cross(r, a))
        return np.abs(np.hypot(rho - d["major_radius"], h) - d["minor_radius"])
    raise AssertionError(kind)


def samples(d, pts, n=4000):
    """Dense samples of the primitive covering every point that could be closer to pts than
    the projection claims (for unbounded primitives: a window around the query points, wide
    enough because |p - X| >= |axial(p) - axial(X)|)."""
    o = np.asarray(d["origin"], dtype=float)
    kind = d["type"]
    reach = float(np.max(norms(pts - o))) + 1.0
    if kind == "line":
        dvec = unit(d["direction"])
        t = np.linspace(-reach * 2, reach * 2, 5 * n)
        return o + t[:, None] * dvec
    if kind == "circle":
        e1, e2 = perp_frame(d["normal"])
        th = np.linspace(0, 2 * np.pi, 2 * n, endpoint=False)
        return o + d["radius"] * (np.cos(th)[:, None] * e1 + np.sin(th)[:, None] * e2)
    if kind == "plane":
        e1, e2 = perp_frame(d["normal"])
        u = np.linspace(-2 * reach, 2 * reach, 160)
        U, V = np.meshgrid(u, u)
        return o + U.reshape(-1, 1) * e1 + V.reshape(-1, 1) * e2
    if kind == "sphere":
        k = np.arange(n * 3) + 0.5  # Fibonacci sphere
        z = 1 - 2 * k / (n * 3)
        phi = np.pi * (1 + 5**0.5) * k
        s = np.sqrt(1 - z * z)
        return o + d["radius"] * np.c_[s * np.cos(phi), s * np.sin(phi), z]
    if kind in ("cylinder", "cone", "torus"):
        a = unit(d["axis"])
        e1, e2 = perp_frame(a)
        th = np.linspace(0, 2 * np.pi, 120, endpoint=False)
        ring = np.cos(th)[:, None] * e1 + np.sin(th)[:, None] * e2
        if kind == "torus":
            phi = np.linspace(0, 2 * np.pi, 100, endpoint=False)
            rr = d["major_radius"] + d["minor_radius"] * np.cos(phi)
            hh = d["minor_radius"] * np.sin(phi)
            return o + (rr[:, None, None] * ring[None] + hh[:, None, None] * a).reshape(-1, 3)
        tp = (pts - o) @ a
        t = np.linspace(tp.min() - reach, tp.max() + reach, 160)
        if kind == "cylinder":
            rr = np.full_like(t, d["radius"])
        else:
            tan = math.tan(d["half_angle"])
            t_apex = -d["radius"] / tan
            t = np.unique(np.r_[t[t > t_apex], t_apex])  # the apex is a surface point
            rr = d["radius"] + t * tan
        return o + (rr[:, None, None] * ring[None] + t[:, None, None] * a).reshape(-1, 3)
    raise AssertionError(kind)


def query_points(d, rng, n=32):
    """Points near the primitive, far from it, and at its special places."""
    o = np.asarray(d["origin"], dtype=float)
    scale = max(d.get("radius", 1.0) or 1.0, d.get("major_radius", 1.0))
    pts = [o + rng.normal(size=(n, 3)) * scale * 1.5, o + rng.normal(size=(n // 4, 3)) * scale * 30]
    if "axis" in d or "normal" in d:
        a = unit(d.get("axis", d.get("normal")))
        pts.append(o + rng.uniform(-3, 3, (8, 1)) * scale * a)  # on the axis
    pts.append(o[None, :])
    return np.vstack(pts)


# ---------------------------------------------------------------------------------------
# property tests
# ---------------------------------------------------------------------------------------


def check_projection(d, pts, proj, curve_3d=False):
    o = np.asarray(d["origin"], dtype=float)
    scale = 1.0 + float(np.max(norms(pts - o)))
    tol = 64 * EPS * scale
    c, nrm, dist = proj.points, proj.normals, proj.distances
    assert c.shape == pts.shape and nrm.shape == pts.shape and dist.shape == (len(pts),)
    assert np.all(np.isfinite(c)) and np.all(np.isfinite(nrm)) and np.all(np.isfinite(dist))
    assert np.max(np.abs(norms(nrm) - 1)) < 1e-14
    # distances are signed Euclidean distances: |p - closest| with the sign of (p - closest) . normal
    assert np.max(np.abs(np.abs(dist) - norms(pts - c))) < tol
    along = rows_dot(pts - c, nrm)
    assert np.all(dist * along >= 0)
    assert np.all(np.abs(along) <= np.abs(dist) + tol)
    if not curve_3d:  # the foot is interior to a surface (or a curve's own plane): the two agree
        assert np.max(np.abs(along - dist)) < tol
    # the closest point is on the primitive
    assert np.max(residual(d, c)) < tol
    # p - closest is along the normal (curves in 3D: only the in-plane part, see curves.py)
    if not curve_3d:
        assert np.max(norms(pts - c - dist[:, None] * nrm)) < tol
    # no densely sampled point of the primitive is closer
    true = norms(pts - c)
    sampled = brute_min_distance(pts, samples(d, pts))
    assert np.all(true <= sampled + 1e-9 * scale), np.max(true - sampled)


@pytest.mark.parametrize("kind", KINDS)
@SETTINGS
@given(data=st.data(), rng_seed=seed)
def test_projection_properties(kind, data, rng_seed):
    d = data.draw(primitives(kind))
    prim = primitive_from_dict(d)
    pts = query_points(d, np.random.default_rng(rng_seed))
    proj = prim.project(pts)
    check_projection(d, pts, proj, curve_3d=kind == "circle")
    # circle in 3D: normal in the circle's plane, away from the centre
    if kind == "circle":
        n = unit(d["normal"])
        assert np.max(np.abs(proj.normals @ n)) < 1e-14
        radial = proj.points - np.asarray(d["origin"])
        assert np.all(rows_dot(radial, proj.normals) > 0)
    # deterministic: same input, same answer (twice in one batch and across calls)
    again = prim.project(np.vstack([pts[:5], pts[:5]]))
    assert np.array_equal(again.points[:5], again.points[5:])
    assert np.array_equal(again.points[:5], proj.points[:5])


def surface_points(d, rng, n=200):
    """(X, N, inward_limit): parametrised points of the primitive, their analytic unit normals,
    and for each the largest inward offset that still projects back to X."""
    o = np.asarray(d["origin"], dtype=float)
    kind = d["type"]
    if kind == "plane":
        e1, e2 = perp_frame(d["normal"])
        uv = rng.uniform(-5, 5, (n, 2))
        X = o + uv[:, :1] * e1 + uv[:, 1:] * e2
        return X, np.tile(unit(d["normal"]), (n, 1)), np.full(n, np.inf)
    if kind == "sphere":
        N = rng.normal(size=(n, 3))
        N /= norms(N)[:, None]
        return o + d["radius"] * N, N, np.full(n, d["radius"])
    a = unit(d["axis"])
    e1, e2 = perp_frame(a)
    th = rng.uniform(0, 2 * np.pi, n)
    u = np.cos(th)[:, None] * e1 + np.sin(th)[:, None] * e2
    if kind == "cylinder":
        t = rng.uniform(-5, 5, (n, 1))
        return o + t * a + d["radius"] * u, u, np.full(n, d["radius"])
    if kind == "cone":
        al = d["half_angle"]
        t_apex = -d["radius"] / math.tan(al)
        t = t_apex + rng.uniform(1e-3, 5, (n, 1))
        r = d["radius"] + t * math.tan(al)
        N = math.cos(al) * u - math.sin(al) * a
        return o + t * a + r * u, N, r[:, 0] / math.cos(al)  # inward: until the axis
    if kind == "torus":
        R, r = d["major_radius"], d["minor_radius"]
        phi = rng.uniform(0, 2 * np.pi, (n, 1))
        N = np.cos(phi) * u + np.sin(phi) * a
        return o + (R + r * np.cos(phi)) * u + r * np.sin(phi) * a, N, np.full(n, r)
    raise AssertionError(kind)


def outward_limit(d, X, N):
    """Largest outward offset that keeps the projection at X (torus: the axis is crossed)."""
    if d["type"] != "torus":
        return np.full(len(X), np.inf)
    a = unit(d["axis"])
    o = np.asarray(d["origin"], dtype=float)
    rho_dir = (X - o) - ((X - o) @ a)[:, None] * a
    rho = norms(rho_dir)
    toward_axis = -rows_dot(N, rho_dir / rho[:, None])
    with np.errstate(divide="ignore"):
        return np.where(toward_axis > 1e-3, rho / toward_axis, np.inf)


@pytest.mark.parametrize("kind", ["plane", "sphere", "cylinder", "cone", "torus"])
@SETTINGS
@given(data=st.data(), rng_seed=seed)
def test_offset_along_normal_projects_back(kind, data, rng_seed):
    d = data.draw(primitives(kind))
    rng = np.random.default_rng(rng_seed)
    X, N, inward = surface_points(d, rng)
    outward = outward_limit(d, X, N)
    frac = rng.uniform(-0.9, 0.9, len(X))
    delta = np.where(frac < 0, frac * np.minimum(inward, 10.0), frac * np.minimum(outward, 10.0))
    p = X + delta[:, None] * N
    proj = primitive_from_dict(d).project(p)
    scale = 1.0 + np.max(norms(p - np.asarray(d["origin"])))
    assert np.max(norms(proj.points - X)) < 200 * EPS * scale
    assert np.max(norms(proj.normals - N)) < 1e-12 * scale
    assert np.max(np.abs(proj.distances - delta)) < 200 * EPS * scale


@SETTINGS
@given(o=vec3, dvec=direction, rng_seed=seed)
def test_line_offset_and_2d_convention(o, dvec, rng_seed):
    rng = np.random.default_rng(rng_seed)
    d2 = np.array(dvec[:2])
    if np.linalg.norm(d2) < 0.1:
        d2 = np.array([1.0, 0.3])
    o2 = np.array(o[:2])
    line = primitive_from_dict(line_dict(o2, d2))
    t = rng.uniform(-10, 10, 100)
    delta = rng.uniform(-10, 10, 100)
    du = unit(d2)
    right = np.array([du[1], -du[0]])  # direction turned by -90 degrees
    p = o2 + t[:, None] * du + delta[:, None] * right
    proj = line.project(p)
    assert proj.points.shape == (100, 2) and proj.normals.shape == (100, 2)
    assert np.max(np.abs(proj.points - (o2 + t[:, None] * du))) < 1e-13
    assert np.max(np.abs(proj.normals - right)) == 0.0
    assert np.max(np.abs(proj.distances - delta)) < 1e-13
    assert np.max(np.abs(proj.parameters - t)) < 1e-13
    # 3D: distance is |p - closest|, normal from the line toward p
    line3 = primitive_from_dict(line_dict(o, dvec))
    a = unit(dvec)
    e1, e2 = perp_frame(a)
    w = rng.normal(size=(100, 2))
    off = w[:, :1] * e1 + w[:, 1:] * e2
    p3 = np.asarray(o) + t[:, None] * a + off
    pr = line3.project(p3)
    assert np.max(norms(pr.points - (np.asarray(o) + t[:, None] * a))) < 1e-13
    assert np.max(np.abs(pr.distances - norms(off))) < 1e-13
    assert np.max(norms(pr.normals - off / norms(off)[:, None])) < 1e-13


@SETTINGS
@given(o=st.tuples(coord, coord), R=length, rng_seed=seed, flip=st.booleans())
def test_circle_2d_offset_projects_back(o, R, rng_seed, flip):
    rng = np.random.default_rng(rng_seed)
    circle = primitive_from_dict({"type": "circle", "origin": list(o), "normal": [0, 0, -1.0 if flip else 1.0], "radius": R})
    th = rng.uniform(-np.pi, np.pi, 200)
    u = np.c_[np.cos(th), np.sin(th)]
    delta = rng.uniform(-0.9 * R, 10 * R, 200)
    p = np.asarray(o) + (R + delta)[:, None] * u
    proj = circle.project(p)
    assert proj.points.shape == (200, 2)
    assert np.max(norms(proj.points - (np.asarray(o) + R * u))) < 1e-13 * (1 + R)
    # the direction from the centre is known to eps |p| / |p - centre| after rounding p
    assert np.all(norms(proj.normals - u) < 8 * EPS * (1 + norms(p)) / (R + delta))
    assert np.max(np.abs(proj.distances - delta)) < 1e-13 * (1 + R)
    expected_angle = -th if flip else th  # the frame's e2 is -y for normal -z
    assert np.max(np.abs(np.angle(np.exp(1j * (proj.parameters - expected_angle))))) < 1e-12


# ---------------------------------------------------------------------------------------
# degenerate points
# ---------------------------------------------------------------------------------------


def test_sphere_centre():
    s = primitive_from_dict({"type": "sphere", "origin": [1, 2, 3], "radius": 2.0})
    pr = s.project(np.array([[1.0, 2, 3], [1.0, 2, 3]]))
    assert np.allclose(pr.distances, -2.0, rtol=0, atol=1e-15)
    assert np.allclose(norms(pr.points - [1, 2, 3]), 2.0, atol=1e-15)
    assert np.allclose(norms(pr.normals), 1.0, atol=1e-15)
    assert np.array_equal(pr.points[0], pr.points[1])
    assert np.allclose(pr.points[0] - [1, 2, 3], 2.0 * pr.normals[0], atol=1e-15)


def test_cylinder_axis_points():
    a = unit([1, 2, 2])
    cyl = primitive_from_dict({"type": "cylinder", "origin": [0, 1, 0], "axis": list(a), "radius": 0.5})
    t = np.linspace(-3, 3, 7)
    p = np.array([0, 1, 0]) + t[:, None] * a
    pr = cyl.project(p)
    assert np.allclose(pr.distances, -0.5, atol=1e-15)
    assert np.max(np.abs(pr.normals @ a)) < 1e-15
    assert np.allclose(norms(pr.normals), 1.0, atol=1e-15)
    assert np.allclose(norms(pr.points - p), 0.5, atol=1e-14)
    assert np.max(residual(cyl.to_dict(), pr.points)) < 1e-14
    # exactly on the axis (local coordinates 0): the fixed meridian, whatever the height
    cyl = primitive_from_dict({"type": "cylinder", "origin": [0, 0, 0], "axis": [0, 0, 1], "radius": 0.5})
    pr = cyl.project(np.c_[0 * t, 0 * t, t])
    assert np.allclose(pr.normals, pr.normals[0], rtol=0, atol=0)


def test_torus_axis_and_core_circle():
    d = {"type": "torus", "origin": [0.5, 0, -1], "axis": [0, 0, 1], "major_radius": 2.0, "minor_radius": 0.5}
    tor = primitive_from_dict(d)
    h = np.array([-3.0, -0.2, 0.0, 0.7, 4.0])
    p_axis = np.array([0.5, 0, -1]) + h[:, None] * np.array([0, 0, 1.0])
    pr = tor.project(p_axis)
    assert np.allclose(pr.distances, np.hypot(2.0, h) - 0.5, rtol=1e-15, atol=1e-15)
    assert np.allclose(norms(pr.points - p_axis), np.hypot(2.0, h) - 0.5, rtol=1e-15)
    assert np.max(residual(d, pr.points)) < 1e-14
    check_projection(d, p_axis, pr)
    th = np.linspace(0, 2 * np.pi, 9)
    core = np.array([0.5, 0, -1]) + 2.0 * np.c_[np.cos(th), np.sin(th), 0 * th]
    pr = tor.project(core)
    assert np.allclose(pr.distances, -0.5, atol=1e-15)
    assert np.allclose(norms(pr.points - core), 0.5, atol=1e-15)
    assert np.allclose(norms(pr.normals), 1.0, atol=1e-15)
    assert np.max(residual(d, pr.points)) < 1e-14


def test_circle_centre_and_line_points():
    c = primitive_from_dict({"type": "circle", "origin": [1, 1, 1], "normal": [1, 1, 0], "radius": 3.0})
    pr = c.project(np.array([[1.0, 1, 1], [1.0, 1, 1]]))
    assert np.allclose(pr.distances, -3.0, atol=1e-15)
    assert np.max(np.abs(pr.normals @ unit([1, 1, 0]))) < 1e-15
    assert np.allclose(norms(pr.points - [1, 1, 1]), 3.0, atol=1e-14)
    line = primitive_from_dict(line_dict([0, 0, 0], [0, 0, 2]))
    p = np.array([[0, 0, -1.0], [0, 0, 0], [0, 0, 5]])
    pr = line.project(p)
    assert np.array_equal(pr.points, p) and np.array_equal(pr.distances, np.zeros(3))
    assert np.allclose(norms(pr.normals), 1.0) and np.max(np.abs(pr.normals[:, 2])) == 0.0
    assert np.allclose(pr.parameters, [-1, 0, 5])


@pytest.mark.parametrize("radius", [0.0, 1.5])
@pytest.mark.parametrize("half_angle", [0.1, 0.7, 1.4])
def test_cone_apex_region(radius, half_angle):
    a = unit([0, 1, 1])
    o = np.array([1.0, -1.0, 2.0])
    d = {"type": "cone", "origin": list(o), "axis": list(a), "radius": radius, "half_angle": half_angle}
    cone = primitive_from_dict(d)
    t_apex = -radius / math.tan(half_angle)
    apex = o + t_apex * a
    e1, e2 = perp_frame(a)
    # the apex itself
    pr = cone.project(apex[None, :])
    assert np.allclose(pr.points[0], apex, atol=1e-14) and abs(pr.distances[0]) < 1e-14
    assert abs(np.linalg.norm(pr.normals[0]) - 1) < 1e-15
    # behind the apex, inside the apex's normal cone: the apex is closest, distance |p - apex|
    rng = np.random.default_rng(3)
    s = rng.uniform(0.01, 5, 50)
    ang = rng.uniform(0, 2 * np.pi, 50)
    # directions from the apex making an angle > half_angle + 90 degrees with the axis
    beta = rng.uniform(half_angle + np.pi / 2, np.pi, 50)
    dirs = np.cos(beta)[:, None] * a + np.sin(beta)[:, None] * (np.cos(ang)[:, None] * e1 + np.sin(ang)[:, None] * e2)
    p = apex + s[:, None] * dirs
    pr = cone.project(p)
    assert np.max(norms(pr.points - apex)) < 1e-13
    assert np.allclose(pr.distances, s, rtol=1e-14)
    assert np.max(norms(pr.normals - dirs)) < 1e-13
    check_projection(d, p, pr)
    # on the axis in front of the apex: distance (t - t_apex) sin(half_angle) inside
    t = t_apex + np.array([1e-9, 0.3, 2.0, 7.0])
    p = o + t[:, None] * a
    pr = cone.project(p)
    assert np.allclose(pr.distances, -(t - t_apex) * math.sin(half_angle), rtol=1e-13, atol=1e-15)
    check_projection(d, p, pr)
    # just off the apex along the axis behind it: distance to the apex
    p = apex - np.array([1e-12, 1e-3, 1.0])[:, None] * a
    pr = cone.project(p)
    assert np.allclose(pr.distances, [1e-12, 1e-3, 1.0], rtol=1e-12)
    # (the direction of a 1e-12 offset is only known to eps |apex| / 1e-12 after rounding p)
    assert np.max(norms(pr.normals[1:] + a)) < 1e-11
    assert abs(np.linalg.norm(pr.normals[0]) - 1) < 1e-15


# ---------------------------------------------------------------------------------------
# definitions: validation and round trip
# ---------------------------------------------------------------------------------------


INVALID = [
    ({"type": "line", "origin": [0, 0, 0], "direction": [0, 0, 0]}, "direction"),
    ({"type": "line", "origin": [0, 0], "direction": [1, "a"]}, "direction"),
    ({"type": "line", "origin": [0, 0, 0, 1], "direction": [1, 0, 0]}, "origin"),
    ({"type": "line", "direction": [1, 0, 0]}, "origin"),
    ({"type": "circle", "origin": [0, 0, 0], "normal": [0, 0, 1], "radius": -1}, "radius"),
    ({"type": "circle", "origin": [0, 0, 0], "normal": [0, 0, 1], "radius": float("nan")}, "radius"),
    ({"type": "circle", "origin": [0, 0, 0], "normal": [0, 0, 0], "radius": 1}, "normal"),
    ({"type": "circle", "origin": [0, float("inf"), 0], "normal": [0, 0, 1], "radius": 1}, "origin"),
    ({"type": "circle", "origin": [0, 0, 0], "normal": [0, 0, 1], "radius": 1, "radious": 2}, "radious"),
    ({"type": "plane", "origin": [0, 0, 0], "normal": [0, 0, 0]}, "normal"),
    ({"type": "plane", "origin": [0, 0], "normal": [0, 0, 1]}, "origin"),
    ({"type": "sphere", "origin": [0, 0, 0], "radius": 0}, "radius"),
    ({"type": "sphere", "origin": [0, 0, 0]}, "radius"),
    ({"type": "cylinder", "origin": [0, 0, 0], "axis": [0, 0, 0], "radius": 1}, "axis"),
    ({"type": "cylinder", "origin": [0, 0, 0], "axis": [0, 0, 1], "radius": "big"}, "radius"),
    ({"type": "cone", "origin": [0, 0, 0], "axis": [0, 0, 1], "radius": -0.1, "half_angle": 0.3}, "radius"),
    ({"type": "cone", "origin": [0, 0, 0], "axis": [0, 0, 1], "radius": 1, "half_angle": 0.0}, "half_angle"),
    ({"type": "cone", "origin": [0, 0, 0], "axis": [0, 0, 1], "radius": 1, "half_angle": math.pi / 2}, "half_angle"),
    ({"type": "cone", "origin": [0, 0, 0], "axis": [0, 0, 1], "radius": 1, "half_angle": -0.5}, "half_angle"),
    ({"type": "torus", "origin": [0, 0, 0], "axis": [0, 0, 1], "major_radius": 1, "minor_radius": 2}, "minor_radius"),
    ({"type": "torus", "origin": [0, 0, 0], "axis": [0, 0, 1], "major_radius": -1, "minor_radius": 0.5}, "major_radius"),
    ({"type": "torus", "origin": [0, 0, 0], "axis": [0, 0, 1], "major_radius": 1, "minor_radius": 0}, "minor_radius"),
]


@pytest.mark.parametrize("d,field", INVALID)
def test_invalid_definitions_name_the_field(d, field):
    with pytest.raises(ValueError, match=field):
        primitive_from_dict(d)


def test_bad_query_points_and_2d_rules():
    sphere = primitive_from_dict({"type": "sphere", "origin": [0, 0, 0], "radius": 1})
    with pytest.raises(ValueError, match="points"):
        sphere.project(np.zeros((4, 2)))  # surfaces need 3D points
    with pytest.raises(ValueError, match="points"):
        sphere.project([["a", "b", "c"]])
    tilted = primitive_from_dict({"type": "circle", "origin": [0, 0, 0], "normal": [1, 0, 0], "radius": 1})
    with pytest.raises(ValueError, match="z = 0"):
        tilted.project(np.zeros((3, 2)))
    with pytest.raises(ValueError, match="z = 0"):
        primitive_from_dict(line_dict([0, 0, 1], [1, 0, 0])).project(np.zeros((3, 2)))
    # a single point is accepted
    assert primitive_from_dict({"type": "plane", "origin": [0, 0, 0], "normal": [0, 0, 1]}).project([1, 2, 3]).distances[0] == 3


@pytest.mark.parametrize("kind", KINDS)
@settings(max_examples=15, deadline=None)
@given(data=st.data())
def test_round_trip_through_json(kind, data):
    d = data.draw(primitives(kind))
    prim = primitive_from_dict(d)
    assert prim.type == kind and isinstance(prim, geometry.Primitive)
    out = prim.to_dict()
    back = primitive_from_dict(json.loads(json.dumps(out)))
    assert type(back) is type(prim)
    again = back.to_dict()
    assert again.keys() == out.keys()
    for key, value in out.items():
        if isinstance(value, list):
            assert np.allclose(again[key], value, rtol=0, atol=4 * EPS)
        else:
            assert again[key] == value
    p = np.random.default_rng(0).normal(size=(20, 3)) * 3
    assert np.allclose(back.project(p).distances, prim.project(p).distances, rtol=0, atol=1e-13)
    # unit vectors are normalised on input
    for key in ("direction", "normal", "axis"):
        if key in out:
            assert abs(np.linalg.norm(out[key]) - 1) < 4 * EPS


@pytest.mark.parametrize("kind", KINDS)
def test_huge_and_tiny_coordinates(kind):
    """Squares of 1e200 overflow and of 1e-200 underflow: answers stay finite and exact."""
    d = {
        "line": line_dict([0, 0, 0], [1, 2, 2]),
        "circle": {"type": "circle", "origin": [0, 0, 0], "normal": [0, 0, 1], "radius": 1.0},
        "plane": {"type": "plane", "origin": [0, 0, 0], "normal": [0, 0, 1]},
        "sphere": {"type": "sphere", "origin": [0, 0, 0], "radius": 1.0},
        "cylinder": {"type": "cylinder", "origin": [0, 0, 0], "axis": [0, 0, 1], "radius": 1.0},
        "cone": {"type": "cone", "origin": [0, 0, 0], "axis": [0, 0, 1], "radius": 1.0, "half_angle": 0.4},
        "torus": {"type": "torus", "origin": [0, 0, 0], "axis": [0, 0, 1], "major_radius": 1.0, "minor_radius": 0.5},
    }[kind]
    prim = primitive_from_dict(d)
    direction = unit([3.0, 4.0, 0.0])
    p = np.array([1e200 * direction, 1e-200 * direction, 5e-324 * np.array([1.0, 1.0, 0.0])])
    with np.errstate(over="raise", invalid="raise", divide="raise"):  # (underflow is legitimate)
        pr = prim.project(p)
    assert np.all(np.isfinite(pr.points)) and np.all(np.isfinite(pr.distances))
    assert np.allclose(norms(pr.normals), 1.0, rtol=0, atol=1e-15)
    if kind in ("circle", "sphere", "cylinder"):
        # radial direction kept exactly, even for denormal coordinates
        assert np.allclose(pr.normals[:2], direction, atol=1e-15)
        assert np.allclose(pr.normals[2], unit([1.0, 1.0, 0.0]), atol=1e-15)
        assert np.allclose(pr.distances, [1e200 - 1.0, -1.0, -1.0], rtol=1e-15)


def evaluate_at_parameters(d, params):
    """The documented parametrisations (frames from geometry._base.orthonormal_frame)."""
    from ibfem.geometry._base import orthonormal_frame

    o = np.asarray(d["origin"], dtype=float)
    kind = d["type"]
    if kind == "line":
        return o + params[:, None] * unit(d["direction"])
    if kind == "circle":
        e1, e2 = orthonormal_frame(unit(d["normal"]))
        return o + d["radius"] * (np.cos(params)[:, None] * e1 + np.sin(params)[:, None] * e2)
    if kind == "plane":
        e1, e2 = orthonormal_frame(unit(d["normal"]))
        return o + params[:, :1] * e1 + params[:, 1:] * e2
    if kind == "sphere":
        u, v = params[:, 0], params[:, 1]
        return o + d["radius"] * np.c_[np.cos(v) * np.cos(u), np.cos(v) * np.sin(u), np.sin(v)]
    a = unit(d["axis"])
    e1, e2 = orthonormal_frame(a)
    th = params[:, 0]
    ring = np.cos(th)[:, None] * e1 + np.sin(th)[:, None] * e2
    if kind == "cylinder":
        return o + params[:, 1:] * a + d["radius"] * ring
    if kind == "cone":
        t = params[:, 1:]
        return o + t * a + (d["radius"] + t * math.tan(d["half_angle"])) * ring
    if kind == "torus":
        phi = params[:, 1:]
        return o + (d["major_radius"] + d["minor_radius"] * np.cos(phi)) * ring + d["minor_radius"] * np.sin(phi) * a
    raise AssertionError(kind)


@pytest.mark.parametrize("kind", KINDS)
@settings(max_examples=15, deadline=None)
@given(data=st.data(), rng_seed=seed)
def test_parameters_reproduce_the_closest_points(kind, data, rng_seed):
    d = data.draw(primitives(kind))
    pts = query_points(d, np.random.default_rng(rng_seed))
    pr = primitive_from_dict(d).project(pts)
    expected_shape = (len(pts),) if kind in ("line", "circle") else (len(pts), 2)
    assert pr.parameters.shape == expected_shape
    scale = 1.0 + np.max(norms(pts - np.asarray(d["origin"])))
    assert np.max(norms(evaluate_at_parameters(d, pr.parameters) - pr.points)) < 1e-13 * scale
