"""The error estimate (``ibfem run``'s ``estimated_error``: a second solve on a grid twice as
coarse, in 2D a third on one 4 times as coarse, Richardson with the orders of
solver.model.accuracy) beside the true error on the shipped
examples: 2D contacts against Hertz for the computed force (a; the peak pressure p0; c against
Cattaneo-Mindlin's c/a times Hertz's a for the computed forces), 3D circular contacts against
Hertz for the computed force (a, p0; elliptical contacts with Johnson's elliptic integrals) and
Mindlin's stick radius for the computed forces (c); the largest subsurface von Mises stress of
frictionless or tied contacts of one material against Hertz's on the axis of a circular 3D contact, and
in 2D, in a table of its own, against Hertz's plus the tension of each half disc pressed through its
flat edge (a half disc on a block or on a half disc; an approximate reference, docs/accuracy.md,
"The 2D subsurface von Mises stress"); sphere_on_flat's semi-axes and normal force against the converged solution of the same bodies (solver.reference.converged.SPHERE_ON_FLAT,
benchmarks/accuracy_reference_3d.py). Each scene solved in this process: the solve's and the
estimate's wall time are both printed (the estimate's cost). The rounded flat punches and the
pin in a bore against the converged solution of the same finite bodies under the same load
(solver.reference.converged.HALF_WIDTHS, fitted-mesh NGSolve: benchmarks/accuracy_reference_2d.py),
with their distance from the infinite bodies' closed forms beside (the punch's on half-planes,
Ciavarella, Hills and Monno 1998; Persson's pin in an infinite plate); the tilted flat punch's
region against Johnson's rigid tilted punch for the computed force. Prints a markdown
table (docs/accuracy.md). With ``--limits`` each scene is also solved on a grid 4 times as
coarse, and a second table gives each size's Richardson limit from the three grids (observed
order), the limit against the reference and the fine grid's error against the limit beside the
estimate.

    python benchmarks/accuracy_estimates.py examples/mesh_convergence.toml ...
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

from ibfem.solver.io.scene import load_scene
from ibfem.solver.reference import theory
from ibfem.solver.reference.converged import HALF_WIDTHS, SPHERE_ON_FLAT
from ibfem.solver.reference.pin import pin_in_bore_angle
from ibfem.solver.reference.punch import rounded_punch_half_width
from ibfem.solver.reports.validate import effective_properties
from ibfem.solver.solving import coarser, estimate_errors, solve


def true_errors_2d(problem, c: dict) -> dict:
    """Relative errors of a, p0 and (frictional) c against Hertz / Cattaneo-Mindlin for the
    computed forces."""
    r_eff, e_eff = effective_properties(problem, c)
    N, a = float(c["normal_force"]), float(c["half_width"])
    a_h = theory.hertz_half_width(N, r_eff, e_eff)
    out = {"half_width": a / a_h - 1.0,
           "max_pressure": c["max_pressure"] / theory.hertz_peak_pressure(N, a_h) - 1.0}
    if c["type"] == "frictional":
        ca = theory.cattaneo_mindlin_stick_ratio(float(c["tangential_force"]), N, float(c["friction"]),
                                                 allow_gross_slip=True)
        if ca > 0:
            out["stick_half_width"] = float(c["stick_half_width"]) / (ca * a_h) - 1.0
    return out


def disc_corrected_peak(a_over_r: float, nu: float) -> float:
    """Largest on-axis plane-strain von Mises stress / p0 of McEwen's field plus the uniform
    sxx = N / (pi R) = p0 a / (2 R) a half disc of radius R pressed through its flat edge carries
    near the contact (a disc compressed along a diameter, Timoshenko and Goodier section 41;
    measured 0.51-0.52 a / R against 0.50: docs/accuracy.md, "The 2D subsurface von Mises
    stress"), by a dense scan of the depth."""
    z = np.linspace(0.3, 1.2, 90001)
    sxx, szz, sxz = theory.mcewen_stress(0.0 * z, z, 1.0, 1.0)
    return float(np.max(theory.von_mises_plane_strain(sxx + 0.5 * a_over_r, szz, sxz, nu)))


def von_mises_error_2d(problem, c: dict, scene) -> float | None:
    """The largest von Mises stress against Hertz's field plus each half disc's tension, the larger
    of the bodies' (frictionless or tied contacts of one material, a half disc pressed through its
    flat edge against a half disc or a block); None for other bodies or friction."""
    vm = c.get("max_von_mises")
    if vm is None or not math.isfinite(vm) or c["type"] == "frictional":
        return None
    mats = {(m.youngs_modulus, m.poissons_ratio) for m in (problem.body(n).material for n in c["bodies"])}
    shapes = {b["name"]: b["shape"] for b in scene.spec.model_dump(mode="json")["bodies"]}
    kinds = [shapes[n]["type"] for n in c["bodies"]]
    if len(mats) != 1 or kinds[0] != "half_disk" or kinds[1] not in ("half_disk", "rectangle"):
        return None
    nu = next(iter(mats))[1]
    r_eff, e_eff = effective_properties(problem, c)
    N = float(c["normal_force"])
    a_h = theory.hertz_half_width(N, r_eff, e_eff)
    p0 = theory.hertz_peak_pressure(N, a_h)
    peak = max(disc_corrected_peak(a_h / shapes[n]["radius"], nu) for n, k in zip(c["bodies"], kinds) if k == "half_disk")
    return vm / (peak * p0) - 1.0


def von_mises_error_3d(problem, c: dict) -> float | None:
    """The largest von Mises stress against Hertz's on the axis of a circular contact (the half
    difference's peak: 0.620 p0 at 0.48 a for nu = 0.3), for the computed force; frictionless or
    tied contacts of one material only (None otherwise)."""
    vm, share = c.get("max_von_mises"), float(c.get("model_share", 1.0))
    curv = c.get("relative_curvatures") or [math.nan, math.nan]
    mats = {(m.youngs_modulus, m.poissons_ratio) for m in (problem.body(n).material for n in c["bodies"])}
    if vm is None or not math.isfinite(vm) or c["type"] == "frictional" or len(mats) != 1 \
            or abs(curv[0] - curv[1]) > 1e-3 * abs(curv[0]):
        return None
    e, nu = next(iter(mats))
    n_full = float(c["normal_force"]) / share
    a_h = theory.hertz_sphere_radius(n_full, 1.0 / curv[0], e / (2.0 * (1.0 - nu ** 2)))
    sr, sz = theory.hertz_sphere_axis_stress(np.linspace(1e-6, 3.0, 30001), 1.0, 1.0, nu)
    return vm / (float(np.max(np.abs(sr - sz))) * theory.hertz_sphere_peak_pressure(n_full, a_h)) - 1.0


def _e_star(problem, c: dict) -> float:
    return effective_properties(problem, c)[1]


def true_errors_converged(problem, c: dict, name: str) -> dict:
    """a against the converged solution of the same finite bodies under the same load
    (ibfem.solver.reference.converged.HALF_WIDTHS: fitted-mesh NGSolve P3)."""
    return {"half_width": float(c["half_width"]) / HALF_WIDTHS[name]["half_width"] - 1.0}


def against_theory(problem, c: dict, name: str) -> float:
    """a against the closed form of the infinite bodies for the computed force: the rounded flat
    punch's on half-planes (``share`` of the whole punch: 0.5 for the half model), Persson's
    contact angle of the pin in an infinite plate (the chord on the pin)."""
    if name == "pin_in_bore":
        angle = pin_in_bore_angle(float(c["normal_force"]), 5e-4, _e_star(problem, c))
        return float(c["half_width"]) / (2.0 * 0.5 * math.sin(0.5 * angle)) - 1.0
    share = 0.5 if name.endswith("_half") else 1.0
    a_ref = rounded_punch_half_width(float(c["normal_force"]) / share, 0.01, 1.0, _e_star(problem, c))
    return float(c["half_width"]) / a_ref - 1.0


def true_errors_tilted(problem, c: dict, scene=None) -> dict:
    """The region's half length (``half_width``: half its length from the corner to the free end)
    against Johnson's rigid tilted flat punch on a half-plane held against rotation (Contact
    Mechanics, 1985, sec. 2.8) for the computed force: P = pi E* eps a / 2."""
    eps = -math.radians(scene.spec.model_dump(mode="json")["bodies"][0]["shape"]["rotate_deg"])
    a_ref = 2.0 * float(c["normal_force"]) / (math.pi * _e_star(problem, c) * eps)
    return {"half_width": float(c["half_width"]) / a_ref - 1.0}


#: the shipped examples with their own exact references (by file stem)
SPECIAL = {"tilted_punch": true_errors_tilted, "sphere_on_flat": lambda pr, c: true_errors_sphere_reference(pr, c),
           **{name: (lambda pr, c, n=name: true_errors_converged(pr, c, n)) for name in HALF_WIDTHS}}


def true_errors_3d(problem, c: dict) -> dict:
    """Relative errors of the semi-axes and p0 against Hertz for the computed force (circular contacts)."""
    share = float(c.get("model_share", 1.0))
    mats = [problem.body(n).material for n in c["bodies"]]
    e_star = 1.0 / sum((1 - m.poissons_ratio ** 2) / m.youngs_modulus for m in mats)
    curv = c.get("relative_curvatures") or [math.nan, math.nan]
    n_full = float(c["normal_force"]) / share
    if abs(curv[0] - curv[1]) > 1e-3 * abs(curv[0]):  # an ellipse: a along the smaller curvature
        major, minor, p0 = theory.hertz_elliptic_contact(n_full, tuple(curv), e_star)
        axes = [major, minor] if curv[0] < curv[1] else [minor, major]
        return {"semi_axes": [s / r - 1.0 for s, r in zip(c["semi_axes"], axes)],
                "max_pressure": c["max_pressure"] / p0 - 1.0}
    a_h = theory.hertz_sphere_radius(n_full, 1.0 / curv[0], e_star)
    out = {"semi_axes": [s / a_h - 1.0 for s in c["semi_axes"]],
           "max_pressure": c["max_pressure"] / theory.hertz_sphere_peak_pressure(n_full, a_h) - 1.0}
    q = float(np.hypot(*c["tangential_force"])) / share
    if c["type"] == "frictional" and q > 0.0:  # Mindlin's stick radius for the computed forces
        ratio = theory.mindlin_sphere_stick_ratio(q, n_full, float(c["friction"]))
        if ratio > 0.0:
            out["stick_semi_axes"] = [s / (ratio * a_h) - 1.0 for s in c["stick_semi_axes"]]
    return out


def true_errors_sphere_reference(problem, c: dict) -> dict:
    """sphere_on_flat: the semi-axes and N against the converged solution of the same finite
    bodies under the same displacement (solver.reference.converged.SPHERE_ON_FLAT: fitted-mesh
    NGSolve), p0 against Hertz's for the computed force (no converged p0 is stored)."""
    hertz = true_errors_3d(problem, c)
    return {"semi_axes": [float(s) / SPHERE_ON_FLAT["a"] - 1.0 for s in c["semi_axes"]],
            "normal_force": float(c["normal_force"]) / SPHERE_ON_FLAT["N"] - 1.0,
            "max_pressure": hertz["max_pressure"]}


def _pct(v) -> str:
    if isinstance(v, list):
        return " / ".join(_pct(x) for x in v)
    return "n/a" if v is None or not math.isfinite(v) else f"{100 * v:.3g} %"


SIZES = ("half_width", "stick_half_width", "semi_axes", "stick_semi_axes")


def _sizes(block: dict) -> dict:
    """The contact's sizes as lists (one value per axis)."""
    out = {}
    for key in SIZES:
        v = block.get(key)
        values = [float(x) for x in (v if isinstance(v, list) else [v])] if v is not None else []
        if values and all(x > 0.0 for x in values):
            out[key] = values
    return out


def limit_rows(scene, solution) -> list[dict]:
    """Each size of the first contact on the scene's grid and on grids 2 and 4 times as coarse,
    with its Richardson limit from the three (observed order)."""
    blocks = [solution.contacts[0]] + [solve(coarser(scene.problem, f)).contacts[0] for f in (2.0, 4.0)]
    rows = []
    for key, fine in _sizes(blocks[0]).items():
        for k, f0 in enumerate(fine):
            f1, f2 = (_sizes(b)[key][k] for b in blocks[1:])
            d_fine, d_coarse = f0 - f1, f1 - f2
            order = math.log2(d_coarse / d_fine) if d_fine and d_coarse / d_fine > 1.0 else math.nan
            limit = f0 + d_fine / (2.0 ** order - 1.0) if math.isfinite(order) else math.nan
            rows.append({"quantity": key, "axis": k, "values": [f0, f1, f2], "order": order, "limit": limit})
    return rows


def _print_limits(rows: list[dict]) -> None:
    print("\n| example | quantity | grid, 2x, 4x coarser (m) | observed order | Richardson limit (m) | limit against the "
          "reference | fine grid against the limit | estimated | estimated / (fine against limit) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        for lim in r.get("limits", []):
            key, k = lim["quantity"], lim["axis"]
            true, est = r["true"].get(key), (r["estimated"] or {}).get(key)
            true = true[k] if isinstance(true, list) else true
            est = est[k] if isinstance(est, list) else est
            f0 = lim["values"][0]
            against = lim["limit"] / (f0 / (1.0 + true)) - 1.0 if true is not None else math.nan
            fine = f0 / lim["limit"] - 1.0
            ratio = f"{est / abs(fine):.2g}" if est is not None and fine else "n/a"
            print(f"| {Path(r['scene']).stem} | {key} | {', '.join(f'{v:.6g}' for v in lim['values'])} | "
                  f"{lim['order']:.2f} | {lim['limit']:.6g} | {_pct(against)} | {_pct(fine)} | {_pct(est)} | {ratio} |")


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="+", type=Path)
    ap.add_argument("--json", type=Path, default=None)
    ap.add_argument("--limits", action="store_true", help="also solve 4x coarser: the sizes' three-grid limits")
    args = ap.parse_args(argv)
    rows = []
    for path in args.scenes:
        scene = load_scene(path)
        t0 = time.perf_counter()
        solution = solve(scene.problem)
        t1 = time.perf_counter()
        estimate_errors(scene.problem, solution)
        t2 = time.perf_counter()
        for c in solution.contacts:
            exact = SPECIAL.get(path.stem) or (true_errors_3d if scene.problem.dim == 3 else true_errors_2d)
            true = exact(scene.problem, c, scene=scene) if exact is true_errors_tilted else exact(scene.problem, c)
            if scene.problem.dim == 3 and (vm := von_mises_error_3d(scene.problem, c)) is not None:
                true["max_von_mises"] = vm
            approx = von_mises_error_2d(scene.problem, c, scene) if scene.problem.dim == 2 else None
            row = {"scene": str(path), "solve_s": t1 - t0, "estimate_s": t2 - t1, "type": c["type"],
                   "estimated": c.get("estimated_error"), "note": c.get("estimate_note"), "true": true}
            if approx is not None:
                row["von_mises_approximate"] = approx
            if path.stem in HALF_WIDTHS:
                row["against_theory"] = against_theory(scene.problem, c, path.stem)
            if args.limits and c is solution.contacts[0]:
                row["limits"] = limit_rows(scene, solution)
            rows.append(row)
            print(json.dumps(row, default=float), flush=True)
    print("\n| example | quantity | true error | estimated | estimated / true | solve (s) | estimate (s) |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        for key, true in r["true"].items():
            est = (r["estimated"] or {}).get(key)
            ts, es = (true if isinstance(true, list) else [true]), (est if isinstance(est, list) else [est])
            ratio = " / ".join("n/a" if e is None or not t else f"{e / abs(t):.2f}" for e, t in zip(es, ts))
            shown = _pct(est) if r["estimated"] is not None else f"none: {r.get('note')}"
            print(f"| {Path(r['scene']).stem} | {key} | {_pct(true)} | {shown} | {ratio} | "
                  f"{r['solve_s']:.1f} | {r['estimate_s']:.1f} |")
    approx_rows = [r for r in rows if "von_mises_approximate" in r]
    if approx_rows:  # 2D: Hertz's field plus the half discs' tension, itself approximate to about 0.15-0.2 %
        print("\n| example | max_von_mises against Hertz plus the half discs' tension | estimated |")
        print("|---|---|---|")
        for r in approx_rows:
            print(f"| {Path(r['scene']).stem} | {_pct(r['von_mises_approximate'])} | {_pct((r['estimated'] or {}).get('max_von_mises'))} |")
    theory_rows = [r for r in rows if "against_theory" in r]
    if theory_rows:
        print("\n| example | a against the converged finite bodies | a against the infinite bodies' closed form |")
        print("|---|---|---|")
        for r in theory_rows:
            print(f"| {Path(r['scene']).stem} | {_pct(r['true']['half_width'])} | {_pct(r['against_theory'])} |")
    if args.limits:
        _print_limits(rows)
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1, default=float))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
