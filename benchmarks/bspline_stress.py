"""Harsh random B-spline projection check against a dense-sampling brute force.

Random curves and surfaces with clustered knots, weights 0.2-5, random orientations;
query points near (1 %), mid (5-30 %) and far (100 %) from the spline. Reports per case
the number of points whose returned distance exceeds the brute-force nearest sample by
more than 1e-12 of the size (a missed global minimum), and the time.

    .venv/bin/python benchmarks/bspline_stress.py [--cases 20] [--points 2000]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy.spatial import cKDTree

from geometry.bspline import BSplineCurve, BSplineSurface


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
    args = ap.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    for kind, make in (("curve", curve_case), ("surface", surface_case)):
        if args.kind not in (kind, "both"):
            continue
        bad_total, worst, elapsed = 0, 0.0, 0.0
        for _ in range(args.cases):
            prim, X, p = make(rng, args.points)
            t0 = time.process_time()
            pr = prim.project(p)
            elapsed += time.process_time() - t0
            got = np.linalg.norm(p - pr.points, axis=1)
            brute = cKDTree(X).query(p)[0]
            excess = (got - brute) / prim.scale
            bad_total += int(np.sum(excess > 1e-12))
            worst = max(worst, float(excess.max()))
        total = args.cases * args.points
        print(f"{kind:8s} cases {args.cases:3d} points {total:7d}  missed {bad_total:4d}  "
              f"worst excess {worst:9.2e} of size  {total / elapsed / 1e3:8.1f} kpts/s cpu")


if __name__ == "__main__":
    main()
