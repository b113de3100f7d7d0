"""The closed forms' and the ellipse's two implementations (compiled kernel of
geometry._closed_kernels on threads, numpy path with IBFEM_NO_JIT=1) against each other,
on random points and on the special places (axes, centres, the cone's apex region, the
ellipse's evolute, huge and tiny coordinates), and the ``out=`` option (results written
into the arrays of an earlier projection, on both paths)."""

import math

import numpy as np
import pytest

from ibfem.geometry import Projection, _jit, primitive_from_dict

KINDS = {
    "line": {"type": "line", "origin": [0.3, -0.2, 0.1], "direction": [1.0, 2.0, 2.0]},
    "circle": {"type": "circle", "origin": [0.3, -0.2, 0.1], "normal": [1.0, 2.0, 2.0], "radius": 1.5},
    "ellipse": {"type": "ellipse", "origin": [0.3, -0.2, 0.1], "normal": [0.0, 0.0, 1.0], "major_axis": [1, 1, 0],
                "major_radius": 2.0, "minor_radius": 0.5},
    "ellipse_round": {"type": "ellipse", "origin": [0, 0, 0], "normal": [0.0, 0.0, 1.0], "major_axis": [1, 0, 0],
                      "major_radius": 1.0001, "minor_radius": 1.0},
    "plane": {"type": "plane", "origin": [0.3, -0.2, 0.1], "normal": [1.0, 2.0, 2.0]},
    "sphere": {"type": "sphere", "origin": [0.3, -0.2, 0.1], "radius": 1.5},
    "cylinder": {"type": "cylinder", "origin": [0.3, -0.2, 0.1], "axis": [1.0, 2.0, 2.0], "radius": 1.5},
    "cone": {"type": "cone", "origin": [0.3, -0.2, 0.1], "axis": [1.0, 2.0, 2.0], "radius": 0.5, "half_angle": 0.5},
    "torus": {"type": "torus", "origin": [0.3, -0.2, 0.1], "axis": [1.0, 2.0, 2.0], "major_radius": 1.0,
              "minor_radius": 0.3},
}


def points(d, n=40000, seed=7):
    rng = np.random.default_rng(seed)
    o = np.asarray(d["origin"], float)
    ax = np.asarray(d.get("axis", d.get("normal", d.get("direction", [0.0, 0.0, 1.0]))), float)
    ax = ax / np.linalg.norm(ax)
    special = [o, o + 1e-200, o + 1e200, o + 5e-324, o + 2.0 * ax, o - 3.0 * ax, o + 1e-9 * ax]
    if d["type"] == "cone":
        apex = o - d["radius"] / math.tan(d["half_angle"]) * ax
        special += [apex, apex - ax, apex + 1e-12]
    if d["type"] == "ellipse":  # the major axis inside the evolute
        e1 = np.array([1.0, 1.0, 0.0]) / math.sqrt(2.0)
        special += [o + s * e1 for s in (0.1, 1.0, 1.8, 1.875, 1.9)]
    p = [np.array(special), o + rng.normal(size=(n, 3)) * 2.0, o + rng.normal(size=(n // 8, 3)) * 1e6]
    return np.vstack(p)


def well_posed(d, p):
    o = np.asarray(d["origin"], float)
    r = p - o
    if d["type"] == "plane":
        return np.ones(len(p), bool)
    if d["type"] == "sphere":
        return np.linalg.norm(r, axis=1) > 1e-6
    ax = np.asarray(d.get("axis", d.get("normal", d.get("direction"))), float)
    ax = ax / np.linalg.norm(ax)
    h = r @ ax
    rho = np.linalg.norm(r - np.outer(h, ax), axis=1)
    good = rho > 1e-6
    if d["type"] == "torus":
        good &= np.hypot(rho - d["major_radius"], h) > 1e-6
    if d["type"] == "ellipse":
        e1 = np.asarray(d["major_axis"], float)
        e2 = np.cross(ax, e1 / np.linalg.norm(e1))
        good &= np.abs(r @ e2) > 1e-6
    return good


def both(prim, p, monkeypatch, **kw):
    monkeypatch.setenv("IBFEM_NO_JIT", "")
    a = prim.project(p, **kw)
    monkeypatch.setenv("IBFEM_NO_JIT", "1")
    b = prim.project(p, **kw)
    return a, b


@pytest.mark.parametrize("name", list(KINDS))
def test_compiled_and_numpy_paths_agree(name, monkeypatch):
    if not _jit.enabled():
        pytest.skip("numba not installed")
    prim = primitive_from_dict(KINDS[name])
    p = points(KINDS[name])
    a, b = both(prim, p, monkeypatch)
    o = np.asarray(KINDS[name]["origin"], float)
    scale = 1.0 + np.abs(p - o).max(axis=1)  # no overflow at 1e200
    err = np.abs(a.distances - b.distances) / scale
    assert err.max() < 1e-14, (err.max(), p[err.argmax()])
    # points, normals and parameters where the closest point is well-posed: away from the
    # axis, the centre, the torus's core circle, and the ellipse's major axis (inside the
    # evolute the two feet +-y are equally close, picked by the sign of a round-off)
    with np.errstate(over="ignore", invalid="ignore"):  # the 1e200 points
        good = well_posed(KINDS[name], p) & (scale < 1e5)
    assert good.sum() > 0.8 * len(p)
    assert (np.abs(a.points - b.points).max(axis=1) / scale)[good].max() < 1e-14
    assert np.all(np.isfinite(a.normals)) and np.allclose(np.linalg.norm(a.normals, axis=1), 1.0, atol=1e-14)
    assert np.abs(a.normals - b.normals)[good].max() < 1e-12
    par_a, par_b = np.asarray(a.parameters).reshape(len(p), -1), np.asarray(b.parameters).reshape(len(p), -1)
    diff = np.abs(par_a - par_b)
    diff = np.minimum(diff, np.abs(diff - 2 * np.pi))  # angles at the seam
    assert (diff.max(axis=1) / scale)[good].max() < 1e-12
    assert a.parameters.shape == b.parameters.shape


@pytest.mark.parametrize("name", ["circle", "ellipse", "sphere", "cone", "plane", "line"])
@pytest.mark.parametrize("jit", [False, True], ids=["numpy", "compiled"])
def test_out_writes_into_the_given_arrays(name, jit, monkeypatch):
    if jit and not _jit.enabled():
        pytest.skip("numba not installed")
    monkeypatch.setenv("IBFEM_NO_JIT", "" if jit else "1")
    prim = primitive_from_dict(KINDS[name])
    p = points(KINDS[name], n=30000)
    first = prim.project(p)
    keep = Projection(first.points.copy(), first.normals.copy(), first.distances.copy(), first.parameters.copy())
    again = prim.project(p + 0.25, out=first)
    assert again.points is first.points or np.shares_memory(again.points, first.points)
    assert np.shares_memory(again.distances, first.distances)
    ref = prim.project(p + 0.25)
    for x, y in ((again.points, ref.points), (again.distances, ref.distances), (again.parameters, ref.parameters)):
        assert np.array_equal(x, y, equal_nan=True)
    assert not np.array_equal(keep.points, again.points)
    with pytest.raises(ValueError, match="out.points must be"):
        prim.project(p[:10], out=first)


def test_threads_setting_is_checked(monkeypatch):
    monkeypatch.setenv("IBFEM_THREADS", "two")
    with pytest.raises(ValueError, match="IBFEM_THREADS"):
        _jit.threads()
    monkeypatch.setenv("IBFEM_THREADS", "1")
    assert _jit.threads() == 1
