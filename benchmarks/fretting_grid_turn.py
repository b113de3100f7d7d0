"""The 2D fretting example turned against its grid: the energy per cycle against the aligned run.

The example (examples/fretting/cylinder_on_flat_fretting.toml: a half disc R = 1 m on a block,
steel, mu 0.3, the normal displacement held from t = 1 and the tangential one cycled at 20 points
a cycle) is turned by each angle about the contact point: both bodies' shapes (``rotate_deg``),
the refinement discs at the contact's edges, and the loaded face's displacement, whose value and
paths are given along the turned tangent and normal (``axes``: the tangential component cycled,
the normal one held). One and a half cycles; the first complete cycle's energy from the loop and from
the friction work against the Mindlin-Deresiewicz closed form for the run's computed N and Q*
(solver.reports.validate_fretting.compare), and against the unturned run.

    python benchmarks/fretting_grid_turn.py [--angles 0 8 17 30 45 60]

Measured (2026-11-29, load average 1 to 2; docs/load-paths.md, "The example turned against its
grid (2D)"): the loop -0.77 % to +0.34 % of the closed form at 8 to 60 degrees (-1.60 % at 0),
the friction work -0.30 % to +0.60 % (-0.20 % at 0); against the unturned run +0.79 % to +1.94 %
and -0.13 % to +0.77 %; the stick half-width within 0.0076 a at every step."""

from __future__ import annotations

import argparse
import math
import tempfile
import tomllib
from pathlib import Path

import numpy as np


def turned_scene(theta_deg: float) -> dict:
    """The example's scene data turned by ``theta_deg`` about the contact point (1.5 cycles)."""
    from ibfem.solver.reports.validate_fretting import EXAMPLE

    data = tomllib.loads(EXAMPLE.read_text(encoding="utf-8"))
    data["output"] = {"vtk": False, "plots": False}
    data["paths"][1]["cycle"]["cycles"] = 1.5
    data["paths"][0]["points"][-1][0] = 2.5
    c, s = math.cos(math.radians(theta_deg)), math.sin(math.radians(theta_deg))
    for body in data["bodies"]:
        body["shape"]["rotate_deg"] = theta_deg
        body["shape"]["pivot"] = [0.0, 0.0]
        for zone in body["refinement"]:
            if isinstance(zone["around"], list):
                x, y = zone["around"]
                zone["around"] = [c * x - s * y, s * x + c * y]
    loaded = data["boundary_conditions"][0]  # its value and paths along the turned tangent and normal
    loaded["axes"] = [[c, s], [-s, c]]
    return data


def run(theta_deg: float) -> dict:
    """The turned example solved: its first complete cycle against the closed form, and the
    largest stick half-width error over the steps (in a)."""
    from ibfem.solver.io.output import write_scene_results
    from ibfem.solver.io.scene import scene_from_dict
    from ibfem.solver.reports.validate_fretting import EXAMPLE, compare
    from ibfem.solver.solving import solve

    out = Path(tempfile.mkdtemp(prefix="fretting_turn_"))
    scene = scene_from_dict(turned_scene(theta_deg), label=f"fretting turned {theta_deg:g} deg", base_dir=EXAMPLE.parent)
    solution = solve(scene.problem)
    summary = write_scene_results(out, scene, solution)
    result = compare(summary, dict(np.load(out / "profiles_0.npz")), 1.0, 2.0e11, 0.3)
    cycle = result["cycles"][0]
    return {"angle": theta_deg, "converged": bool(solution.converged), "loop": cycle["energy_loop"],
            "loop_error": cycle["loop_error"], "friction": cycle["energy_friction"],
            "friction_error": cycle["friction_error"],
            "stick_error": max(abs(r["c_error_over_a"]) for r in result["steps"])}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--angles", type=float, nargs="+", default=[0.0, 8.0, 17.0, 30.0, 45.0, 60.0],
                    help="turns in degrees (the first is the reference the others are read against)")
    args = ap.parse_args()
    rows = []
    print("| angle | converged | W loop (vs closed form, vs first) | W friction (vs closed form, vs first) | "
          "largest stick error |")
    print("|---|---|---|---|---|")
    for theta in args.angles:
        r = run(theta)
        rows.append(r)
        ref = rows[0]
        print(f"| {theta:g} deg | {r['converged']} | {r['loop']:.2f} J/m ({r['loop_error']:+.2%}, "
              f"{r['loop'] / ref['loop'] - 1:+.2%}) | {r['friction']:.2f} J/m ({r['friction_error']:+.2%}, "
              f"{r['friction'] / ref['friction'] - 1:+.2%}) | {r['stick_error']:.4f} a |", flush=True)


if __name__ == "__main__":
    main()
