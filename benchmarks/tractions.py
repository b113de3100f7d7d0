"""The numbers engineers read: contact pressure, shear and the subsurface von Mises
peak against theory, on every example and on the same scenes turned on the grid, shifted by
fractions of a cell and loaded from a = 3 cells to a = R/4.

Per case (each in its own subprocess), for the forces the solver computed
(solver.reports.validate.compare_contact and solver.reference.theory):

- ``a``, ``c``, ``N``, ``Q`` as reported (these must not move with the recovery) and the error
  of a against Hertz;
- ``p_rms``: RMS of the reported pressure minus Hertz inside 0.9 a, in p0; ``p_min``: the most
  negative reported pressure, in p0; ``ripple``: RMS of the reported pressure minus its own
  smooth fit (a degree-8 polynomial in s times sqrt(1 - s^2/a^2), least squares inside 0.9 a), in
  p0: the cell-scale oscillation;
- frictional: ``q_rms`` the shear RMS against Cattaneo-Mindlin inside 0.95 a in mu p0, and
  ``q_excess`` the largest |q| - mu p of the profile in mu p0 (Coulomb: <= 0);
- ``vm_peak``: the largest von Mises stress of the recovered field below the contact (body 2)
  against the peak of McEwen's half-space field (or the Cattaneo-Mindlin superposition),
  relative; ``vm_depth``: the depth of the computed peak minus the theoretical one, in a (a
  dense window of 3a x 1.6a, then the vertex of a quadratic fitted around the best sample);
- examples (full run): the same scene with one and two more refinement levels; ``vm_peak_h``
  and ``vm_depth_h``: the peak and its depth against those of the finest grid (the
  discretisation error of the peak; the rest of ``vm_peak`` is the bodies' finite size, which
  the half-space references leave out: docs/contact.md measures it with NGSolve);
- turned and shifted variants: ``vm_peak_conv`` / ``vm_depth_conv``, the peak (in its own p0)
  and depth (in its own a) against the same example's finest grid (the same bodies, turned or
  on a shifted grid). Where these exist the 1 % target on the von Mises peak is judged on them (the error of the
  solution of the posed problem), else on ``vm_peak``. The loads (a/R up to 1/4, where the
  half-space value is not the posed problem's) up to a = 16 cells also run two more levels
  (a = R/8 and R/4 would need 15-50 million dofs there).

    .venv/bin/python benchmarks/tractions.py              # all cases (~5 minutes on 2 cores)
    .venv/bin/python benchmarks/tractions.py --quick      # the examples only
    .venv/bin/python benchmarks/tractions.py --only ex3   # cases whose name contains ex3

Writes benchmarks/results/tractions.json (or --out) and prints one line per case with the
targets (p_rms <= 0.02, p_min >= -0.005, q_rms <= 0.05, |vm_peak| <= 0.01,
|vm_depth| <= 0.02; the peak against the converged solution of the same bodies where measured).
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import subprocess
import sys
import time
import tomllib
from pathlib import Path

HERE = Path(__file__).resolve().parent
EXAMPLES = HERE.parent / "examples"

EXAMPLE_CASES = [
    ("ex1_ellipse_on_block", "ellipse_on_block.toml"),
    ("ex2_cylinder_on_block", "mesh_convergence.toml"),
    ("ex3_cylinder_on_cylinder", "cylinder_on_cylinder_frictionless.toml"),
    ("ex4_cylinder_on_flat_slip", "cylinder_on_flat_partial_slip.toml"),
    ("ex5_cylinder_on_cylinder_slip", "cylinder_on_cylinder_partial_slip.toml"),
    ("ex6_cylinder_in_concave_slip", "cylinder_in_concave_partial_slip.toml"),
    ("ex7_cylinder_on_wedge", "cylinder_on_wedge_frictionless.toml"),
]

ACCEPT = {"p_rms": 0.02, "p_min": -0.005, "q_rms": 0.05, "vm_peak": 0.01, "vm_depth": 0.02}
#: the peak judged against the converged solution of the same bodies where a row has it
CONVERGED_KEYS = {"vm_peak": "vm_peak_conv", "vm_depth": "vm_depth_conv"}
BASE = {f: n for n, f in EXAMPLE_CASES}


def _rotate(v, deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return [c * v[0] - s * v[1], s * v[0] + c * v[1]]


def _turn(data: dict, deg: float) -> None:
    """Turn the whole scene by ``deg`` about the origin (shapes, loads, contact points)."""
    for b in data["bodies"]:
        shape = b["shape"]
        if shape.get("type") == "profile":
            for e in shape["edges"]:
                for key in ("center", "start", "end"):
                    if key in e:
                        e[key] = _rotate(e[key], deg)
                if e.get("type") == "arc":
                    e["start_angle"] += deg
                    e["end_angle"] += deg
        elif shape.get("type") == "polygon":
            shape["points"] = [_rotate(p, deg) for p in shape["points"]]
        else:
            shape["rotate_deg"] = shape.get("rotate_deg", 0.0) + deg
    for bc in data["boundary_conditions"]:
        if bc["type"] == "displacement":
            if any(v == "free" for v in bc["value"]):
                if deg:
                    raise ValueError("a displacement with a free component cannot be turned")
                continue
            bc["value"] = _rotate(bc["value"], deg)
    for c in data["contacts"]:
        if "point" in c:
            c["point"] = _rotate(c["point"], deg)


def _scene_dict(spec: dict) -> dict:
    data = tomllib.loads((EXAMPLES / spec["file"]).read_text())
    data.pop("output", None)
    if spec.get("uy_scale"):
        for bc in data["boundary_conditions"]:
            if bc["type"] == "displacement":
                bc["value"] = [v * spec["uy_scale"] if isinstance(v, (int, float)) else v for v in bc["value"]]
    if spec.get("refinement"):
        for b in data["bodies"]:
            b["element_size"] = spec["refinement"]["element_size"]
            b["refinement"] = spec["refinement"]["zones"]
    if spec.get("extra_levels"):
        for b in data["bodies"]:
            finest = max(b["refinement"], key=lambda r: r["levels"])
            finest["levels"] += spec["extra_levels"]
    if spec.get("turn"):
        _turn(data, spec["turn"])
    return data


def _smooth_fit_ripple(s, p, a, p0) -> float:
    """RMS of p minus its least-squares fit sqrt(1 - x^2) * (degree-8 polynomial) inside 0.9 a."""
    import numpy as np

    x = s / a
    inner = np.abs(x) <= 0.9
    if inner.sum() < 12:
        return math.nan
    basis = np.sqrt(1.0 - x[inner, None] ** 2) * np.vander(x[inner], 9, increasing=True)
    coef, *_ = np.linalg.lstsq(basis, p[inner], rcond=None)
    return float(np.sqrt(np.mean((basis @ coef - p[inner]) ** 2)) / p0)


def _quadratic_vertex(f, x0: float, z0: float, step: float) -> tuple[float, float, float]:
    """Peak of f(x, z) near (x0, z0): a quadratic fitted by least squares to a 9 x 9 patch of
    samples ``step`` apart (the recovered field is piecewise bilinear: a local optimiser stalls
    on its kinks), its vertex if inside the patch, else the best sample."""
    import numpy as np

    g = step * np.arange(-4, 5)
    X, Z = np.meshgrid(x0 + g, z0 + g)
    x, z = X.ravel(), Z.ravel()
    v = f(x, z)
    ok = np.isfinite(v)
    dx, dz = x[ok] - x0, z[ok] - z0
    basis = np.column_stack([np.ones(ok.sum()), dx, dz, dx * dx, dx * dz, dz * dz])
    c, *_ = np.linalg.lstsq(basis, v[ok], rcond=None)
    hess = np.array([[2 * c[3], c[4]], [c[4], 2 * c[5]]])
    try:
        d = np.linalg.solve(hess, -c[1:3])
    except np.linalg.LinAlgError:
        d = np.array([np.inf, np.inf])
    if np.all(np.linalg.eigvalsh(hess) < 0) and np.all(np.abs(d) <= 4 * step):
        b = np.array([1.0, d[0], d[1], d[0] ** 2, d[0] * d[1], d[1] ** 2])
        return float(b @ c), x0 + float(d[0]), z0 + float(d[1])
    k = int(np.nanargmax(v))
    return float(v[k]), float(x[k]), float(z[k])


def _vm_peak(problem, solution, block, m) -> dict:
    """Largest recovered von Mises stress below the contact against theory's field peak."""
    import numpy as np
    from ibfem.solver.reference import theory
    from ibfem.solver.reports.validate import reference_field

    a, p0 = m["a_hertz"], m["p0"]
    point, normal, tangent = (np.asarray(block[k], dtype=float) for k in ("point", "normal", "tangent"))
    body = block["bodies"][1]

    def vm_at(x, z):
        pts = point + a * (np.atleast_1d(x)[:, None] * tangent - np.atleast_1d(z)[:, None] * normal)
        return np.asarray(solution.von_mises(pts, body=body), dtype=float)

    xs, zs = np.linspace(-1.5, 1.5, 121), np.linspace(0.05, 1.6, 63)
    X, Z = np.meshgrid(xs, zs)
    vm = vm_at(X.ravel(), Z.ravel())
    k = int(np.nanargmax(vm))
    peak, x, z = _quadratic_vertex(vm_at, float(X.ravel()[k]), float(Z.ravel()[k]), 0.04)
    nu = problem.body(body).material.poissons_ratio
    field = reference_field(block, m)
    ref, x_ref, z_ref = theory.field_peak(lambda xx, zz: field(xx * a, zz * a), nu=nu, extent=2.0, n=81)
    return {"vm_peak": peak / ref - 1.0, "vm_depth": z - z_ref, "vm_x": x - x_ref,
            "vm_peak_p0": peak / p0, "vm_peak_theory_p0": ref / p0, "vm_z": z, "vm_z_theory": z_ref}


def run_one(spec: dict) -> dict:
    """One case; with ``converge`` also the same scene with 1 and 2 more refinement levels, and
    the peak's change from this grid to the finest (the discretisation error of the peak)."""
    row = _run(spec)
    if spec.get("converge"):
        finer = [_run({**spec, "extra_levels": k}) for k in (1, 2)]
        row["vm_peak_levels"] = [row["vm_peak_p0"]] + [f["vm_peak_p0"] for f in finer]
        row["vm_z_levels"] = [row["vm_z"]] + [f["vm_z"] for f in finer]
        row["p_rms_levels"] = [row["p_rms"]] + [f["p_rms"] for f in finer]
        row["vm_peak_h"] = row["vm_peak_p0"] / finer[-1]["vm_peak_p0"] - 1.0
        row["vm_depth_h"] = row["vm_z"] - finer[-1]["vm_z"]
    return row


def _run(spec: dict) -> dict:
    import numpy as np

    from ibfem.solver.io.scene import scene_from_dict
    from ibfem.solver.reports.validate import compare_contact
    from ibfem.solver.solving import solve

    data = _scene_dict(spec)
    problem = scene_from_dict(data, label=spec["file"], base_dir=EXAMPLES).problem
    if spec.get("offset"):
        problem = problem.with_options(grid_offset=tuple(spec["offset"]))
    t = time.perf_counter()
    sol = solve(problem)
    wall = time.perf_counter() - t
    block = sol.contacts[0]
    m = compare_contact(problem, block, {})
    a_h, p0 = m["a_hertz"], m["p0"]
    s, p = np.asarray(block["pressure"]["s"]), np.asarray(block["pressure"]["value"])
    h = min(v["min_element_size"] for v in sol.body_info.values())
    row = {"case": spec["name"], "converged": sol.converged, "a": block["half_width"], "c": block["stick_half_width"],
           "N": block["normal_force"], "Q": block["tangential_force"], "a_error": m["a_error"],
           "cells_across_a": block["half_width"] / h, "a_over_R": block["half_width"] / m["R_eff"],
           "p_rms": m.get("pressure_rms"), "p_min": float(p.min() / p0),
           "ripple": _smooth_fit_ripple(s, p, block["half_width"], p0), "wall_s": wall}
    if block["type"] == "frictional":
        q = np.asarray(block["shear"]["value"])
        row.update(q_rms=m.get("shear_rms"), ca=m["ca"], ca_theory=m["ca_theory"],
                   q_excess=float(np.max(np.abs(q) - block["friction"] * np.maximum(p, 0.0)) / (block["friction"] * p0)))
    row.update(_vm_peak(problem, sol, block, m))
    return row


def cases(quick: bool) -> list[dict]:
    out = [{"name": n, "file": f, "converge": not quick} for n, f in EXAMPLE_CASES]
    if quick:
        return out
    ex2, ex3 = "mesh_convergence.toml", "cylinder_on_cylinder_frictionless.toml"
    ex4, ex5 = "cylinder_on_flat_partial_slip.toml", "cylinder_on_cylinder_partial_slip.toml"
    variants = []
    for deg in (10.0, 25.0, 45.0):
        variants.append({"name": f"ex3_turned_{deg:g}deg", "file": ex3, "turn": deg})
        variants.append({"name": f"ex4_turned_{deg:g}deg", "file": ex4, "turn": deg})
    variants.append({"name": "ex2_turned_25deg", "file": ex2, "turn": 25.0})
    variants.append({"name": "ex5_turned_25deg", "file": ex5, "turn": 25.0})
    # grid origins shifted by fractions of the finest cell (element_size / 16 here)
    for off in ((1 / 64, 1 / 64), (2 / 64, 3 / 64), (0.37, 0.26)):
        variants.append({"name": f"ex3_shift_{off[0]:.3f}_{off[1]:.3f}", "file": ex3, "offset": off})
        variants.append({"name": f"ex4_shift_{off[0]:.3f}_{off[1]:.3f}", "file": ex4, "offset": off})
    variants.append({"name": "ex3_turned_25deg_shift_0.37_0.26", "file": ex3, "turn": 25.0, "offset": (0.37, 0.26)})
    out += [{**v, "base": BASE[v["file"]]} for v in variants]
    # loads on example 2 (h = 3.125 mm): a ~ 3, 6 cells, then a = R/8 and R/4 with the refined
    # zone widened to hold the region (the finest cells 2 levels coarser: a ~ 20 / 40 cells)
    for scale in (0.15, 0.5, 2.0):
        out.append({"name": f"ex2_load_x{scale:g}", "file": ex2, "uy_scale": scale, "converge": True})
    for scale, radius in ((15.0, 0.3), (60.0, 0.55)):
        zones = [{"levels": 1, "around": "contact", "radius": 2 * radius}, {"levels": 2, "around": "contact", "radius": radius}]
        out.append({"name": f"ex2_load_x{scale:g}", "file": ex2, "uy_scale": scale,
                    "refinement": {"element_size": 0.05, "zones": zones}})
    return out


def _line(row: dict) -> str:
    if "error" in row:
        return f"{row['case']:36s} ERROR {row['error']}"
    fail = []
    for key, tol in ACCEPT.items():
        v = row.get(CONVERGED_KEYS.get(key, key), row.get(key))
        if v is None or (isinstance(v, float) and math.isnan(v)):
            continue
        bad = v < tol if key == "p_min" else abs(v) > tol
        if bad:
            fail.append(key)
    q = f" q_rms {row['q_rms']:.4f} q_exc {row['q_excess']:+.1e}" if "q_rms" in row else ""
    if "vm_peak_h" in row:
        q += f" | vs 2 levels finer: vM {row['vm_peak_h']:+.3%} depth {row['vm_depth_h']:+.4f} a"
    elif "vm_peak_conv" in row:
        q += f" | vs the example 2 levels finer: vM {row['vm_peak_conv']:+.3%} depth {row['vm_depth_conv']:+.4f} a"
    q += " | half-space:"
    return (f"{row['case']:36s} a/h {row['cells_across_a']:5.1f} a {row['a_error']:+.3%} p_rms {row['p_rms']:.4f} "
            f"p_min {row['p_min']:+.4f} ripple {row['ripple']:.4f}{q} vM {row['vm_peak']:+.3%} "
            f"depth {row['vm_depth']:+.4f} a  {'ok' if not fail else 'FAIL ' + ','.join(fail)}  {row['wall_s']:.1f}s")


def _against_base(row: dict, spec: dict, rows: list[dict]) -> None:
    """The peak of a row against the converged solution of its bodies: its own finest grid (an
    example run with ``converge``), or its example's finest grid (a turned / shifted variant,
    when that example ran first in this run)."""
    if "vm_peak_h" in row:
        row["vm_peak_conv"], row["vm_depth_conv"] = row["vm_peak_h"], row["vm_depth_h"]
        return
    base = next((r for r in rows if r.get("case") == spec.get("base") and "vm_peak_levels" in r), None)
    if base is not None:
        row["vm_peak_conv"] = row["vm_peak_p0"] / base["vm_peak_levels"][-1] - 1.0
        row["vm_depth_conv"] = row["vm_z"] - base["vm_z_levels"][-1]


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="the examples only")
    ap.add_argument("--only", help="run the cases whose name contains this")
    ap.add_argument("--single", help=argparse.SUPPRESS)
    ap.add_argument("--out", default=str(HERE / "results" / "tractions.json"))
    args = ap.parse_args(argv)
    if args.single:
        print(json.dumps(run_one(json.loads(args.single))))
        return 0
    rows = []
    for spec in cases(args.quick):
        if args.only and args.only not in spec["name"]:
            continue
        r = subprocess.run([sys.executable, __file__, "--single", json.dumps(spec)], capture_output=True, text=True)
        if r.returncode != 0:
            last = r.stderr.strip().splitlines()[-1] if r.stderr.strip() else "?"
            rows.append({"case": spec["name"], "error": last})
        else:
            rows.append(json.loads(r.stdout.strip().splitlines()[-1]))
            _against_base(rows[-1], spec, rows)
        print(_line(rows[-1]), flush=True)
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"machine": platform.platform(), "runs": rows}, indent=2))
    return 0 if all("error" not in r for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
