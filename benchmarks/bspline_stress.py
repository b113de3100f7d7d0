"""Harsh random B-spline projection check against a dense-sampling brute force.

Random curves and surfaces with clustered knots, weights 0.2-5, random orientations;
query points near (1 %), mid (5-30 %) and far (100 %) from the spline. Reports per case
the number of points whose returned distance exceeds the brute-force nearest sample by
more than 1e-12 of the size (a missed global minimum), and the time. With ``--focal`` the
points are instead put near centres of curvature (p = S + n / kappa, principal normal and
curvature at random parameters, radius scaled by 0.9-1.1, within twice the size), where
the distance is nearly flat and has several local minima.

    .venv/bin/python benchmarks/bspline_stress.py [--cases 20] [--points 2000] [--kind curve|surface|both] [--focal]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy.spatial import cKDTree

from ibfem.geometry.bspline import BSplineCurve, BSplineSurface


def clustered_knots(rng, count):
    """Interior knots drawn from a squared/cubed uniform distribution: clustered near 0 or 1."""
    x = np.sort(rng.uniform(0, 1, count) ** rng.choice([1.0, 2.0, 3.0]))
    x = 1e-3 + 0.99 * x + 1e-3 * np.arange(count) / max(count, 1)  # distinct: no C^-1 jumps
    return np.sort(1.0 - x) if rng.random() < 0.5 else x


def rotation(rng):
    q, r = np.linalg.qr(rng.standard_normal((3, 3)))
    return q * np.sign(np.diag(r))


def query(rng, X, size, m):
    """Points around samples X of the spline at 1 %, 5-30 % and 100 % of its size."""
    base = X[rng.integers(0, len(X), m)]
    scale = size * np.concatenate([np.full(m // 3, 0.01), rng.uniform(0.05, 0.3, m // 3), np.full(m - 2 * (m // 3), 1.0)])
    return base + scale[:, None] * rng.standard_normal((m, 3))


def focal_points(rng, S, normal, kappa, size):
    """Points near the centres of curvature of the spline points S (principal normals and
    curvatures given), within twice the size of the spline."""
    ok = np.abs(kappa) > 1e-3 / size
    radius = (1.0 / kappa[ok]) * rng.uniform(0.9, 1.1, ok.sum())
    p = S[ok] + normal[ok] * radius[:, None] + rng.normal(0.0, 1e-3 * size, (ok.sum(), 3))
    return p[np.linalg.norm(p - S[ok], axis=1) < 2.0 * size]


def curve_focal(rng, c, m):
    C, C1, C2 = c.derivatives(rng.uniform(0.02, 0.98, m), 2)
    speed = np.linalg.norm(C1, axis=1)
    T = C1 / speed[:, None]
    a = C2 - np.einsum("ij,ij->i", C2, T)[:, None] * T  # the acceleration's normal part
    size = np.linalg.norm(a, axis=1)
    return focal_points(rng, C, a / np.maximum(size, 1e-300)[:, None], size / speed**2, c.scale)


def surface_focal(rng, s, m):
    d = s.derivatives(rng.uniform(0.05, 0.95, (m, 2)), 2)
    Su, Sv = d[(1, 0)], d[(0, 1)]
    n = np.cross(Su, Sv)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    E, F, G = (np.einsum("ij,ij->i", a, b) for a, b in ((Su, Su), (Su, Sv), (Sv, Sv)))
    L, M, N = (np.einsum("ij,ij->i", d[nu], n) for nu in ((2, 0), (1, 1), (0, 2)))
    K = (L * N - M * M) / (E * G - F * F)
    H = (E * N - 2 * F * M + G * L) / (2 * (E * G - F * F))
    root = np.sqrt(np.maximum(H * H - K, 0.0))
    kappa = np.where(rng.uniform(size=m) < 0.5, H + root, H - root)  # a principal curvature
    return focal_points(rng, d[(0, 0)], n, kappa, s.scale)


def curve_case(rng, m):
    n = int(rng.integers(4, 12))
    k = int(rng.integers(1, min(5, n - 1) + 1))
    t = np.r_[[0.0] * (k + 1), clustered_knots(rng, n - k - 1), [1.0] * (k + 1)]
    P = np.cumsum(rng.uniform(-1, 1, (n, 3)), axis=0) @ rotation(rng).T
    w = np.exp(rng.uniform(np.log(0.2), np.log(5.0), n))
    c = BSplineCurve(k, t, P, w)
    X = c.evaluate(np.linspace(0, 1, 200_001))
    return c, X, query(rng, X, c.scale, m)


def surface_case(rng, m):
    nu, nv = int(rng.integers(3, 8)), int(rng.integers(3, 8))
    ku, kv = int(rng.integers(1, min(3, nu - 1) + 1)), int(rng.integers(1, min(3, nv - 1) + 1))
    tu = np.r_[[0.0] * (ku + 1), clustered_knots(rng, nu - ku - 1), [1.0] * (ku + 1)]
    tv = np.r_[[0.0] * (kv + 1), clustered_knots(rng, nv - kv - 1), [1.0] * (kv + 1)]
    U, V = np.meshgrid(np.linspace(0, 2, nu), np.linspace(0, 2, nv), indexing="ij")
    P = np.stack([U, V, 0.6 * rng.standard_normal((nu, nv))], axis=-1) @ rotation(rng).T
    w = np.exp(rng.uniform(np.log(0.2), np.log(5.0), (nu, nv)))
    s = BSplineSurface(ku, kv, tu, tv, P, w)
    g = np.linspace(0, 1, 801)
    X = s.evaluate(np.stack(np.meshgrid(g, g, indexing="ij"), -1).reshape(-1, 2))
    return s, X, query(rng, X, s.scale, m)


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--cases", type=int, default=20)
    ap.add_argument("--points", type=int, default=2000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--kind", choices=("curve", "surface", "both"), default="both")
    ap.add_argument("--focal", action="store_true", help="points near centres of curvature")
    args = ap.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    for kind, make in (("curve", curve_case), ("surface", surface_case)):
        if args.kind not in (kind, "both"):
            continue
        bad_total, worst, elapsed, total = 0, 0.0, 0.0, 0
        for _ in range(args.cases):
            prim, X, p = make(rng, args.points)
            if args.focal:
                p = (curve_focal if kind == "curve" else surface_focal)(rng, prim, args.points)
            t0 = time.process_time()
            pr = prim.project(p)
            elapsed += time.process_time() - t0
            got = np.linalg.norm(p - pr.points, axis=1)
            brute = cKDTree(X).query(p)[0]
            excess = (got - brute) / prim.scale
            bad_total += int(np.sum(excess > 1e-12))
            total += len(p)
            worst = max(worst, float(excess.max(initial=0.0)))
        print(f"{kind:8s} cases {args.cases:3d} points {total:7d}  missed {bad_total:4d}  "
              f"worst excess {worst:9.2e} of size  {total / max(elapsed, 1e-9) / 1e3:8.1f} kpts/s cpu")


if __name__ == "__main__":
    main()
