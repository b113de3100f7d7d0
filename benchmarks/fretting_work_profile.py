"""Where along the contact a shifted grid changes the 2D fretting example's energy per cycle.

The example (examples/fretting/cylinder_on_flat_fretting.toml, three cycles at 20 points per
cycle unless ``--points-per-cycle``) is solved on its own grid and on grids shifted by the given offsets (fractions of the
coarsest cell). For the first complete cycle it prints, in J/m:

- the loop's area, the work of the contact's terms (the discrete model's dissipation over the
  cycle, benchmarks/fretting_energy.py) and the friction work (the Coulomb traction the terms
  apply at each slipping sample times its slip, as the run reports it);
- the friction work read with the cell-mean shear instead of the point traction (as the run
  read it before), and read cell by cell:
  per finest cell between the grids' lines, the integral of the slipping samples' point shear
  (the cell's friction force, free of the point traction's oscillation within the cell) times
  their mean slip (a diagnostic; the run reports the first reading);
- the friction work by tenths of the half-width |x| / a, beside the closed form's
  (4 int 2 mu p S dx over the same tenths, Hertz's pressure, c' from the cycle's Q* and N:
  solver.reference.fretting);
- per step of the cycle, the contact terms' work less the friction work (J/m; the discrete
  model's dissipation beyond the slipping samples' friction work, with the strain energy's
  change of the step);
- the cell-mean pressure over p0 near the contact's edge at t = 1 (the normal load alone, before
  any tangential load), beside Hertz's sqrt(1 - (x / a)^2).

    .venv/bin/python benchmarks/fretting_work_profile.py                     # aligned, 0.4 h across, 0.4 h along
    .venv/bin/python benchmarks/fretting_work_profile.py --offsets 0.37 0.21
    .venv/bin/python benchmarks/fretting_work_profile.py --spacing 0.015625 --band-fraction 0.125
    .venv/bin/python benchmarks/fretting_work_profile.py --without-edge-discs --edge-ring

The example's grid has cells half as large in discs about the contact's edges (0.58 a to 1.08 a,
a = 0.03337 m its half-width); ``--without-edge-discs`` removes them (the grid of the measurements
before they were added), and ``--edge-ring`` refines both bodies one level more than the finest
in discs of radius 0.15 a about x = +-0.92 a (with ``--without-edge-discs``: cells half as large
from 0.77 a to 1.07 a, the ring first tried).

Each run takes about 5 to 7 s of CPU and 0.25 GB; prints only, writes nothing.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import fretting_energy  # noqa: E402  (the audit's scene and recorded solve)

BINS = np.linspace(0.0, 1.0, 11)
EDGE = (0.85, 1.0)  # the stretch of x / a whose pressure is printed


def _closed_form_bins(q_star: float, n: float, mu: float, radius: float, e_star: float) -> np.ndarray:
    """The closed form's energy per cycle by tenths of |x| / a (J/m)."""
    from ibfem.solver.reference.fretting import cattaneo_slip

    a = math.sqrt(4.0 * n * radius / (math.pi * e_star))
    p0 = 2.0 * n / (math.pi * a)
    c = a * math.sqrt(1.0 - q_star / (mu * n))
    x = np.linspace(c, a, 200001)
    f = 4.0 * mu * p0 * np.sqrt(np.clip(1.0 - (x / a) ** 2, 0.0, None)) * 2.0 * cattaneo_slip(x, c, mu, radius)
    r = np.clip(np.digitize(x / a, BINS) - 1, 0, len(BINS) - 2)
    return np.array([np.trapezoid(np.where(r == k, f, 0.0), x) for k in range(len(BINS) - 1)])


EXAMPLE_A = 0.03337  # the example's half-width (m): where the edge ring goes


def _scene(offset, spacing: float | None, band_fraction: float | None, edge_ring: bool = False,
           points_per_cycle: int = 20, edge_discs: bool = True):
    """The example at this grid offset, sample spacing and band fraction (None: the example's)."""
    import tomllib

    from ibfem.solver.io.scene import scene_from_dict

    data = tomllib.loads(fretting_energy.EXAMPLE_2D.read_text(encoding="utf-8"))
    data["output"] = {"vtk": False, "plots": False}
    data["paths"][1]["cycle"]["points_per_cycle"] = points_per_cycle
    if offset is not None:
        data["solver"]["grid_offset"] = list(offset)
    if spacing is not None:
        data["contacts"][0]["sample_spacing"] = spacing
    if band_fraction is not None:
        data["solver"]["band_fraction"] = band_fraction
    if not edge_discs:  # the example's grid without its finer discs about the contact's edges
        for body in data["bodies"]:
            body["refinement"] = [r for r in body["refinement"] if r["around"] == "contact"]
    if edge_ring:
        for body in data["bodies"]:
            levels = max(r["levels"] for r in body["refinement"]) + 1
            body["refinement"] = body["refinement"] + [
                {"levels": levels, "around": [side * 0.92 * EXAMPLE_A, 0.0], "radius": 0.15 * EXAMPLE_A} for side in (-1.0, 1.0)]
    return scene_from_dict(data, label=str(fretting_energy.EXAMPLE_2D), base_dir=fretting_energy.EXAMPLE_2D.parent)


def _cell_work(c, dw: np.ndarray, ds: np.ndarray) -> float:
    """The step's friction work cell by cell: per finest cell between the grids' lines, the
    integral of the slipping samples' point shear times their mean slip increment."""
    slip = c.zone != 0.0
    cell = np.searchsorted(np.unique(np.asarray(c.breakpoints)), c.samples.s)
    n = int(cell.max()) + 1
    force = np.bincount(cell, weights=np.where(slip, c._raw[1] * ds, 0.0), minlength=n)
    moved = np.bincount(cell, weights=np.where(slip, dw * ds, 0.0), minlength=n)
    length = np.bincount(cell, weights=np.where(slip, ds, 0.0), minlength=n)
    used = length > 0.0
    return float(-np.sum(force[used] * moved[used] / length[used]))


def run(offset: list[float] | None, spacing: float | None = None, band_fraction: float | None = None,
        edge_ring: bool = False, points_per_cycle: int = 20, edge_discs: bool = True) -> dict:
    """The example on this grid: its first cycle's energies, by tenths of the half-width."""
    from ibfem.solver.contact import friction_history as fh
    from ibfem.solver.io.fretting_outputs import cycles_of, loop_energy
    from ibfem.solver.reference.theory import effective_modulus

    problem = _scene(offset, spacing, band_fraction, edge_ring, points_per_cycle, edge_discs).problem
    records, original = [], fh.HistoryBandContact.end_step

    def recording(self, x, a, info):
        original(self, x, a, info)
        loc = self.local(self.samples.s) / a
        ds = np.gradient(self.samples.s)
        records.append((loc, self.zone.copy(), self.step_increment.copy(), self.shear_prev.copy(),
                        self._raw[1].copy(), self.step_pressure.copy(), ds, _cell_work(self, self.step_increment, ds)))

    r, cpu = fretting_energy.audit_recording(problem, recording)
    steps = list(range(len(r["t"]) - len(records), len(r["t"])))  # the steps that ran end_step
    by_step = dict(zip(steps, records))
    i, j = cycles_of(r["q"])[0]
    point_bins, mean_work, cell_work = np.zeros(len(BINS) - 1), 0.0, 0.0
    for k in range(i + 1, j + 1):
        loc, zone, dw, q_mean, q_point, _, ds, cw = by_step[k]
        cell_work += cw
        slip = zone != 0.0
        b = np.clip(np.digitize(np.abs(loc), BINS) - 1, 0, len(BINS) - 2)
        np.add.at(point_bins, b[slip], (-q_point * dw * ds)[slip])
        mean_work += float(-np.sum((q_mean * dw * ds)[slip]))
    friction = float(r["friction"][i + 1:j + 1].sum())
    assert abs(point_bins.sum() - friction) <= 1e-6 * abs(friction), "profiles not aligned with the steps"
    n = float(np.mean(r["normal"][i:j + 1]))
    q_star = 0.5 * (abs(r["q"][i:j + 1].max()) + abs(r["q"][i:j + 1].min()))
    e_star = effective_modulus(2.0e11, 0.3, 2.0e11, 0.3)  # both bodies steel
    theory = _closed_form_bins(q_star, n, 0.3, 1.0, e_star)
    loc, *_, p, _, _ = by_step[int(np.argmin(np.abs(r["t"] - 1.0)))]
    a = math.sqrt(4.0 * n / (math.pi * e_star))
    edge = (loc > EDGE[0]) & (loc <= EDGE[1])
    return {"cpu_s": cpu, "solves": r["solves"], "loop": abs(loop_energy(r["q"], r["delta"], i, j)),
            "contact": abs(r["contact"][i:j].sum()), "friction": friction, "mean_work": mean_work, "cell_work": cell_work,
            "bins": point_bins, "excess": np.abs(r["contact"][i:j]) - r["friction"][i + 1:j + 1], "t": r["t"][i + 1:j + 1], "theory": theory, "edge_x": loc[edge][::4], "edge_p": p[edge][::4] * math.pi * a / (2.0 * n)}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--offsets", type=float, nargs="*", default=[0.0, 0.025, 0.025, 0.0],
                    help="pairs of grid offsets (fractions of the coarsest cell); the aligned grid always runs")
    ap.add_argument("--spacing", type=float, default=None, help="the contact's sample_spacing (finest cells)")
    ap.add_argument("--band-fraction", type=float, default=None)
    ap.add_argument("--points-per-cycle", type=int, default=20)
    ap.add_argument("--edge-ring", action="store_true", help="one level more about the contact's edges")
    ap.add_argument("--without-edge-discs", action="store_true",
                    help="the example's grid without its finer discs about the contact's edges")
    args = ap.parse_args(argv)
    if len(args.offsets) % 2:
        ap.error("--offsets takes pairs")
    for off in [None] + [args.offsets[k:k + 2] for k in range(0, len(args.offsets), 2)]:
        r = run(off, args.spacing, args.band_fraction, args.edge_ring, args.points_per_cycle, not args.without_edge_discs)
        label = "aligned" if off is None else f"shift {off[0]:g}, {off[1]:g}"
        print(f"{label}: {r['solves']} solves, {r['cpu_s']:.1f} s CPU; first cycle (J/m): loop {r['loop']:.2f}, "
              f"contact terms {r['contact']:.2f}, friction work {r['friction']:.2f} (cell-mean shear: "
              f"{r['mean_work']:.2f}, cell by cell: {r['cell_work']:.2f}), closed form {r['theory'].sum():.2f}")
        print("  friction work by |x|/a tenths: " + " ".join(f"{v:.1f}" for v in r["bins"][5:]) + "  (0.5 to 1.0)")
        print("  closed form by |x|/a tenths:   " + " ".join(f"{v:.1f}" for v in r["theory"][5:]))
        print("  contact terms' work less friction work per step, t = "
              f"{r['t'][0]:.2f} to {r['t'][-1]:.2f}: " + " ".join(f"{v:+.1f}" for v in r["excess"]))
        print("  t = 1, x/a:    " + " ".join(f"{v:.3f}" for v in r["edge_x"]))
        print("  p mean / p0:   " + " ".join(f"{v:.3f}" for v in r["edge_p"]))
        print("  Hertz:         " + " ".join(f"{math.sqrt(max(1.0 - v * v, 0.0)):.3f}" for v in r["edge_x"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
