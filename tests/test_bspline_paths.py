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

from geometry import _jit  # noqa: E402


def _cases(seed, count, points):
    rng = np.random.default_rng(seed)
    return [bspline_stress.curve_case(rng, points) for _ in range(count)]


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("jit", [False, True])
def test_curve_projection_finds_the_global_minimum(seed, jit, monkeypatch):
    if jit and not _jit.enabled():
        pytest.skip("numba not installed")
    monkeypatch.setenv("IBFEM_NO_JIT", "" if jit else "1")
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
@pytest.mark.parametrize("jit", [False, True])
def test_surface_projection_finds_the_global_minimum(seed, jit, monkeypatch):
    """Harsh random NURBS surfaces (degrees 1-3, clustered knots, weights 0.2-5)."""
    if jit and not _jit.enabled():
        pytest.skip("numba not installed")
    monkeypatch.setenv("IBFEM_NO_JIT", "" if jit else "1")
    rng = np.random.default_rng(seed)
    for _ in range(3):
        s, X, p = bspline_stress.surface_case(rng, 200)
        pr = s.project(p)
        got = np.linalg.norm(p - pr.points, axis=1)
        assert np.all(got <= cKDTree(X).query(p)[0] + 1e-12 * s.scale)
        assert np.allclose(s.evaluate(pr.parameters), pr.points, atol=1e-13 * s.scale, rtol=0)
