"""Two-body contact: wall time, iterations, peak memory and accuracy per
example, the width updates side by side, and stress tests.

Cases (each in its own subprocess, so that the peak resident memory belongs to it):

- examples 1 (exact and tessellated geometry), 2, 3, 7 and the partial-slip examples 4, 5, 6
  of examples/ with the default width search ("edge": root of the edge coefficient), and
  examples 1, 2, 3, 7 with the one-cell "bracket" search and the thesis's update (sections
  5.5.3-5.5.4);
- example 3 on grids shifted by fractions of a cell (the answer must not depend on where the
  grid starts: four quarter-cell shifts and five random fractions of the coarsest cell), with
  a 10 times stiffer upper body, and turned by 30 degrees (default and "bracket" search);
- example 3 with one more refinement level (h halved);
- examples 4-6 without the slip-zone friction traction (the thesis's variant); example 4 at
  mu = 0.05 and 1 with |Q|/(mu N) near 0.05 and 0.95, in gross slip, and turned by 30 degrees;
- a cylinder on a block under loads from a ~ 2 cells to a ~ R/4.

Per case: a against Hertz for the computed normal force (solver.reference.theory), the final bracket
of the width search, N, Q, the balance of the supports' reactions and N against them, the
RMS pressure error inside 0.9 a against Hertz (in p0), the von Mises peak on the load axis
against McEwen (0.5575 p0 at 0.704 a, frictionless cases); frictional cases: Q/N, |Q|/(mu N),
c/a against Cattaneo-Mindlin for the computed forces and the shear RMS inside 0.95 a in mu p0
(solver.reports.validate.compare_contact); iterations per load step, wall time and peak memory.

    .venv/bin/python benchmarks/contact.py            # all cases (several minutes on 2 cores)
    .venv/bin/python benchmarks/contact.py --quick    # the examples with the default search only

Writes benchmarks/results/contact.json and contact.csv.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import platform
import resource
import subprocess
import sys
import time
import tomllib
from pathlib import Path

HERE = Path(__file__).resolve().parent
EXAMPLES = HERE.parent / "examples"

# name, scene file, R* of the pair, depth direction of the subsurface line is taken from the scene
EXAMPLE_CASES = [
    ("ex1_ellipse_on_block", "ellipse_on_block.toml", 0.1),
    ("ex1_ellipse_tessellated", "ellipse_on_block_tessellated.toml", 0.1),
    ("ex2_mesh_convergence", "mesh_convergence.toml", 1.0),
    ("ex3_cylinder_on_cylinder", "cylinder_on_cylinder_frictionless.toml", 0.5),
    ("ex7_cylinder_on_wedge", "cylinder_on_wedge_frictionless.toml", 1.0),
    ("ex4_cylinder_on_flat_partial_slip", "cylinder_on_flat_partial_slip.toml", 1.0),
    ("ex5_cylinder_on_cylinder_partial_slip", "cylinder_on_cylinder_partial_slip.toml", 0.5),
    ("ex6_cylinder_in_concave_partial_slip", "cylinder_in_concave_partial_slip.toml", 2.0),
]


def _rotate(v, deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return [c * v[0] - s * v[1], s * v[0] + c * v[1]]


def _scene_dict(spec: dict) -> dict:
    data = tomllib.loads((EXAMPLES / spec["file"]).read_text())
    data.pop("output", None)
    if spec.get("stiff_upper"):
        data["materials"].append({"name": "stiff", "youngs_modulus": 10 * data["materials"][0]["youngs_modulus"],
                                  "poissons_ratio": data["materials"][0]["poissons_ratio"]})
        data["bodies"][0]["material"] = "stiff"
    if spec.get("extra_level"):
        for b in data["bodies"]:
            for r in b.get("refinement", []):
                if r["levels"] >= 4:
                    r["levels"] += 1
    if spec.get("uy") is not None:
        for bc in data["boundary_conditions"]:
            if bc["type"] == "displacement":
                bc["value"] = [bc["value"][0], spec["uy"]]
    if spec.get("ux") is not None:
        for bc in data["boundary_conditions"]:
            if bc["type"] == "displacement":
                bc["value"] = [spec["ux"], bc["value"][1]]
    if spec.get("mu") is not None:
        for c in data["contacts"]:
            c["friction"] = spec["mu"]
    turn = spec.get("rotate_deg", 0.0)
    if turn:
        for b in data["bodies"]:
            b["shape"]["rotate_deg"] = turn
        for bc in data["boundary_conditions"]:
            if bc["type"] == "displacement":
                bc["value"] = _rotate([0.0 if v == "free" else v for v in bc["value"]], turn)
        for c in data["contacts"]:
            if "point" in c:
                c["point"] = _rotate(c["point"], turn)
    return data


def run_one(spec: dict) -> dict:
    import numpy as np

    from ibfem.solver.reference import theory
    from ibfem.solver.io.scene import scene_from_dict
    from ibfem.solver.solving import solve

    data = _scene_dict(spec)
    problem = scene_from_dict(data, label=spec["file"], base_dir=EXAMPLES).problem
    problem = problem.with_options(grid_offset=tuple(spec.get("offset", (0.0, 0.0))))
    if spec.get("chord_fraction"):
        problem = problem.with_options(chord_fraction=spec["chord_fraction"])
    problem = problem.with_contact_options(width_update=spec.get("width_update", "edge"), flux=spec.get("flux", "average"),
                                           friction_traction=spec.get("friction_traction", True))
    t = time.perf_counter()
    sol = solve(problem)
    wall = time.perf_counter() - t
    c = sol.contacts[0]
    mats = {m["name"]: m for m in data["materials"]}
    m1, m2 = (mats[b["material"]] for b in data["bodies"][:2])
    e_star = theory.effective_modulus(m1["youngs_modulus"], m1["poissons_ratio"], m2["youngs_modulus"], m2["poissons_ratio"])
    n_force, a = c["normal_force"], c["half_width"]
    a_hertz = theory.hertz_half_width(max(n_force, 0.0), spec["R"], e_star)
    p0 = 2 * n_force / (math.pi * a_hertz)
    s = np.asarray(c["pressure"]["s"])
    p = np.asarray(c["pressure"]["value"])
    inner = np.abs(s) <= 0.9 * a_hertz
    rms = float(np.sqrt(np.mean((p[inner] - theory.hertz_pressure(s[inner], a_hertz, p0)) ** 2)) / p0)
    reactions = {k: np.asarray(v) for k, v in sol.reactions.items()}
    lower = data["bodies"][1]["name"]
    by_body = {}
    for k, v in reactions.items():
        by_body.setdefault(k.split("/")[0], np.zeros(2))
        by_body[k.split("/")[0]] += v
    r_lower = by_body.get(lower, np.zeros(2))
    balance = float(np.linalg.norm(sum(reactions.values())) / max(np.linalg.norm(r_lower), 1e-300))
    n_vs_reaction = float(n_force / max(abs(r_lower @ np.asarray(c["normal"])), 1e-300) - 1.0)
    row = {
        "case": spec["name"],
        "width_update": problem.contacts[0].options.width_update,
        "flux": problem.contacts[0].options.flux,
        "a": a,
        "a_hertz": a_hertz,
        "a_error": a / a_hertz - 1.0,
        "bracket_error": [x / a_hertz - 1.0 for x in c["checks"]["half_width_bracket"]],
        "normal_force": n_force,
        "tangential_force": c["tangential_force"],
        "reaction_balance": balance,
        "normal_force_vs_reaction": n_vs_reaction,
        "pressure_rms_p0": rms,
        "cells_across_2a": 2 * a / min(v["min_element_size"] for v in sol.body_info.values()),
        "dofs": int(sum(v["dofs"] for v in sol.body_info.values())),
        "contact_dofs": sol.iterations["contact_dofs"],
        "iterations": sol.iterations["per_step"],
        "converged": sol.converged,
        "messages": sol.iterations["messages"],
        "wall_s": wall,
        "timings": sol.timings,
        "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
    }
    if c["type"] == "frictional":
        from ibfem.solver.reports.validate import compare_contact

        m = compare_contact(problem, c, {})  # Cattaneo-Mindlin for the computed N and Q
        mu = c["friction"]
        row.update(friction=mu, friction_traction=problem.contacts[0].options.friction_traction, Q_over_N=m["Q_over_N"],
                   Q_over_mu_N=abs(m["Q"]) / (mu * m["N"]), ca=m["ca"], ca_theory=m["ca_theory"],
                   ca_error=m["ca_error"], shear_rms_mu_p0=m.get("shear_rms"), gross_slip=c.get("gross_slip"),
                   slip_direction_violations=c["checks"].get("slip_direction_violations"),
                   stick_shear_above_mu_p=c["checks"].get("stick_shear_above_mu_p"))
    if c["type"] == "frictionless" or spec.get("subsurface"):
        # von Mises along the contact normal into the second body from the contact point
        point, normal = np.asarray(c["point"]), np.asarray(c["normal"])
        z = np.linspace(0.05, 2.0, 400) * a_hertz
        vm = sol.von_mises(point[None, :] - z[:, None] * normal[None, :], body=lower)
        k = int(np.nanargmax(vm))
        peak, depth = theory.axis_peak(data["materials"][0]["poissons_ratio"])
        row["von_mises_peak_error"] = float(vm[k] / (peak * p0) - 1.0)
        row["von_mises_depth_error"] = float(z[k] / (depth * a_hertz) - 1.0)
    return row


def cases(quick: bool) -> list[dict]:
    out = [{"name": n, "file": f, "R": r} for n, f, r in EXAMPLE_CASES]
    if quick:
        return out
    out += [{"name": n + "_thesis", "file": f, "R": r, "width_update": "thesis"} for n, f, r in EXAMPLE_CASES
            if "tessellated" not in n]
    out += [{"name": n + "_bracket", "file": f, "R": r, "width_update": "bracket"} for n, f, r in EXAMPLE_CASES
            if "tessellated" not in n]
    ex3 = {"file": "cylinder_on_cylinder_frictionless.toml", "R": 0.5}
    # offsets in fractions of element_size; the finest cells are element_size / 16 here, so
    # multiples of 1/16 would leave the fine grid where it was: quarters of a fine cell, and
    # five random fractions of the coarsest cell (the slow test's, numpy seed 5)
    import numpy as np

    offs = [(1 / 64, 1 / 64), (2 / 64, 3 / 64), (3 / 64, 1 / 64), (0.37, 0.26)]
    offs += [tuple(float(v) for v in o) for o in np.random.default_rng(5).uniform(0.0, 1.0, (5, 2))]
    for off in offs:
        out.append({**ex3, "name": f"ex3_offset_{off[0]:.4f}_{off[1]:.4f}", "offset": off})
        out.append({**ex3, "name": f"ex3_offset_{off[0]:.4f}_{off[1]:.4f}_bracket", "offset": off,
                    "width_update": "bracket"})
    out.append({**ex3, "name": "ex3_stiffness_ratio_10_bracket", "stiff_upper": True, "width_update": "bracket"})
    out.append({**ex3, "name": "ex3_turned_30deg_bracket", "rotate_deg": 30.0, "width_update": "bracket"})
    out.append({**ex3, "name": "ex3_stiffness_ratio_10", "stiff_upper": True})
    # consistency flux: body 1's alone with weight 1 or 1/2 (the thesis's reading) against the average
    out.append({**ex3, "name": "ex3_flux_body1", "flux": "body1"})
    out.append({**ex3, "name": "ex3_flux_body1_half", "flux": "body1_half"})
    out.append({**ex3, "name": "ex3_turned_30deg", "rotate_deg": 30.0})
    out.append({**ex3, "name": "ex3_one_more_level", "extra_level": True})
    # exact_geometry = false: the degradation against the tessellation's chord tolerance
    # (Settings.chord_fraction x element_size: 1 mm by default for example 1, where a ~ 2 mm)
    for cf in (0.01, 0.001):
        out.append({"name": f"ex1_tessellated_chord_{cf * 10:g}mm", "file": "ellipse_on_block_tessellated.toml",
                    "R": 0.1, "chord_fraction": cf})
    # partial slip: the thesis's variant (no slip-zone friction traction) on examples 4-6, and
    # example 4 at mu 0.05 / 1 with |Q|/(mu N) ~ 0.05 / ~0.95 (ux from Q/N ~ 274 ux here), turned
    for n, f, r in EXAMPLE_CASES:
        if "partial_slip" in n:
            out.append({"name": n + "_no_slip_traction", "file": f, "R": r, "friction_traction": False})
    ex4 = {"file": "cylinder_on_flat_partial_slip.toml", "R": 1.0}
    for mu, ux in ((0.05, 9.1e-6), (0.05, 1.78e-4), (1.0, 1.8e-4), (1.0, 3.56e-3)):
        out.append({**ex4, "name": f"ex4_mu_{mu:g}_ux_{ux * 1e3:g}mm", "mu": mu, "ux": ux})
    out.append({**ex4, "name": "ex4_gross_slip_mu_0.05_ux_0.5mm", "mu": 0.05, "ux": 5e-4})
    out.append({**ex4, "name": "ex4_turned_30deg", "rotate_deg": 30.0})
    flat = {"file": "mesh_convergence.toml", "R": 1.0}
    for uy in (-0.1e-3, -0.5e-3, -4.0e-3, -12.0e-3):  # a from ~2 cells (h = 3.1 mm) to ~R/10-R/4
        out.append({**flat, "name": f"ex2_uy_{uy * 1e3:g}mm", "uy": uy})
    return out


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="the examples with the default search only")
    ap.add_argument("--single", help=argparse.SUPPRESS)
    ap.add_argument("--out", default=str(HERE / "results" / "contact.json"))
    args = ap.parse_args(argv)
    if args.single:
        print(json.dumps(run_one(json.loads(args.single))))
        return 0
    rows = []
    for spec in cases(args.quick):
        r = subprocess.run([sys.executable, __file__, "--single", json.dumps(spec)], capture_output=True, text=True)
        if r.returncode != 0:
            print(f"{spec['name']}: failed\n{r.stderr[-2000:]}", flush=True)
            rows.append({"case": spec["name"], "error": r.stderr.strip().splitlines()[-1] if r.stderr.strip() else "?"})
            continue
        row = json.loads(r.stdout.strip().splitlines()[-1])
        rows.append(row)
        vm = f" vM {row['von_mises_peak_error']:+.1%}" if "von_mises_peak_error" in row else ""
        if "ca" in row:
            vm += (f" Q/N {row['Q_over_N']:+.4f} |Q|/muN {row['Q_over_mu_N']:.3f} c/a {row['ca']:.4f} "
                   f"({row['ca_theory']:.4f}) q_rms {row['shear_rms_mu_p0']:.3f} gross {row['gross_slip']}")
        print(f"{row['case']:32s} {row['width_update']:8s} a {row['a_error']:+6.2%} "
              f"[{row['bracket_error'][0]:+.1%}, {row['bracket_error'][1]:+.1%}] "
              f"N {row['normal_force']:.4g} Q {row['tangential_force']:+.2g} bal {row['reaction_balance']:.1e} "
              f"p_rms {row['pressure_rms_p0']:.3f}{vm} it {sum(row['iterations'])} "
              f"t {row['wall_s']:.1f}s mem {row['peak_rss_mb']:.0f}MB conv {row['converged']}", flush=True)
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"machine": platform.platform(), "python": platform.python_version(), "runs": rows},
                              indent=2))
    keys = ["case", "width_update", "a", "a_hertz", "a_error", "normal_force", "tangential_force", "reaction_balance",
            "normal_force_vs_reaction", "pressure_rms_p0", "von_mises_peak_error", "Q_over_N", "Q_over_mu_N", "ca",
            "ca_theory", "ca_error", "shear_rms_mu_p0", "gross_slip", "cells_across_2a", "dofs",
            "contact_dofs", "wall_s", "peak_rss_mb", "converged"]
    with open(out.with_suffix(".csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        for row in rows:
            if "error" not in row:
                w.writerow(row)
    return 0 if all("error" not in r for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
