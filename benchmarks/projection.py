"""Projection throughput and accuracy of every primitive type in the registry.

For each primitive (built with ``geometry.primitive_from_dict`` from a plain definition) the
script projects N random points in a box around it and reports points per second (best of
3) as wall-clock and per CPU second (process CPU time over all threads). The compiled
kernels (numba, the ``fast`` extra) run on the threads of ``geometry._jit.run_ranges``
(``IBFEM_THREADS``, default every core; ``--threads 1`` for one core); BLAS/OpenMP threads
are pinned to 1 before numpy is imported; ``IBFEM_NO_JIT=1`` measures the numpy path.
``out=`` is the wall-clock rate when the results are written into the arrays of an earlier
projection (closed forms and ellipse: no allocation, no page faults of fresh memory).
Also the largest errors against checks independent of the code under test:

- ``residual``: the primitive's implicit equation at the returned closest points (closed forms;
  relative to the primitive's size), e.g. ``| |c - o| - R |`` for a sphere;
- ``consistency``: the signed Euclidean distance (|distance| is the distance to the closest point), ``| |distance| - |p - c| |``
  (relative to 1 + |p - c|; infinite if a sign disagrees with ``(p - c) . n``), and ``| |n| - 1 |``;
- ``brute``: on a subset, how much farther the returned closest point is than the nearest of a
  dense sampling of the primitive (> 0 only if the projection missed a closer point; the
  ellipse's samples are refined by golden-section search, so there it is a 1e-12 check);
- ``offset``: points of the primitive (from its own parametrisation here) offset along their
  analytic normals and projected back: the largest distance from the original point and
  the largest error of the signed distance.

Errors are relative to the primitive's size (1 for the unit-sized definitions below).

    .venv/bin/python benchmarks/projection.py            # 10^6 points (10^5 for B-splines)
    .venv/bin/python benchmarks/projection.py --quick    # 10^5 points (10^4 for B-splines)

Writes benchmarks/results/projection.json and projection.csv.
"""

from __future__ import annotations

import os
import sys

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS"):
    os.environ[_var] = "1"
if "--threads" in sys.argv[:-1]:
    os.environ["IBFEM_THREADS"] = sys.argv[sys.argv.index("--threads") + 1]

import argparse  # noqa: E402
import inspect  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import platform  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from ibfem import geometry  # noqa: E402
from ibfem.geometry import _jit  # noqa: E402
from ibfem.geometry._base import _REGISTRY  # noqa: E402  (the list of registered primitive types)

GOLD = (math.sqrt(5.0) - 1.0) / 2.0


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def perp(axis):
    axis = unit(axis)
    trial = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = unit(trial - trial.dot(axis) * axis)
    return e1, np.cross(axis, e1)


def norms(a):
    return np.linalg.norm(a, axis=-1)


def rows_dot(a, b):
    return np.einsum("ij,ij->i", a, b)


# ---------------------------------------------------------------------------------------
# definitions
# ---------------------------------------------------------------------------------------

O = [0.3, -0.2, 0.1]
AX = list(unit([1.0, 2.0, 2.0]))
E1, E2 = perp(AX)


def _bspline_curve_def():
    # open cubic through a wavy 3D polygon, clamped knots
    cp = [[0, 0, 0], [1, 1, 0.2], [2, -0.5, 0.4], [3, 0.8, -0.3], [4, 0, 0.5], [5, 1, 0], [6, 0, 0.2]]
    k = 3
    n = len(cp)
    inner = list(np.linspace(0, 1, n - k + 1)[1:-1])
    return {"type": "bspline_curve", "degree": k, "knots": [0.0] * (k + 1) + inner + [1.0] * (k + 1), "control_points": cp}


def _bspline_surface_def():
    nu, nv, k = 6, 6, 3
    u = np.linspace(0, 1, nu)
    v = np.linspace(0, 1, nv)
    U, V = np.meshgrid(u, v, indexing="ij")
    Z = 0.3 * np.sin(3 * U) * np.cos(2 * V)
    cp = np.stack([U * 2, V * 2, Z], axis=-1)
    knots = [0.0] * (k + 1) + list(np.linspace(0, 1, nu - k + 1)[1:-1]) + [1.0] * (k + 1)
    return {
        "type": "bspline_surface",
        "degree_u": k,
        "degree_v": k,
        "knots_u": knots,
        "knots_v": knots,
        "control_points": cp.tolist(),
    }


def definitions():
    """(label, definition, bspline?) for every registered type; extra ellipse aspect ratios."""
    ell = {"type": "ellipse", "origin": O, "normal": AX, "major_axis": list(E1), "major_radius": 1.0}
    cases = [
        ("line", {"type": "line", "origin": O, "direction": AX}),
        ("circle", {"type": "circle", "origin": O, "normal": AX, "radius": 1.0}),
        ("ellipse", {**ell, "minor_radius": 0.5}),
        ("ellipse a/b=1.0001", {**ell, "minor_radius": 1 / 1.0001}),
        ("ellipse a/b=1000", {**ell, "minor_radius": 1e-3}),
        ("plane", {"type": "plane", "origin": O, "normal": AX}),
        ("sphere", {"type": "sphere", "origin": O, "radius": 1.0}),
        ("cylinder", {"type": "cylinder", "origin": O, "axis": AX, "radius": 1.0}),
        ("cone", {"type": "cone", "origin": O, "axis": AX, "radius": 0.5, "half_angle": 0.5}),
        ("torus", {"type": "torus", "origin": O, "axis": AX, "major_radius": 1.0, "minor_radius": 0.3}),
        ("bspline_curve", _bspline_curve_def()),
        ("bspline_surface", _bspline_surface_def()),
        (
            "sweep",
            {
                "type": "sweep",
                "profile": {"type": "ellipse", "origin": [0, 0, 0], "normal": [0, 0, 1], "major_axis": [1, 0, 0],
                            "major_radius": 1.0, "minor_radius": 0.6},
                "direction": [0.0, 0.3, 1.0],
            },
        ),
    ]
    known = {label for label, _ in cases}
    for name in sorted(_REGISTRY):
        if name not in known:  # a type registered later without a case here: say so
            cases.append((name, None))
    return cases


# ---------------------------------------------------------------------------------------
# independent references
# ---------------------------------------------------------------------------------------


def residual(d, c):
    """Implicit-equation residual (None where the primitive has no closed-form equation)."""
    kind = d["type"]
    if kind not in ("line", "circle", "ellipse", "plane", "sphere", "cylinder", "cone", "torus"):
        return None
    o = np.asarray(d["origin"], dtype=float)
    r = c - o
    if kind == "line":
        return norms(np.cross(r, unit(d["direction"])))
    if kind == "plane":
        return np.abs(r @ unit(d["normal"]))
    if kind == "sphere":
        return np.abs(norms(r) - d["radius"])
    if kind in ("circle", "ellipse"):
        n = unit(d["normal"])
        h = r @ n
        if kind == "circle":
            return np.abs(h) + np.abs(np.sqrt(np.maximum(rows_dot(r, r) - h * h, 0)) - d["radius"])
        e1 = unit(np.asarray(d["major_axis"]) - np.dot(d["major_axis"], n) * n)
        e2 = np.cross(n, e1)
        a, b = d["major_radius"], d["minor_radius"]
        # |(u/a)^2 + (v/b)^2 - 1| * b / 2 ~ distance from the ellipse near it
        return np.abs(h) + np.abs(((r @ e1) / a) ** 2 + ((r @ e2) / b) ** 2 - 1) * b / 2
    a = unit(d["axis"])
    t = r @ a
    rho = norms(np.cross(r, a))
    if kind == "cylinder":
        return np.abs(rho - d["radius"])
    if kind == "cone":
        rt = d["radius"] + t * math.tan(d["half_angle"])
        return np.abs(rho - rt) * math.cos(d["half_angle"]) + np.maximum(-rt, 0)
    return np.abs(np.hypot(rho - d["major_radius"], t) - d["minor_radius"])


def _bspline_eval(d, params):
    """Points of a (non-rational) B-spline curve/surface with scipy directly."""
    from scipy.interpolate import BSpline, NdBSpline

    if d["type"] == "bspline_curve":
        return BSpline(np.asarray(d["knots"], float), np.asarray(d["control_points"], float), d["degree"])(params)
    spl = NdBSpline(
        (np.asarray(d["knots_u"], float), np.asarray(d["knots_v"], float)),
        np.asarray(d["control_points"], float),
        (d["degree_u"], d["degree_v"]),
    )
    return spl(params)


def _sweep_eval(d, s, h):
    prof = d["profile"]
    a, b = prof["major_radius"], prof["minor_radius"]
    e1 = unit(prof["major_axis"])
    e2 = np.cross(unit(prof["normal"]), e1)
    c = np.asarray(prof["origin"], float) + a * np.cos(s)[:, None] * e1 + b * np.sin(s)[:, None] * e2
    return c + h[:, None] * np.asarray(d["direction"], float)


def dense_samples(d, pts):
    """Dense points of the primitive covering everything that could be closer to pts than the
    returned closest points (unbounded primitives: a window wide enough that any point outside
    it is farther than the farthest query point's distance bound)."""
    kind = d["type"]
    if kind == "bspline_curve":
        t = np.linspace(d["knots"][0], d["knots"][-1], 200001)
        return _bspline_eval(d, t)
    if kind == "bspline_surface":
        u = np.linspace(d["knots_u"][0], d["knots_u"][-1], 600)
        U, V = np.meshgrid(u, u, indexing="ij")
        return _bspline_eval(d, np.c_[U.ravel(), V.ravel()])
    if kind == "sweep":
        s = np.linspace(-np.pi, np.pi, 720, endpoint=False)
        span = float(np.max(norms(pts))) * 3 + 3
        h = np.linspace(-span, span, 2000)
        S, H = np.meshgrid(s, h)
        return _sweep_eval(d, S.ravel(), H.ravel())
    o = np.asarray(d["origin"], dtype=float)
    reach = float(np.max(norms(pts - o))) + 1.0
    if kind == "line":
        t = np.linspace(-2 * reach, 2 * reach, 400001)
        return o + t[:, None] * unit(d["direction"])
    if kind in ("circle", "ellipse"):
        e1, e2 = perp(d["normal"])
        if kind == "ellipse":
            n = unit(d["normal"])
            e1 = unit(np.asarray(d["major_axis"]) - np.dot(d["major_axis"], n) * n)
            e2 = np.cross(n, e1)
        a = d.get("radius", d.get("major_radius"))
        b = d.get("radius", d.get("minor_radius"))
        th = np.linspace(-np.pi, np.pi, 200000, endpoint=False)
        return o + a * np.cos(th)[:, None] * e1 + b * np.sin(th)[:, None] * e2
    if kind == "plane":
        e1, e2 = perp(d["normal"])
        u = np.linspace(-2 * reach, 2 * reach, 800)
        U, V = np.meshgrid(u, u)
        return o + U.reshape(-1, 1) * e1 + V.reshape(-1, 1) * e2
    if kind == "sphere":
        m = 400000
        k = np.arange(m) + 0.5
        z = 1 - 2 * k / m
        phi = np.pi * (1 + 5**0.5) * k
        s = np.sqrt(1 - z * z)
        return o + d["radius"] * np.c_[s * np.cos(phi), s * np.sin(phi), z]
    a = unit(d["axis"])
    e1, e2 = perp(a)
    th = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    ring = np.cos(th)[:, None] * e1 + np.sin(th)[:, None] * e2
    if kind == "torus":
        phi = np.linspace(0, 2 * np.pi, 500, endpoint=False)
        rr = d["major_radius"] + d["minor_radius"] * np.cos(phi)
        hh = d["minor_radius"] * np.sin(phi)
    else:
        tp = (pts - o) @ a
        t = np.linspace(tp.min() - reach, tp.max() + reach, 600)
        if kind == "cylinder":
            rr = np.full_like(t, d["radius"])
        else:
            tan = math.tan(d["half_angle"])
            t_apex = -d["radius"] / tan
            t = np.unique(np.r_[t[t > t_apex], t_apex])
            rr = d["radius"] + t * tan
        hh = t
    return o + (rr[:, None, None] * ring[None] + hh[:, None, None] * a).reshape(-1, 3)


def golden_ellipse_distance(d, pts):
    """Unsigned 3D distance to the ellipse: dense angles refined by golden-section search."""
    o = np.asarray(d["origin"], float)
    n = unit(d["normal"])
    e1 = unit(np.asarray(d["major_axis"]) - np.dot(d["major_axis"], n) * n)
    e2 = np.cross(n, e1)
    a, b = d["major_radius"], d["minor_radius"]
    x, y, h = (pts - o) @ e1, (pts - o) @ e2, (pts - o) @ n
    th = np.linspace(-np.pi, np.pi, 8192, endpoint=False)
    ex, ey = a * np.cos(th), b * np.sin(th)
    best = np.concatenate([((x[i:i + 256, None] - ex) ** 2 + (y[i:i + 256, None] - ey) ** 2).argmin(1)
                           for i in range(0, len(x), 256)])

    def f(t):
        return (x - a * np.cos(t)) ** 2 + (y - b * np.sin(t)) ** 2

    hstep = 2 * np.pi / 8192
    lo, hi = th[best] - hstep, th[best] + hstep
    c, dd = hi - GOLD * (hi - lo), lo + GOLD * (hi - lo)
    fc, fd = f(c), f(dd)
    for _ in range(90):
        left = fc < fd
        hi = np.where(left, dd, hi)
        lo = np.where(left, lo, c)
        nc, nd = hi - GOLD * (hi - lo), lo + GOLD * (hi - lo)
        c, dd = np.where(left, nc, dd), np.where(left, c, nd)
        fc, fd = np.where(left, f(nc), fd), np.where(left, fc, f(nd))
    return np.hypot(np.sqrt(np.minimum(np.minimum(fc, fd), f(th[best]))), h)


def min_sample_distance(pts, samples, chunk=8):
    out = np.empty(len(pts))
    for i in range(0, len(pts), chunk):
        diff = pts[i:i + chunk, None, :] - samples[None, :, :]
        out[i:i + chunk] = np.sqrt(np.einsum("ijk,ijk->ij", diff, diff).min(axis=1))
    return out


def offset_points(d, rng, m=20000):
    """(X, N, delta, tangential_only): points of the primitive from its parametrisation, unit
    normals (analytic or, for B-splines and sweeps, from scipy's derivatives / the profile),
    offsets that keep X the closest point. ``tangential_only``: the sign convention of the
    normal is not checked (only |distance|) for free-form primitives."""
    kind = d["type"]
    if kind == "bspline_curve":
        t = rng.uniform(0.05, 0.95, m)
        X = _bspline_eval(d, t)
        from scipy.interpolate import BSpline

        T = BSpline(np.asarray(d["knots"], float), np.asarray(d["control_points"], float), d["degree"]).derivative()(t)
        N = np.cross(T, rng.normal(size=(m, 3)))
        N /= norms(N)[:, None]
        return X, N, rng.uniform(0.0, 1e-3, m), True
    if kind == "bspline_surface":
        from scipy.interpolate import NdBSpline

        uv = rng.uniform(0.05, 0.95, (m, 2))
        spl = NdBSpline(
            (np.asarray(d["knots_u"], float), np.asarray(d["knots_v"], float)),
            np.asarray(d["control_points"], float),
            (d["degree_u"], d["degree_v"]),
        )
        X = spl(uv)
        N = np.cross(spl(uv, nu=(1, 0)), spl(uv, nu=(0, 1)))
        N /= norms(N)[:, None]
        return X, N, rng.uniform(-1e-2, 1e-2, m), True
    if kind == "sweep":
        s = rng.uniform(-np.pi, np.pi, m)
        h = rng.uniform(-2, 2, m)
        X = _sweep_eval(d, s, h)
        prof = d["profile"]
        e1 = unit(prof["major_axis"])
        e2 = np.cross(unit(prof["normal"]), e1)
        T = -prof["major_radius"] * np.sin(s)[:, None] * e1 + prof["minor_radius"] * np.cos(s)[:, None] * e2
        N = np.cross(T, np.asarray(d["direction"], float))
        N /= norms(N)[:, None]
        return X, N, rng.uniform(-1e-2, 1e-2, m), True
    o = np.asarray(d["origin"], dtype=float)
    frac = rng.uniform(-0.9, 0.9, m)
    if kind == "line":
        dv = unit(d["direction"])
        e1, e2 = perp(dv)
        ang = rng.uniform(0, 2 * np.pi, m)
        N = np.cos(ang)[:, None] * e1 + np.sin(ang)[:, None] * e2
        return o + rng.uniform(-3, 3, (m, 1)) * dv, N, rng.uniform(0, 2, m), False
    if kind == "plane":
        e1, e2 = perp(d["normal"])
        X = o + rng.uniform(-3, 3, (m, 1)) * e1 + rng.uniform(-3, 3, (m, 1)) * e2
        return X, np.tile(unit(d["normal"]), (m, 1)), frac * 2, False
    if kind == "sphere":
        N = rng.normal(size=(m, 3))
        N /= norms(N)[:, None]
        return o + d["radius"] * N, N, frac * d["radius"], False
    if kind in ("circle", "ellipse"):
        n = unit(d["normal"])
        if kind == "circle":
            e1, e2 = perp(n)
            a = b = d["radius"]
        else:
            e1 = unit(np.asarray(d["major_axis"]) - np.dot(d["major_axis"], n) * n)
            e2 = np.cross(n, e1)
            a, b = d["major_radius"], d["minor_radius"]
        th = rng.uniform(-np.pi, np.pi, m)
        X = o + a * np.cos(th)[:, None] * e1 + b * np.sin(th)[:, None] * e2
        nn = b * np.cos(th)[:, None] * e1 + a * np.sin(th)[:, None] * e2
        N = nn / norms(nn)[:, None]
        rc = (a * a * np.sin(th) ** 2 + b * b * np.cos(th) ** 2) ** 1.5 / (a * b)  # radius of curvature
        ny = np.abs(rows_dot(N, np.tile(e2, (m, 1))))
        with np.errstate(divide="ignore"):
            to_axis = np.where(ny > 0, np.abs(b * np.sin(th)) / ny, np.inf)
        inward = np.minimum(rc, to_axis)
        return X, N, np.where(frac < 0, frac * inward, frac * a), False
    a = unit(d["axis"])
    e1, e2 = perp(a)
    th = rng.uniform(0, 2 * np.pi, m)
    u = np.cos(th)[:, None] * e1 + np.sin(th)[:, None] * e2
    if kind == "cylinder":
        return o + rng.uniform(-3, 3, (m, 1)) * a + d["radius"] * u, u, frac * d["radius"], False
    if kind == "cone":
        al = d["half_angle"]
        t_apex = -d["radius"] / math.tan(al)
        t = t_apex + rng.uniform(1e-3, 3, (m, 1))
        r = d["radius"] + t * math.tan(al)
        N = math.cos(al) * u - math.sin(al) * a
        delta = np.where(frac < 0, frac * r[:, 0] / math.cos(al), frac * 3)
        return o + t * a + r * u, N, delta, False
    if kind == "torus":
        R, r = d["major_radius"], d["minor_radius"]
        phi = rng.uniform(0, 2 * np.pi, (m, 1))
        N = np.cos(phi) * u + np.sin(phi) * a
        X = o + (R + r * np.cos(phi)) * u + r * np.sin(phi) * a
        return X, N, frac * r, False  # |delta| < r < R - r keeps the hole side too
    raise AssertionError(kind)


# ---------------------------------------------------------------------------------------
# the run
# ---------------------------------------------------------------------------------------


def query_box(d, rng, n):
    if d["type"] in ("bspline_curve", "bspline_surface"):
        pts = _bspline_eval(d, rng.uniform(0, 1, n) if d["type"] == "bspline_curve" else rng.uniform(0, 1, (n, 2)))
        return pts + rng.normal(size=(n, 3)) * 0.3
    o = np.asarray(d.get("origin", [0, 0, 0]), float)
    return o + rng.uniform(-2, 2, (n, 3))


def time_it(fn, repeats=3):
    wall, cpu = [], []
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        fn()
        wall.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    return min(wall), min(cpu)


def run_case(label, d, n, n_check, rng):
    row = {"primitive": label, "type": None if d is None else d["type"], "points": n}
    if d is None:
        row["skipped"] = "registered type without a benchmark definition"
        return row
    if d["type"] not in _REGISTRY:
        row["skipped"] = f"type {d['type']!r} is not registered (module not written yet)"
        return row
    try:
        prim = geometry.primitive_from_dict(d)
    except Exception as exc:  # a placeholder module, or a definition the module rejects
        row["skipped"] = f"could not build: {type(exc).__name__}: {exc}"
        return row
    pts = query_box(d, rng, n)
    prim.project(pts[:1000])  # warm-up (caches, lazy set-up)
    wall, cpu = time_it(lambda: prim.project(pts))
    row.update(wall_s=wall, cpu_s=cpu, mpts_per_s_wall=n / wall / 1e6, mpts_per_s_cpu=n / cpu / 1e6)

    pr = prim.project(pts)
    if "out" in inspect.signature(prim.project).parameters:
        wall_out, _ = time_it(lambda: prim.project(pts, out=pr))
        row["mpts_per_s_wall_out"] = n / wall_out / 1e6
    pr = prim.project(pts)
    c, nrm, dist = pr.points, pr.normals, pr.distances
    length = norms(pts - c)
    sign_ok = np.all(dist * rows_dot(pts - c, nrm) >= 0)
    euclid = float(np.max(np.abs(np.abs(dist) - length) / (1 + length))) if sign_ok else math.inf
    row["max_consistency"] = float(max(euclid, np.max(np.abs(norms(nrm) - 1))))
    res = residual(d, c)
    row["max_residual"] = None if res is None else float(np.max(res))

    sub = pts[:n_check]
    got = norms(sub - prim.project(sub).points)
    if d["type"] == "ellipse":
        ref = golden_ellipse_distance(d, sub)
        row["brute_check"] = "golden-section refined, |error|"
        row["max_brute_excess"] = float(np.max(np.abs(got - ref) / (1 + ref)))
    else:
        ref = min_sample_distance(sub, dense_samples(d, sub))
        row["brute_check"] = "dense samples, returned minus nearest sample (>0: a closer sample)"
        row["max_brute_excess"] = float(np.max(got - ref))

    X, N, delta, free_form = offset_points(d, rng)
    back = prim.project(X + delta[:, None] * N)
    row["max_offset_position_error"] = float(np.max(norms(back.points - X)))
    if free_form:
        row["max_offset_distance_error"] = float(np.max(np.abs(np.abs(back.distances) - np.abs(delta))))
    else:
        row["max_offset_distance_error"] = float(np.max(np.abs(back.distances - delta)))
    return row


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="10^5 points (10^4 for B-splines and sweeps)")
    ap.add_argument("--points", type=int, default=None, help="points per closed-form primitive")
    ap.add_argument("--threads", type=int, default=None, help="threads of the compiled kernels (IBFEM_THREADS)")
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "projection.json"))
    args = ap.parse_args(argv)
    n_closed = args.points or (100_000 if args.quick else 1_000_000)
    n_free = max(n_closed // 10, 1000)
    n_check = 200 if args.quick else 300
    rng = np.random.default_rng(20261122)

    print(f"compiled kernels: {_jit.enabled()}, threads: {_jit.threads()}")
    rows = []
    for label, d in definitions():
        free = d is not None and d["type"] in ("bspline_curve", "bspline_surface", "sweep")
        row = run_case(label, d, n_free if free else n_closed, n_check, rng)
        rows.append(row)
        print_row(row, header=len(rows) == 1)

    result = {
        "benchmark": "projection",
        "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "machine": {"platform": platform.platform(), "processor": platform.processor(), "cpus": os.cpu_count()},
        "numpy": np.__version__,
        "threads": _jit.threads(),
        "compiled": _jit.enabled(),
        "repeats": 3,
        "note": "points/s = points / best-of-3 wall time (threads of the compiled kernels: see 'threads'); "
                "cpu = points per process CPU second over all threads; out = wall rate writing into an earlier result",
        "rows": rows,
    }
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(result, indent=2))
    columns = ["primitive", "type", "points", "mpts_per_s_wall", "mpts_per_s_cpu", "mpts_per_s_wall_out", "max_residual", "max_consistency",
               "max_brute_excess", "max_offset_position_error", "max_offset_distance_error", "skipped"]
    lines = [",".join(columns)]
    for row in rows:
        lines.append(",".join("" if row.get(c) is None else str(row.get(c)).replace(",", ";") for c in columns))
    out.with_suffix(".csv").write_text("\n".join(lines) + "\n")
    print(f"\nwritten {out} and {out.with_suffix('.csv').name}")
    return result


def _fmt(x, spec):
    return "-" if x is None else format(x, spec)


def print_row(row, header=False):
    if header:
        print(f"{'primitive':20s} {'points':>8s} {'Mpts/s wall':>11s} {'Mpts/s cpu':>10s} {'out=':>6s} {'residual':>9s} "
              f"{'consist.':>9s} {'brute':>9s} {'offset pos':>10s} {'offset d':>9s}")
    if "skipped" in row:
        print(f"{row['primitive']:20s} skipped: {row['skipped']}")
        return
    print(
        f"{row['primitive']:20s} {row['points']:8d} {row['mpts_per_s_wall']:11.2f} {row['mpts_per_s_cpu']:10.2f} "
        f"{_fmt(row.get('mpts_per_s_wall_out'), '6.1f')} "
        f"{_fmt(row['max_residual'], '9.1e')} {row['max_consistency']:9.1e} {row['max_brute_excess']:9.1e} "
        f"{row['max_offset_position_error']:10.1e} {row['max_offset_distance_error']:9.1e}"
    )


if __name__ == "__main__":
    main()
