"""Why the largest subsurface von Mises stress below the 2D cylinder on a block
(``examples/mesh_convergence.toml``, frictionless, plane strain, nu = 0.3) reads about 2 % above
Hertz's value for two half-planes (0.5575 p0 at 0.704 a, ``theory.axis_peak``) on every grid.

For each load and grid (the scene's, and its contact zones one and two levels deeper) it prints:

- the offset of the computed sxx (recovered) from McEwen's half-plane field at 1.5 a below the
  contact point, in each body, in units of p0 (Hertz's for the computed force): a smooth field the
  finite bodies add to Hertz's;
- the largest von Mises stress of each body over |x| <= 0.3 a, 0.4 a <= depth <= 1.1 a, and the run's
  own reading (``solving.max_von_mises``), against Hertz's half-plane peak;
- the peak of Hertz's field plus a uniform sxx = N / (pi R) (the uniform tension of a disc of
  radius R compressed along a diameter by N per unit thickness, which with the opposite load's
  Flamant field at 2 R adds sxx = N / (pi R), szz about 0 near the contact: Timoshenko and Goodier,
  Theory of Elasticity, section 41), against the same half-plane peak.

One process, the solves one after the other (each a second or two of CPU).

    python benchmarks/accuracy_von_mises_2d.py
"""

from __future__ import annotations

import sys
import tomllib
from pathlib import Path

import numpy as np

from ibfem.solver.io.scene import scene_from_dict
from ibfem.solver.reference import theory
from ibfem.solver.reports.validate import hertz_for_force
from ibfem.solver.solving import max_von_mises, solve

SCENE = Path(__file__).resolve().parents[1] / "examples" / "mesh_convergence.toml"
#: (displacement of the cylinder's flat edge (m), contact levels added to the scene's)
CASES = [(-1.0e-3, 0), (-2.5e-3, 0), (-4.0e-3, 0), (-2.5e-3, 1), (-2.5e-3, 2)]
NU = 0.3


def disc_corrected_peak(a_over_r: float, nu: float = NU) -> float:
    """Largest on-axis von Mises stress / p0 of McEwen's field plus a uniform sxx = N / (pi R)
    (= p0 a / (2 R) with p0 = 2 N / (pi a)), by a dense scan of the depth."""
    z = np.linspace(0.3, 1.2, 90001)
    sxx, szz, sxz = theory.mcewen_stress(0.0 * z, z, 1.0, 1.0)
    return float(np.max(theory.von_mises_plane_strain(sxx + 0.5 * a_over_r, szz, sxz, nu)))


def solve_case(uy: float, extra_levels: int) -> dict:
    data = tomllib.loads(SCENE.read_text())
    data["output"] = {"vtk": False, "plots": False}
    data["boundary_conditions"][0]["value"] = [0.0, uy]
    for body in data["bodies"]:
        body["refinement"][-1]["levels"] += extra_levels
    scene = scene_from_dict(data, label="von Mises study", base_dir=SCENE.parent)
    solution = solve(scene.problem)
    c = solution.contacts[0]
    r_eff, a, p0 = hertz_for_force(scene.problem, c)
    peak = theory.axis_peak(NU, "von_mises")[0] * p0
    row = {"uy": uy, "extra": extra_levels, "a_over_r": a / r_eff, "offset": [], "body_peak": []}
    xs, zs = np.linspace(-0.3, 0.3, 31) * a, np.linspace(0.4, 1.1, 141) * a
    grid_x, grid_z = np.meshgrid(xs, zs)
    for side in (-1.0, 1.0):  # the block below, the cylinder above
        s = solution.stress(np.array([[0.0, side * 1.5 * a]]))[0]
        sxx = theory.mcewen_stress(0.0, 1.5 * a, a, p0)[0]
        row["offset"].append((s[0] - sxx) / p0)
        pts = np.stack([grid_x.ravel(), side * grid_z.ravel()], axis=1)
        row["body_peak"].append(float(np.nanmax(solution.von_mises(pts))) / peak - 1.0)
    row["run_peak"] = max_von_mises(solution, c, 2) / peak - 1.0
    row["disc_peak"] = disc_corrected_peak(a / r_eff) / theory.axis_peak(NU, "von_mises")[0] - 1.0
    return row


def main() -> int:
    print("| flat edge moved (mm) | contact levels added | a / R | sxx - McEwen's at 1.5 a (p0): block, cylinder "
          "| cylinder's / (a / R) | largest von Mises / half-plane peak - 1: block, cylinder, the run's "
          "| Hertz + N / (pi R): peak - 1 |")
    print("|---|---|---|---|---|---|---|")
    for uy, extra in CASES:
        r = solve_case(uy, extra)
        print(f"| {-uy * 1e3:g} | {extra} | {r['a_over_r']:.4f} | {r['offset'][0]:+.4f}, {r['offset'][1]:+.4f} "
              f"| {r['offset'][1] / r['a_over_r']:.3f} | {100 * r['body_peak'][0]:+.2f}, {100 * r['body_peak'][1]:+.2f}, "
              f"{100 * r['run_peak']:+.2f} % | {100 * r['disc_peak']:+.2f} % |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
