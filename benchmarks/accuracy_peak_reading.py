"""How the 3D peak pressure is read, against the grid's own error: the ball on a flat
(examples/solid/sphere_on_flat.toml) on grids refined around the contact, and on each the peak
pressure p0 read four ways from the same solution (the band traction at the region's quadrature
points, the quarter model's points with their mirror images):

- ``fit``: the earlier reading, the centre value of the least-squares fit by
  sqrt(1 - X^2 - Y^2) times a quadratic in (X, Y) over the computed ellipse;
- ``hertz_inner``: the fit by Hertz's shape alone, c sqrt(1 - X^2 - Y^2), over the inner region
  X^2 + Y^2 < 0.64 (clear of the edge's cells): the summary's reading where the region is
  Hertz-like (``reading`` and ``misfit``, solver.contact.ellipse_report.peak_reading);
- ``squared``: p^2 = p0^2 (1 - r^2 / a^2) is linear in r^2 for Hertz's pressure: its least-squares
  line over the inner region gives p0 and a radius of its own, neither read at the edge;
- ``force``: 3 N / (2 pi a b) from the whole contact's force and the computed semi-axes.

Each against Hertz's p0 for the computed force (the bodies are finite: the converged solution of
these bodies differs from Hertz's by an amount not known here; docs/accuracy.md). Each grid solved
in its own process (peak memory of the process).

    python benchmarks/accuracy_peak_reading.py --levels 5 6 --radius 0.07
"""

from __future__ import annotations

import argparse
import json
import math
import resource
import subprocess
import sys
import time
import tomllib
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
SCENE = ROOT / "examples" / "solid" / "sphere_on_flat.toml"
INNER = 0.8


def readings(X, Y, weights, p, a: float, b: float, n_full: float, e_star: float, radius: float) -> dict:
    """The four p0 readings (module docstring) and the squared fit's radius; Hertz's p0 and a."""
    whole = np.sqrt(np.clip(1.0 - X * X - Y * Y, 0.0, None))
    inner = X * X + Y * Y < INNER**2
    w = np.sqrt(np.maximum(weights[inner], 0.0))
    c = float(np.linalg.lstsq((whole[inner] * w)[:, None], p[inner] * w, rcond=None)[0][0])
    r2 = (X[inner] * a) ** 2 + (Y[inner] * b) ** 2
    A = np.stack([np.ones_like(r2), r2], axis=1)
    k0, k1 = np.linalg.lstsq(A * w[:, None], np.sign(p[inner]) * p[inner] ** 2 * w, rcond=None)[0]
    a_h = (3.0 * n_full * radius / (4.0 * e_star)) ** (1.0 / 3.0)
    p0_h = 3.0 * n_full / (2.0 * math.pi * a_h**2)
    return {"hertz_inner": c, "squared": math.sqrt(k0), "squared_radius": math.sqrt(-k0 / k1),
            "force": 3.0 * n_full / (2.0 * math.pi * a * b), "hertz_p0": p0_h, "hertz_a": a_h}


def one(levels: int, radius: float) -> dict:
    from ibfem.solver.contact import ellipse_report
    from ibfem.solver.io.scene import scene_from_dict
    from ibfem.solver.solving import solve

    data = tomllib.loads(SCENE.read_text())
    data.pop("output", None)
    for body in data["bodies"]:
        body["refinement"] = {"levels": levels, "around": "contact", "radius": radius}
    captured = []
    original = ellipse_report.fit_profile

    def capture(X, Y, weights, values):
        captured.append((X.copy(), Y.copy(), weights.copy(), values.copy()))
        return original(X, Y, weights, values)

    ellipse_report.fit_profile = capture
    t = time.perf_counter()
    solution = solve(scene_from_dict(data, label="peak reading", base_dir=ROOT).problem)
    wall = time.perf_counter() - t
    c = solution.contacts[0]
    X, Y, w, p = captured[0]
    a, b = c["semi_axes"]
    n_full = c["normal_force"] / c["model_share"]
    e_star = 2.0e11 / (2.0 * (1.0 - 0.3**2))
    out = readings(X, Y, w, p, a, b, n_full, e_star, 1.0)
    peak = c["profile_recovery"]["peak"]
    out.update({"levels": levels, "radius": radius, "dofs": int(sum(v.get("dofs", 0) for v in solution.body_info.values())),
                "a": a, "N_full": n_full, "fit": float(original(X, Y, w, p)[0]),
                "summary_p0": float(c["profile_recovery"]["pressure_coefficients"][0]),
                "reading": peak["reading"], "misfit": peak["misfit"], "residual": peak["residual"],
                "converged": bool(solution.converged), "wall_s": wall,
                "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0})
    return out


def _share(value) -> str:
    return "none" if value is None else f"{100.0 * value:.2f} %"


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--levels", type=int, nargs="+", default=[5, 6])
    ap.add_argument("--radius", type=float, default=0.07)
    ap.add_argument("--one", type=int, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one is not None:
        print(json.dumps(one(args.one, args.radius)))
        return 0
    print("| levels (finest cell, m) | dofs | a / Hertz's a - 1 | p0: fit | Hertz's shape, inner | squared, inner (its radius) "
          "| from N, a, b | summary's reading (misfit, residual) | wall (s) | peak (MB) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    rows = []
    for levels in args.levels:
        r = subprocess.run([sys.executable, __file__, "--one", str(levels), "--radius", repr(args.radius)],
                           capture_output=True, text=True)
        if r.returncode:
            print(r.stderr[-2000:], file=sys.stderr)
            continue
        row = json.loads(r.stdout.strip().splitlines()[-1])
        rows.append(row)
        print(json.dumps(row), file=sys.stderr)
        h, p0 = 0.25 / 2**levels, row["hertz_p0"]
        pct = lambda v: f"{100.0 * (v / p0 - 1.0):+.3f} %"  # noqa: E731
        print(f"| {levels} ({h:.4g}) | {row['dofs']} | {100.0 * (row['a'] / row['hertz_a'] - 1.0):+.3f} % | {pct(row['fit'])} | "
              f"{pct(row['hertz_inner'])} | {pct(row['squared'])} ({100.0 * (row['squared_radius'] / row['hertz_a'] - 1.0):+.2f} %) | "
              f"{pct(row['force'])} | {pct(row['summary_p0'])} {row['reading']} ({_share(row['misfit'])}, "
              f"{_share(row['residual'])}) | {row['wall_s']:.0f} | {row['peak_mb']:.0f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
