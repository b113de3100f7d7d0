"""Signed Euclidean distances for every primitive:
``|distances| == |p - closest|`` to round-off, with the sign of ``(p - closest) . normal``,
checked against dense samples of each primitive (an independent brute force), on random
points including points off the plane of 3D circles and ellipses, beyond the ends of open
B-spline curves and beyond the edges and corners of B-spline patches; on the numpy path
and on the compiled one (``IBFEM_NO_JIT``). Also the input checks: unknown fields of B-spline curves, surfaces and sweeps, and query arrays that are
not real numbers."""

import functools
import math

import numpy as np
import pytest

from ibfem.geometry import _jit, primitive_from_dict

@pytest.fixture(params=[False, True], ids=["numpy", "compiled"])
def path(request, monkeypatch):
    """Runs a test on the numpy path and on the compiled kernels (skipped without numba)."""
    if request.param and not _jit.enabled():
        pytest.skip("numba not installed")
    monkeypatch.setenv("IBFEM_NO_JIT", "" if request.param else "1")
    return request.param


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def frame(n):
    n = unit(n)
    e1 = unit(np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0]))
    return e1, np.cross(n, e1), n


AX = list(unit([1.0, 2.0, 2.0]))
E1, E2, _ = frame(AX)
O = [0.3, -0.2, 0.1]


def _bspline_surface_def(weights=False):
    nu = nv = 6
    k = 3
    U, V = np.meshgrid(np.linspace(0, 1, nu), np.linspace(0, 1, nv), indexing="ij")
    cp = np.stack([2 * U, 2 * V, 0.3 * np.sin(3 * U) * np.cos(2 * V)], axis=-1)
    knots = [0.0] * (k + 1) + list(np.linspace(0, 1, nu - k + 1)[1:-1]) + [1.0] * (k + 1)
    d = {"type": "bspline_surface", "degree_u": k, "degree_v": k, "knots_u": knots, "knots_v": knots,
         "control_points": cp.tolist()}
    if weights:
        d["weights"] = (1.0 + 0.8 * np.cos(5 * U + 2 * V) ** 2).tolist()
    return d


def _bspline_curve_def(planar=False):
    cp = np.array([[0, 0, 0], [1, 1, 0.2], [2, -0.5, 0.4], [3, 0.8, -0.3], [4, 0, 0.5], [5, 1, 0], [6, 0, 0.2]], float)
    if planar:
        cp[:, 2] = 0.0
    k = 3
    inner = list(np.linspace(0, 1, len(cp) - k + 1)[1:-1])
    return {"type": "bspline_curve", "degree": k, "knots": [0.0] * (k + 1) + inner + [1.0] * (k + 1),
            "control_points": cp.tolist()}


DEFS = {
    "line": {"type": "line", "origin": O, "direction": AX},
    "circle": {"type": "circle", "origin": O, "normal": AX, "radius": 1.0},
    "ellipse": {"type": "ellipse", "origin": O, "normal": AX, "major_axis": list(E1), "major_radius": 1.0,
                "minor_radius": 0.4},
    "plane": {"type": "plane", "origin": O, "normal": AX},
    "sphere": {"type": "sphere", "origin": O, "radius": 1.0},
    "cylinder": {"type": "cylinder", "origin": O, "axis": AX, "radius": 1.0},
    "cone": {"type": "cone", "origin": O, "axis": AX, "radius": 0.5, "half_angle": 0.5},
    "torus": {"type": "torus", "origin": O, "axis": AX, "major_radius": 1.0, "minor_radius": 0.3},
    "bspline_curve": _bspline_curve_def(),
    "bspline_surface": _bspline_surface_def(),
    "nurbs_surface": _bspline_surface_def(weights=True),
    "sweep": {"type": "sweep", "profile": _bspline_curve_def(planar=True), "direction": [0.0, 0.4, 1.0]},
    "sweep_ellipse": {"type": "sweep", "direction": [0.0, 0.3, 1.0],
                      "profile": {"type": "ellipse", "origin": [0, 0, 0], "normal": [0, 0, 1], "major_axis": [1, 0, 0],
                                  "major_radius": 1.0, "minor_radius": 0.6}},
}


def samples(name, prim, p):
    """Dense points of the primitive (unbounded ones over a window wider than any query's reach)."""
    d = DEFS[name]
    reach = float(np.max(np.linalg.norm(p, axis=1))) + 4.0
    if name in ("bspline_curve",):
        return prim.evaluate(np.linspace(0, 1, 400001))
    if name in ("bspline_surface", "nurbs_surface"):
        u = np.linspace(0, 1, 801)
        U, V = np.meshgrid(u, u, indexing="ij")
        return prim.evaluate(np.column_stack([U.ravel(), V.ravel()]))
    if name.startswith("sweep"):
        # |p - (C(t) + h d)| is smallest at h = (p - C(t)) . d: the distance is the one between
        # p and the profile's samples both flattened along d (the primitive's Sweep.evaluate
        # is not used: the profile is sampled from its own primitive)
        t = np.linspace(0, 1, 400001) if name == "sweep" else np.linspace(-np.pi, np.pi, 400000, endpoint=False)
        prof = primitive_from_dict(d["profile"])
        X = prof.evaluate(t) if name == "sweep" else _ellipse_points(d["profile"], t)
        X = np.column_stack([X, np.zeros(len(X))]) if X.shape[1] == 2 else X
        dd = unit(d["direction"])
        return X - np.outer(X @ dd, dd), dd
    o = np.asarray(d["origin"], float)
    if name == "line":  # along the line from the nearest to the farthest foot
        t = (p - o) @ unit(AX)
        return o + np.linspace(t.min() - 1, t.max() + 1, 400001)[:, None] * unit(AX)
    if name in ("circle", "ellipse"):
        th = np.linspace(-np.pi, np.pi, 400000, endpoint=False)
        a, b = (1.0, 1.0) if name == "circle" else (1.0, 0.4)
        e1, e2 = (prim._frame[0], prim._frame[1])  # the primitive's own in-plane axes
        return o + a * np.cos(th)[:, None] * e1 + b * np.sin(th)[:, None] * e2
    if name == "plane":
        u = np.linspace(-reach, reach, 1501)
        U, V = np.meshgrid(u, u)
        return o + U.reshape(-1, 1) * E1 + V.reshape(-1, 1) * E2
    if name == "sphere":
        m = 600000
        k = np.arange(m) + 0.5
        z = 1 - 2 * k / m
        phi = math.pi * (1 + 5**0.5) * k
        s = np.sqrt(1 - z * z)
        return o + np.c_[s * np.cos(phi), s * np.sin(phi), z]
    a = unit(AX)
    th = np.linspace(0, 2 * np.pi, 1440, endpoint=False)
    ring = np.cos(th)[:, None] * E1 + np.sin(th)[:, None] * E2
    if name == "torus":
        ph = np.linspace(0, 2 * np.pi, 720, endpoint=False)
        rr, hh = 1.0 + 0.3 * np.cos(ph), 0.3 * np.sin(ph)
    else:
        t = np.linspace(-reach, reach, 1200)
        if name == "cone":
            t_apex = -0.5 / math.tan(0.5)
            t = np.unique(np.r_[t[t > t_apex], t_apex])
            rr = 0.5 + t * math.tan(0.5)
        else:
            rr = np.ones_like(t)
        hh = t
    return o + (rr[:, None, None] * ring[None] + hh[:, None, None] * a).reshape(-1, 3)


def _ellipse_points(d, th):
    n = unit(d["normal"])
    e1 = unit(np.asarray(d["major_axis"], float) - np.dot(d["major_axis"], n) * n)
    e2 = np.cross(n, e1)
    return np.asarray(d["origin"], float) + d["major_radius"] * np.cos(th)[:, None] * e1 + \
        d["minor_radius"] * np.sin(th)[:, None] * e2


@functools.lru_cache(maxsize=None)
def _tree(name):
    """The k-d tree of the samples of DEFS[name] (built once for both paths: the queries
    are the same)."""
    from scipy.spatial import cKDTree

    prim = primitive_from_dict(DEFS[name])
    X = samples(name, prim, queries(name, prim))
    if isinstance(X, tuple):  # sweep: flattened profile samples and the direction
        return cKDTree(X[0]), X[1]
    return cKDTree(X), None


def nearest_sample(name, p):
    tree, dd = _tree(name)
    if dd is not None:
        p = p - np.outer(p @ dd, dd)
    return tree.query(p)[0]


def queries(name, prim):
    """Random points around the primitive, plus the places where the dot product and the
    Euclidean distance differ: off the plane of a 3D curve, beyond B-spline ends, edges and
    corners."""
    rng = np.random.default_rng(sorted(DEFS).index(name))  # the same points on both paths
    o = np.asarray(DEFS[name].get("origin", [1.0, 1.0, 0.0]), float)
    p = [o + rng.normal(size=(150, 3)) * 1.5]
    if name in ("circle", "ellipse"):
        e1, e2, n = prim._frame
        h = rng.uniform(-4, 4, 60)
        th = rng.uniform(-np.pi, np.pi, 60)
        r = rng.uniform(0, 2, 60)
        p.append(o + (r * np.cos(th))[:, None] * e1 + (r * np.sin(th))[:, None] * e2 + h[:, None] * n)
    if name in ("bspline_surface", "nurbs_surface"):
        g = rng.uniform(-1.5, 3.5, (200, 2))  # the patch covers about [0, 2]^2 in x, y
        p.append(np.column_stack([g, rng.uniform(-1.5, 1.5, 200)]))
        corners = np.array([[0, 0], [2, 0], [0, 2], [2, 2]], float)
        out = corners[rng.integers(0, 4, 80)] + np.sign(corners[rng.integers(0, 4, 80)] - 1) * rng.uniform(0.1, 2, (80, 2))
        p.append(np.column_stack([out, rng.uniform(-1, 1, 80)]))
    if name in ("bspline_curve", "sweep"):
        p.append(np.array([-1.0, 0.0, 0.0]) + rng.normal(size=(60, 3)))  # beyond the start
        p.append(np.array([7.0, 0.0, 0.0]) + rng.normal(size=(60, 3)))  # beyond the end
    return np.vstack(p)


@pytest.mark.parametrize("name", list(DEFS))
def test_distances_are_signed_euclidean_against_brute_force(name, path):
    prim = primitive_from_dict(DEFS[name])
    p = queries(name, prim)
    pr = prim.project(p)
    r = p - pr.points
    length = np.linalg.norm(r, axis=1)
    scale = 1.0 + np.linalg.norm(p, axis=1)
    # |distance| == |p - closest| to round-off, sign of (p - closest) . normal
    assert np.max(np.abs(np.abs(pr.distances) - length) / scale) < 1e-14
    along = np.einsum("ij,ij->i", r, pr.normals)
    assert np.all(pr.distances * along >= 0)
    assert np.allclose(np.linalg.norm(pr.normals, axis=1), 1.0, rtol=0, atol=1e-14)
    # against dense samples of the primitive: no sample closer, and none farther than the
    # sampling allows (half the largest spacing of the samples, 0.02 along the axis of the
    # cylinder and cone windows)
    brute = nearest_sample(name, p)
    assert np.all(np.abs(pr.distances) <= brute + 1e-12 * scale)
    assert np.max(brute - np.abs(pr.distances)) < 1.2e-2


def test_issue_reproducers_off_plane_and_beyond_corner(path):
    """A point 3.5 above a circle's plane (reported 0.18 before) and points beyond a patch's
    edges (3.71 for 3.73, 4.64 for 5.32 in the issue's measurements)."""
    c = primitive_from_dict({"type": "circle", "origin": [0, 0, 0], "normal": [0, 0, 1], "radius": 1.0})
    pr = c.project([[1.18, 0.0, 3.5], [0.5, 0.0, -2.0], [1.0, 0.0, 3.0]])
    assert np.allclose(pr.distances, [math.hypot(0.18, 3.5), -math.hypot(0.5, 2.0), 3.0], rtol=1e-15, atol=0)
    e = primitive_from_dict({"type": "ellipse", "origin": [0, 0, 0], "normal": [0, 0, 1], "major_axis": [1, 0, 0],
                             "major_radius": 2.0, "minor_radius": 1.0})
    pr = e.project([[2.5, 0.0, 1.2], [0.0, 0.5, -3.0]])
    assert np.allclose(pr.distances, [math.hypot(0.5, 1.2), -math.hypot(0.5, 3.0)], rtol=1e-15, atol=0)
    # a flat bilinear patch [0, 1]^2 in z = 0: beyond its corner the distance is to the corner
    s = primitive_from_dict({"type": "bspline_surface", "degree_u": 1, "degree_v": 1, "knots_u": [0, 0, 1, 1],
                             "knots_v": [0, 0, 1, 1], "control_points": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 0]]]})
    p = np.array([[2.0, 3.0, 1.0], [-1.0, 0.5, -2.0], [0.5, 0.5, 0.25]])
    pr = s.project(p)
    assert np.allclose(pr.points, [[1, 1, 0], [0, 0.5, 0], [0.5, 0.5, 0]], atol=1e-14)
    assert np.allclose(pr.distances, [math.sqrt(6.0), -math.sqrt(5.0), 0.25], rtol=1e-14, atol=0)


# ---------------------------------------------------------------------------------------
# input checks
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["bspline_curve", "bspline_surface", "sweep"])
def test_free_form_primitives_reject_unknown_fields(name):
    d = dict(DEFS[name])
    d["weigths"] = [1.0] * 7
    with pytest.raises(ValueError, match=f"{name}: unknown field 'weigths'"):
        primitive_from_dict(d)


def test_quarter_circle_with_misspelt_weights_is_rejected():
    """The reproducer: ``weigths`` silently turned an exact quarter circle into another curve."""
    d = {"type": "bspline_curve", "degree": 2, "knots": [0, 0, 0, 1, 1, 1], "control_points": [[1, 0], [1, 1], [0, 1]],
         "weigths": [1.0, math.sqrt(0.5), 1.0]}
    with pytest.raises(ValueError, match="unknown field 'weigths'"):
        primitive_from_dict(d)
    d["weights"] = d.pop("weigths")
    pr = primitive_from_dict(d).project([[2.0, 2.0]])
    assert np.allclose(pr.distances, [math.sqrt(8.0) - 1.0], rtol=1e-13)


@pytest.mark.parametrize("name", ["line", "circle", "ellipse", "sphere", "torus", "bspline_curve", "bspline_surface",
                                  "sweep_ellipse"])
@pytest.mark.parametrize(
    "bad, word",
    [
        (np.ones((3, 3), dtype=bool), "booleans"),
        (np.ones((3, 3), dtype=complex), "complex"),
        (np.array([[1.0, 2.0, None]], dtype=object), "objects"),
        (np.array([["1", "2", "3"]]), "strings"),
        ([[1.0, 2.0, 3.0], [1.0, 2.0]], "ragged"),
    ],
)
def test_project_rejects_arrays_that_are_not_real_numbers(name, bad, word):
    prim = primitive_from_dict(DEFS[name])
    with pytest.raises(ValueError, match=f"points must be an array of real numbers.*{word}"):
        prim.project(bad)


@pytest.mark.parametrize("name", ["line", "circle", "sphere", "bspline_curve", "bspline_surface"])
def test_project_accepts_integer_arrays(name):
    prim = primitive_from_dict(DEFS[name])
    ints = np.array([[1, 2, 3], [0, -1, 2]], dtype=np.int32)
    assert np.array_equal(prim.project(ints).points, prim.project(ints.astype(float)).points)
