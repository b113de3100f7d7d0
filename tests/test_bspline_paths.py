"""The B-spline projection's two implementations (compiled kernel, numpy path)
against a dense brute force and against each other, on the harsh random cases of
benchmarks/bspline_stress.py (clustered knots, weights 0.2-5, points 1 %-100 % of the size
away), including the cases that once missed (rational curves with a sharp turn)."""

import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import bspline_stress  # noqa: E402

from ibfem.geometry import _jit  # noqa: E402
from ibfem.geometry.bspline import BSplineSurface  # noqa: E402


@pytest.fixture(params=[False, True], ids=["numpy", "compiled"])
def jit(request, monkeypatch):
    """Runs a test on the numpy path and on the compiled kernels (skipped without numba)."""
    if request.param and not _jit.enabled():
        pytest.skip("numba not installed")
    monkeypatch.setenv("IBFEM_NO_JIT", "" if request.param else "1")
    return request.param


def _cases(seed, count, points):
    rng = np.random.default_rng(seed)
    return [bspline_stress.curve_case(rng, points) for _ in range(count)]


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_curve_projection_finds_the_global_minimum(seed, jit):
    for c, X, p in _cases(seed, 6, 400):
        pr = c.project(p)
        got = np.linalg.norm(p - pr.points, axis=1)
        brute = cKDTree(X).query(p)[0]
        assert np.all(got <= brute + 1e-12 * c.scale)
        # the returned points lie on the curve at the returned parameters
        assert np.allclose(c.evaluate(pr.parameters), pr.points, atol=1e-13 * c.scale, rtol=0)


def test_compiled_and_numpy_paths_agree(monkeypatch):
    if not _jit.enabled():
        pytest.skip("numba not installed")
    for c, X, p in _cases(4, 5, 300):
        monkeypatch.setenv("IBFEM_NO_JIT", "")
        a = c.project(p)
        monkeypatch.setenv("IBFEM_NO_JIT", "1")
        b = c.project(p)
        assert np.allclose(a.distances, b.distances, atol=1e-12 * c.scale, rtol=0)
        assert np.allclose(a.points, b.points, atol=1e-9 * c.scale, rtol=0)


def test_sharp_turn_of_a_rational_curve_is_split_into_cells():
    """Weights 0.2-5 put a sharp turn into a short stretch of parameter: the cells there
    are halved until the tangent turns by at most 40 degrees over each."""
    c, _, _ = _cases(3, 16, 10)[15]
    edges = c._pieces[0]
    net = c._tangent_nets(edges)
    u = net / np.linalg.norm(net, axis=2, keepdims=True)
    axis = u.sum(axis=1)
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    assert np.degrees(np.arccos(np.clip(np.einsum("cld,cd->cl", u, axis).min(), -1, 1))) <= 20.0 + 1e-9


@pytest.mark.parametrize("seed", [2, 3])
def test_surface_projection_finds_the_global_minimum(seed, jit):
    """Harsh random NURBS surfaces (degrees 1-3, clustered knots, weights 0.2-5)."""
    rng = np.random.default_rng(seed)
    for _ in range(3):
        s, X, p = bspline_stress.surface_case(rng, 200)
        pr = s.project(p)
        got = np.linalg.norm(p - pr.points, axis=1)
        assert np.all(got <= cKDTree(X).query(p)[0] + 1e-12 * s.scale)
        assert np.allclose(s.evaluate(pr.parameters), pr.points, atol=1e-13 * s.scale, rtol=0)


def _crease_surface():
    """A rational surface (degrees 3 x 2, weights 0.5-2) with C0 creases (knot multiplicity
    = degree) at u = 0.5 (a ridge) and v = 0.4 (a valley)."""
    rng = np.random.default_rng(7)
    ku, kv = 3, 2
    tu = np.r_[[0.0] * 4, [0.5] * 3, [1.0] * 4]
    tv = np.r_[[0.0] * 3, [0.4] * 2, [1.0] * 3]
    nu, nv = len(tu) - ku - 1, len(tv) - kv - 1
    U, V = np.meshgrid(np.linspace(0, 2, nu), np.linspace(0, 2, nv), indexing="ij")
    # the net is kinked at the control points the creases pass through (U = 1, V = 1)
    Z = 0.8 - 0.8 * np.abs(U - 1.0) + 0.5 * np.abs(V - 1.0) + 0.1 * rng.standard_normal((nu, nv))
    w = np.exp(rng.uniform(np.log(0.5), np.log(2.0), (nu, nv)))
    return BSplineSurface(ku, kv, tu, tv, np.stack([U, V, Z], axis=-1), w)


def _dense(s, n=801):
    """Dense samples of the surface (scipy's evaluation, not the projection's cells)."""
    g = np.linspace(0, 1, n)
    return s.evaluate(np.stack(np.meshgrid(g, g, indexing="ij"), -1).reshape(-1, 2))


def _assert_global_minimum(s, X, p):
    pr = s.project(p)
    got = np.linalg.norm(p - pr.points, axis=1)
    assert np.all(got <= cKDTree(X).query(p)[0] + 1e-12 * s.scale)
    assert np.allclose(s.evaluate(pr.parameters), pr.points, atol=1e-13 * s.scale, rtol=0)
    return pr


def test_surface_projection_across_creases(jit):
    """C0 creases: points near and far, and points above and below the crease lines (closest
    point on the ridge, or one of two minima beside the valley / under the ridge)."""
    s = _crease_surface()
    assert len(s._creases[0]) == 1 and len(s._creases[1]) == 1
    X = _dense(s)
    rng = np.random.default_rng(11)
    t = rng.uniform(0, 1, 300)
    on = np.concatenate([np.column_stack([np.full(300, 0.5), t]), np.column_stack([t, np.full(300, 0.4)])])
    h = s.scale * rng.uniform(0.001, 0.5, (len(on), 1)) * rng.choice([-1.0, 1.0], (len(on), 1))
    p = np.concatenate([s.evaluate(on) + h * np.array([0.0, 0.0, 1.0]), bspline_stress.query(rng, X, s.scale, 600)])
    pr = _assert_global_minimum(s, X, p)
    # the ridge's crest: straight above it the closest point is on the crease
    above = np.flatnonzero((on[:, 0] == 0.5) & (h[:, 0] > 0.05 * s.scale))
    assert np.allclose(pr.parameters[above, 0], 0.5, atol=1e-9)


@pytest.mark.parametrize("seed", [5, 6])
def test_surface_projection_of_far_points(seed, jit):
    """Points about the surface's size away (around it, and along its normals, near the
    centres of curvature, where the distance is flat over many cells)."""
    rng = np.random.default_rng(seed)
    for _ in range(2):
        s, X, _ = bspline_stress.surface_case(rng, 0)
        uv = rng.uniform(0, 1, (300, 2))
        along = s.scale * rng.uniform(0.3, 1.5, (300, 1)) * rng.choice([-1.0, 1.0], (300, 1))
        p = np.concatenate([s.evaluate(uv) + along * s.normals_at(uv), X[rng.integers(0, len(X), 300)] + s.scale * rng.standard_normal((300, 3))])
        _assert_global_minimum(s, X, p)


def test_surface_points_near_centres_of_curvature(monkeypatch):
    """An elliptic paraboloid patch z = a x^2 + b y^2 (exact as a bicubic, rational with
    random weights too) and points near its axis around the centres of curvature 1/(2a),
    1/(2b), where the distance is nearly flat and has several local minima: the global one
    against a dense brute force, on both paths."""
    rng = np.random.default_rng(5)
    x_ctrl = np.array([-1.0, -1 / 3, 1 / 3, 1.0])
    sq_ctrl = np.array([1.0, -1 / 3, -1 / 3, 1.0])  # x^2 on [-1, 1] in cubic Bernstein form
    t = np.r_[[0.0] * 4, [1.0] * 4]
    g = np.linspace(0, 1, 401)
    UV = np.stack(np.meshgrid(g, g, indexing="ij"), -1).reshape(-1, 2)
    for rational in (False, True):
        a, b = rng.uniform(0.3, 2.0, 2)
        X, Y = np.meshgrid(x_ctrl, x_ctrl, indexing="ij")
        P = np.stack([X, Y, a * sq_ctrl[:, None] + b * sq_ctrl[None, :]], -1)
        w = np.exp(rng.uniform(-0.5, 0.5, (4, 4))) if rational else None
        s = BSplineSurface(3, 3, t, t, P, w)
        h = rng.uniform(0.2, 3.0, 150) * max(1 / (2 * a), 1 / (2 * b))
        p = np.column_stack([rng.normal(0, 0.02, 150), rng.normal(0, 0.02, 150), h])
        # nearest sample by matrix products (a k-d tree is slow here: many samples are
        # nearly equidistant), then its exact distance
        S = s.evaluate(UV)
        D2 = np.einsum("ij,ij->i", S, S) - 2.0 * sum(p[:, d, None] * S[:, d] for d in range(3))
        brute = np.linalg.norm(S[np.argmin(D2, axis=1)] - p, axis=1)
        for jit in (False, True) if _jit.enabled() else (False,):
            monkeypatch.setenv("IBFEM_NO_JIT", "" if jit else "1")
            got = np.linalg.norm(p - s.project(p).points, axis=1)
            assert np.all(got <= brute + 1e-12 * s.scale), jit


def test_no_points_to_project(jit):
    """An empty (0, 3) query gives empty results on both paths (curves and surfaces)."""
    rng = np.random.default_rng(0)
    c, _, _ = bspline_stress.curve_case(rng, 3)
    s, _, _ = bspline_stress.surface_case(rng, 3)
    for prim in (c, s):
        pr = prim.project(np.empty((0, 3)))
        assert pr.points.shape == (0, 3) and pr.distances.shape == (0,) and pr.normals.shape == (0, 3)


def test_non_finite_points_are_rejected(jit):
    """A NaN or infinite query point is an error naming the row (the search would return
    an arbitrary point for it), on both paths, and for a sweep of a B-spline profile."""
    from ibfem.geometry import primitive_from_dict

    rng = np.random.default_rng(0)
    c, _, _ = bspline_stress.curve_case(rng, 3)
    s, _, _ = bspline_stress.surface_case(rng, 3)
    profile = {"type": "bspline_curve", "degree": 2, "knots": [0, 0, 0, 1, 1, 1],
               "control_points": [[0, 0, 0], [1, 1, 0], [2, 0, 0]]}
    sweep = primitive_from_dict({"type": "sweep", "profile": profile, "direction": [0, 0, 1]})
    for prim in (c, s, sweep):
        for bad in (np.nan, np.inf):
            p = np.zeros((3, 3))
            p[1, 2] = bad
            with pytest.raises(ValueError, match="row 1"):
                prim.project(p)
