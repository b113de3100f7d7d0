"""Validation of partial slip with memory (2D): a fretting run of a cylinder on a flat against the
Mindlin-Deresiewicz superposition for the line contact (solver.reference.fretting).

Per step after the normal load is held: the computed stick half-width against the current
branch's c' (Cattaneo on first loading, sqrt(1 - |Q - Q_t| / (2 mu N)) a after a turning point
Q_t), the computed shear against the superposed shear (RMS over the region, relative to mu p0),
both from the computed N, Q and a; per complete cycle the energy from the local friction work and
from the loop against the closed form W(Q*) with Q* the mean of the cycle's two extremes and N the
mean over the cycle's steps.

``python -m ibfem.solver.reports.validate_fretting [scene] [--out DIR] [--no-sphere]`` runs the
shipped fretting example (or ``scene``) and prints the table, then (unless ``--no-sphere``) the 3D
validation of a ball on a flat (solver.reports.validate_fretting_sphere, into DIR/sphere);
``compare(summary, profiles)`` is what the tests use.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from ..io.fretting_outputs import turning_steps
from ..reference.fretting import energy_per_cycle, history_shear
from ..reference.theory import effective_modulus, plane_strain_modulus

__all__ = ["compare", "main"]

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "fretting" / "cylinder_on_flat_fretting.toml"


def compare(summary: dict, profiles: dict, radius: float, youngs_modulus: float, poissons_ratio: float,
            contact: int = 0) -> dict:
    """Per step and per cycle, the computed values beside the superposition's (see the module)."""
    steps = summary["steps"]
    mu = float(summary["contacts"][contact]["friction"])
    q_all = np.array([st["contacts"][contact]["tangential_force"] for st in steps])
    n_all = np.array([st["contacts"][contact]["normal_force"] for st in steps])
    t_all = np.array([st["t"] for st in steps])
    # the first step with shear: a grid not symmetric about the contact transmits a parasitic shear
    # under the normal load alone (2.5e-5 of Q* on the example's grid shifted by (0.37, 0.21))
    start = int(np.flatnonzero(np.abs(q_all) > 1e-3 * mu * n_all.max())[0])
    sign = 1.0  # Q along the contact's tangent; the shear on body 1 is along -t for Q > 0 on body 2
    turns = [k for k in turning_steps(q_all) if k >= start]
    e_star = effective_modulus(youngs_modulus, poissons_ratio, youngs_modulus, poissons_ratio)
    s = np.asarray(profiles["s"])
    rows = []
    for k in range(start, len(steps)):
        c = steps[k]["contacts"][contact]
        a, n, q = c["half_width"], c["normal_force"], c["tangential_force"]
        centre = c.get("region_centre", 0.0)
        past = [float(q_all[j]) for j in turns if j < k]
        x = s - centre
        q_ref, c_ref = history_shear(x, a, n, mu, past, q)
        p0 = 2.0 * n / (math.pi * a)
        inside = np.abs(x) < a
        q_num = -sign * np.asarray(profiles["shear"][k])  # shear applied to the flat: minus that on body 1
        rms = float(np.sqrt(np.mean((q_num[inside] - q_ref[inside]) ** 2)) / (mu * p0))
        rows.append({"t": steps[k]["t"], "Q": q, "N": n, "a": a, "c": c["stick_half_width"], "c_theory": c_ref,
                     "c_error_over_a": (c["stick_half_width"] - c_ref) / a, "shear_rms_over_mu_p0": rms,
                     "branch": len(past)})
    cycles = []
    for cyc in summary.get("fretting", [{}])[contact].get("cycles", []):
        lo, hi = cyc["tangential_force_range"]
        q_star = 0.5 * (hi - lo)
        in_cycle = (t_all >= cyc["t"][0] - 1e-9) & (t_all <= cyc["t"][1] + 1e-9)
        w_ref = energy_per_cycle(q_star, float(np.mean(n_all[in_cycle])), mu, radius, e_star)  # the cycle's N
        cycles.append({**cyc, "Q_amplitude": q_star, "energy_theory": w_ref,
                       "friction_error": cyc["energy_friction"] / w_ref - 1.0,
                       "loop_error": cyc["energy_loop"] / w_ref - 1.0})
    return {"steps": rows, "cycles": cycles, "plane_modulus": plane_strain_modulus(youngs_modulus, poissons_ratio)}


def _table(result: dict) -> str:
    lines = ["   t      Q/(mu N)   c/a     c'/a theory  error/a  shear RMS/(mu p0)"]
    for r in result["steps"]:
        lines.append(f"{r['t']:6.3f}  {r['Q'] / (0.3 * r['N']):+8.4f}  {r['c'] / r['a']:7.4f}  {r['c_theory'] / r['a']:9.4f}"
                     f"  {r['c_error_over_a']:+8.4f}  {r['shear_rms_over_mu_p0']:8.4f}")
    for c in result["cycles"]:
        lines.append(f"cycle t = {c['t']}: W friction {c['energy_friction']:.4g} J/m ({c['friction_error']:+.2%}), "
                     f"W loop {c['energy_loop']:.4g} J/m ({c['loop_error']:+.2%}), theory {c['energy_theory']:.4g} J/m")
    return "\n".join(lines)


def run(scene: Path, out: Path) -> dict:
    from ..io.output import write_scene_results
    from ..io.scene import load_scene
    from ..solving import solve

    sc = load_scene(scene)
    solution = solve(sc.problem)
    summary = write_scene_results(out, sc, solution)
    profiles = dict(np.load(out / "profiles_0.npz"))
    body = sc.problem.bodies[0]
    radius = float(sc.spec.bodies[0].shape["radius"])  # the cylinder is the first body
    m = body.material
    return compare(summary, profiles, radius, m.youngs_modulus, m.poissons_ratio)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene", nargs="?", default=str(EXAMPLE))
    ap.add_argument("--out", default="validation_fretting")
    ap.add_argument("--no-sphere", action="store_true",
                    help="skip the 3D validation (a ball on a flat: solver.reports.validate_fretting_sphere)")
    args = ap.parse_args(argv)
    result = run(Path(args.scene), Path(args.out))
    print(_table(result))
    (Path(args.out) / "validation.json").write_text(json.dumps(result, indent=1), encoding="utf-8")
    if not args.no_sphere:
        from .validate_fretting_sphere import main as sphere_main

        return sphere_main(["--out", str(Path(args.out) / "sphere")])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
